#!/usr/bin/env python3
"""A snapshot of the API's answers, timing fields removed, to show that a change of the code
leaves every number the same (bit for bit: numbers are compared as the JSON text gives them).

Starts the given server binary on a free loopback port, sends the paper's six scenes to
POST /simulate (JSON with every method, and as a stream), POST /scorecard with the paper's six
scenes and the seven methods of the paper's class (DLA^0.5, DLA^0.4, DLA^{0,1}, LF, DD, DD-AVF,
RK4), named explicitly so that a server whose defaults grew answers the same question, and a
small POST /work-precision, and writes the answers with `elapsed_ms`, `cpu_ms` and other
wall-clock fields removed.

  cargo build --release -p nhlab-server
  python3 bench/api_snapshot.py target/release/nhlab after.json
  python3 bench/api_snapshot.py OLD_BINARY before.json && cmp before.json after.json

An API that gained fields answers with more than the old one did; `--compare` takes both
snapshots and checks every field of the old answers against the new ones (a field only the
new answer has is no difference; a description's new wording is shown apart), and exits
non-zero on any difference:

  python3 bench/api_snapshot.py --compare OLD_BINARY NEW_BINARY [OLD.json NEW.json]
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
# Fields that describe how something is measured, in words: `--compare` lists a change of
# their wording apart, not as a different answer.
PROSE = {"properties_test"}


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


def snapshot(binary):
    """The stripped answers of the server `binary`."""
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
        scenes = [{"system": system, "preset": preset} for system, preset in SCENES]
        snap["scorecard"] = post(base, "/scorecard", {"scenes": scenes, "methods": METHODS})
        snap["work-precision"] = post(
            base,
            "/work-precision",
            {"system": "knife_edge", "preset": "paper-perturbed", "methods": ["leapfrog", "dd"]},
        )
    finally:
        server.terminate()
        server.wait()
    return strip(snap)


def differences(old, new, path="", out=None):
    """Where `new` differs from `old` in a field `old` has, as (path, old, new). Numbers
    compare by their text (repr), so that -0.0 differs from 0.0; lists element by element."""
    out = [] if out is None else out
    if isinstance(old, dict) and isinstance(new, dict):
        for k, v in old.items():
            if k in new:
                differences(v, new[k], f"{path}.{k}", out)
            else:
                out.append((f"{path}.{k}", v, "(missing)"))
    elif isinstance(old, list) and isinstance(new, list) and len(old) == len(new):
        for i, (a, b) in enumerate(zip(old, new)):
            differences(a, b, f"{path}[{i}]", out)
    elif type(old) is not type(new) or repr(old) != repr(new):
        out.append((path, old, new))
    return out


def leaves(x):
    """The numbers, strings, booleans and nulls in `x`."""
    if isinstance(x, dict):
        return sum(leaves(v) for v in x.values())
    if isinstance(x, list):
        return sum(leaves(v) for v in x)
    return 1


def write(snap, out):
    with open(out, "w") as f:
        json.dump(snap, f, indent=1, sort_keys=True)


def main():
    if sys.argv[1] != "--compare":
        write(snapshot(sys.argv[1]), sys.argv[2])
        return
    old, new = snapshot(sys.argv[2]), snapshot(sys.argv[3])
    if len(sys.argv) > 5:
        write(old, sys.argv[4])
        write(new, sys.argv[5])
    found = differences(old, new)
    wording = [d for d in found if d[0].rsplit(".", 1)[-1] in PROSE]
    diffs = [d for d in found if d not in wording]
    print(f"{len(old)} requests; {leaves(old)} values of the old answers checked against the "
          f"new answers ({leaves(new)} values): {len(diffs)} differ")
    for path, a, b in diffs[:40]:
        print(f"  {path}: {json.dumps(a)[:70]} -> {json.dumps(b)[:70]}")
    for path, a, b in wording:
        print(f"reworded (not counted), {path}:\n  old: {a}\n  new: {b}")
    sys.exit(1 if diffs else 0)


if __name__ == "__main__":
    main()
