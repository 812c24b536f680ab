#!/usr/bin/env python3
"""A snapshot of the API's answers, timing fields removed, to show that a change of the code
leaves every number the same (bit for bit: numbers are compared as the JSON text gives them).

Starts the given server binary on a free loopback port, sends the paper's six scenes to
POST /simulate (JSON with every method, and as a stream), POST /scorecard {} and a small
POST /work-precision, and writes the answers with `elapsed_ms`, `cpu_ms` and other
wall-clock fields removed.

  cargo build --release -p nhlab-server
  python3 bench/api_snapshot.py target/release/nhlab after.json
  python3 bench/api_snapshot.py OLD_BINARY before.json && cmp before.json after.json
"""

import json
import socket
import subprocess
import sys
import time
import urllib.request

SCENES = [
    ("knife_edge", "paper"),
    ("knife_edge", "paper-perturbed"),
    ("cvt_pendulum", "oscillating"),
    ("cvt_pendulum", "rotating"),
    ("cvt_pendulum", "oscillating-perturbed"),
    ("cvt_pendulum", "rotating-perturbed"),
]
METHODS = ["dla", {"id": "dla", "alpha": 0.4}, "dla01", "leapfrog", "dd", "dd_avf", "rk4"]
TIMING = {"elapsed_ms", "cpu_ms", "time_ms", "wall_ms", "uptime_s", "seconds", "ms"}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def post(base, path, body, stream=False):
    req = urllib.request.Request(
        base + path,
        data=json.dumps(body).encode(),
        headers={
            "content-type": "application/json",
            "accept": "text/event-stream" if stream else "application/json",
        },
    )
    with urllib.request.urlopen(req, timeout=600) as r:
        text = r.read().decode()
    if not stream:
        return json.loads(text)
    events = []
    for block in text.split("\n\n"):
        lines = block.strip().splitlines()
        kind = next((l[6:].strip() for l in lines if l.startswith("event:")), None)
        data = "".join(l[5:].strip() for l in lines if l.startswith("data:"))
        if kind and kind != "progress":
            events.append({"event": kind, "data": json.loads(data) if data else None})
    return events


def by_run(events):
    """A stream as each run's own events: runs compute in parallel, so the interleaving of
    their events varies from one request to the next, and each `points` event holds whatever
    buckets were ready; what a stream must reproduce is, per run, the concatenated series
    and the `run` event, after the `scene` and before the `done` event."""
    runs = {}
    for e in events:
        data = e["data"] or {}
        if e["event"] == "points":
            series = runs.setdefault(data["run"], {}).setdefault(data["integral"], {})
            for k, v in data.items():
                if k not in ("run", "integral"):
                    series.setdefault(k, []).extend(v if isinstance(v, list) else [v])
        elif e["event"] == "run":
            runs.setdefault(data["run"], {})["run"] = data
    other = [e for e in events if e["event"] not in ("points", "run")]
    return {"events": other, "runs": {str(k): v for k, v in sorted(runs.items())}}


def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if k not in TIMING and not k.endswith("_ms")}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x


def main():
    binary, out = sys.argv[1], sys.argv[2]
    port = free_port()
    server = subprocess.Popen([binary, "--addr", f"127.0.0.1:{port}"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}"
    try:
        for _ in range(300):
            try:
                urllib.request.urlopen(base + "/health", timeout=1)
                break
            except OSError:
                time.sleep(0.1)
        snap = {}
        for system, preset in SCENES:
            body = {"system": system, "preset": preset, "methods": METHODS, "points": 500}
            key = f"{system}/{preset}"
            snap["simulate " + key] = post(base, "/simulate", body)
            snap["stream " + key] = by_run(post(base, "/simulate", body, stream=True))
        snap["scorecard"] = post(base, "/scorecard", {})
        snap["work-precision"] = post(
            base,
            "/work-precision",
            {"system": "knife_edge", "preset": "paper-perturbed", "methods": ["leapfrog", "dd"]},
        )
    finally:
        server.terminate()
        server.wait()
    with open(out, "w") as f:
        json.dump(strip(snap), f, indent=1, sort_keys=True)


if __name__ == "__main__":
    main()
