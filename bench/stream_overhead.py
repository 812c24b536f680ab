#!/usr/bin/env python3
"""Streaming overhead: the wall time of a whole SSE stream, read event by event by a client,
against the compute alone of the same runs.

Two scenes:
  long  knife_edge/paper, leapfrog, 10⁷ steps (t_end = (10⁷ + ½)·π/10), 1000 points
  cvt   cvt_pendulum/rotating-perturbed (the paper's preset: 30,000 steps), the paper's five
        methods, every integral (latitude included), 1000 points

Compute alone: core/examples/compute_baseline.rs (scene resolved and prepared, then one
thread per method, all at once, into a counting observer: what the server's blocking pool
does, without the server), run under `nice -n 19` like the server's simulation threads
(runner.rs lowers them), unless --baseline-nice 0.

Stream: the release server on loopback (ephemeral port unless --port); per repetition
  - python: this script's stdlib client reads and JSON-decodes every event;
  - curl:   `curl -N` reads every byte to /dev/null (the lightest client);
  - json:   the same request as plain JSON, for comparison.
Reported per client: min and median wall, the server's own view (the `done` event's
elapsed_ms: from the runs' start to the last event queued), the runs' elapsed_ms, and the
server's CPU time per request (/proc/PID/stat; 10 ms ticks, averaged over the repetitions)
against the baseline's.

overhead = (stream wall − compute wall) / compute wall, from the minima (and the medians).
Target (docs/performance.md): under 10 %.

  python3 bench/stream_overhead.py                # 9 repetitions per scene and client
  python3 bench/stream_overhead.py --reps 21 --no-build --port 8082
"""

import argparse
import atexit
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

from nhlab_bench import ROOT, Server, build, cpu_seconds, log, median, other_load, stream
from nhlab_bench import Quiet, post_json

H_KNIFE = None  # filled from /systems

SCENES = {
    "long": {
        "label": "knife_edge/paper, leapfrog, 10⁷ steps, 1000 points",
        "system": "knife_edge",
        "preset": "paper",
        "steps": 10**7,
        "methods": "leapfrog",
    },
    "cvt": {
        "label": "cvt_pendulum/rotating-perturbed, paper's five, 30,000 steps, all integrals",
        "system": "cvt_pendulum",
        "preset": "rotating-perturbed",
        "steps": None,
        "methods": "paper",
    },
}


def baseline_binary(skip):
    if not skip:
        log("building: cargo build --release -p nhlab-core --example compute_baseline")
        subprocess.run(
            ["cargo", "build", "--release", "--quiet", "-p", "nhlab-core", "--example",
             "compute_baseline"],
            cwd=ROOT,
            check=True,
        )
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    return os.path.join(target, "release", "examples", "compute_baseline")


def run_baseline(binary, scene, t_end, reps, nice):
    cmd = [binary, scene["system"], scene["preset"], "-" if t_end is None else repr(t_end),
           scene["methods"], "1000", str(reps)]
    if nice:
        cmd = ["nice", "-n", str(nice), *cmd]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return [json.loads(line) for line in out.splitlines()], cpu / reps


def body(scene, t_end):
    b = {"system": scene["system"], "preset": scene["preset"], "points": 1000}
    if t_end is not None:
        b["t_end"] = t_end
    if scene["methods"] != "paper":
        b["methods"] = [{"id": scene["methods"]}]
    return b


def curl_stream(server, req, path):
    """curl reads the stream into `path`; returns (wall s, the `done` event's elapsed s)."""
    url = f"http://{server.host}:{server.port}/simulate"
    out = subprocess.run(
        ["curl", "-sS", "-N", "-o", path, "-w", "%{time_total}",
         "-H", "accept: text/event-stream", "-H", "content-type: application/json",
         "--data-binary", json.dumps(req), url],
        capture_output=True, text=True, check=True,
    ).stdout
    with open(path, "rb") as f:
        tail = f.read()[-4096:].decode(errors="replace")
    done = json.loads(tail.split("event: done", 1)[1].split("data: ", 1)[1].split("\n", 1)[0])
    return float(out), done["elapsed_ms"] / 1e3


def fmt(xs, unit=1e3):
    return f"{min(xs) * unit:.1f} / {median(xs) * unit:.1f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--port", type=int, default=0)
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument("--reps", type=int, default=9)
    ap.add_argument("--baseline-nice", type=int, default=19)
    ap.add_argument("--scenes", default="long,cvt")
    ap.add_argument("--max-busy", type=float, default=0.15,
                    help="wait before each measurement until the cores are at most this busy "
                         "(1 = never wait)")
    ap.add_argument("--quiet-timeout", type=float, default=60.0)
    args = ap.parse_args()
    quiet = Quiet(args.max_busy, args.quiet_timeout)

    binary = build(args.no_build)
    base = baseline_binary(args.no_build)
    has_curl = shutil.which("curl") is not None
    tmp = tempfile.NamedTemporaryFile(prefix="nhlab-stream-", delete=False).name
    atexit.register(os.remove, tmp)
    server = Server(binary, port=args.port)
    info = server.get("/systems")
    knife = next(s for s in info["systems"] if s["id"] == "knife_edge")
    h = next(p for p in knife["presets"] if p["id"] == "paper")["step"]

    results = []
    for key in args.scenes.split(","):
        scene = SCENES[key]
        t_end = None if scene["steps"] is None else (scene["steps"] + 0.5) * h
        req = body(scene, t_end)
        log(f"== {scene['label']}")
        # warm-up (threads of the blocking pool, page cache, CPU frequency)
        stream(server, req)
        run_baseline(base, scene, t_end, 1, args.baseline_nice)
        r = {"label": scene["label"], "base": [], "base_runs": [], "py": [], "py_done": [],
             "py_runs": [], "curl": [], "curl_done": [], "json": [], "json_runs": [],
             "events": None, "bytes": None, "base_cpu": [], "stream_cpu": []}
        for i in range(args.reps):
            quiet.wait()
            lines, cpu = run_baseline(base, scene, t_end, 1, args.baseline_nice)
            r["base"] += [ln["wall_ms"] / 1e3 for ln in lines]
            r["base_runs"] += [max(ln["runs_ms"]) / 1e3 for ln in lines]
            r["base_cpu"].append(cpu)
            quiet.wait()
            c0 = cpu_seconds(server.pid)
            res = stream(server, req)
            r["stream_cpu"].append(cpu_seconds(server.pid) - c0)
            done = res.of("done")[0]
            assert done["failed"] == 0, done
            r["py"].append(res.wall)
            r["py_done"].append(done["elapsed_ms"] / 1e3)
            r["py_runs"].append(max(x["elapsed_ms"] for x in res.of("run")) / 1e3)
            r["events"], r["bytes"] = len(res.events), res.bytes
            if has_curl:
                quiet.wait()
                wall, done_s = curl_stream(server, req, tmp)
                r["curl"].append(wall)
                r["curl_done"].append(done_s)
            quiet.wait()
            status, js, wall = post_json(server, req)
            assert status == 200, js
            r["json"].append(wall)
            r["json_runs"].append(max(x["elapsed_ms"] for x in js["runs"]) / 1e3)
            log(f"  rep {i + 1}: compute {r['base'][-1] * 1e3:.1f} ms, python stream "
                f"{res.wall * 1e3:.1f} ms (server {done['elapsed_ms']:.1f} ms)"
                + (f", curl {r['curl'][-1] * 1e3:.1f} ms" if has_curl else "")
                + f", json {wall * 1e3:.1f} ms")
        results.append(r)

    print(f"{args.reps} repetitions each, interleaved; times in ms as min / median; compute "
          f"baseline under nice {args.baseline_nice}")
    print()
    print("| scene | compute alone (baseline wall) | longest run in the baseline | stream, "
          "python client (wall) | server's `done` elapsed_ms | longest run's elapsed_ms in the "
          "stream | stream, curl (wall) | server's `done`, curl | JSON request | events / bytes "
          "| CPU per request: baseline / server (stream) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    summary = []
    for r in results:
        curl = fmt(r["curl"]) if r["curl"] else "–"
        curl_done = fmt(r["curl_done"]) if r["curl_done"] else "–"
        print(f"| {r['label']} | {fmt(r['base'])} | {fmt(r['base_runs'])} | {fmt(r['py'])} | "
              f"{fmt(r['py_done'])} | {fmt(r['py_runs'])} | {curl} | {curl_done} | {fmt(r['json'])} | "
              f"{r['events']} / {r['bytes']} | {sum(r['base_cpu']) / len(r['base_cpu']) * 1e3:.0f}"
              f" / {sum(r['stream_cpu']) / len(r['stream_cpu']) * 1e3:.0f} |")
        b_min, b_med = min(r["base"]), median(r["base"])
        for client in ("py", "curl"):
            if r[client]:
                o_min = (min(r[client]) - b_min) / b_min
                o_med = (median(r[client]) - b_med) / b_med
                summary.append(f"{r['label'].split(',')[0]} {client}: {o_min:+.1%} (min) "
                               f"{o_med:+.1%} (median)")
        d = r["curl_done"] or r["py_done"]
        summary.append(f"{r['label'].split(',')[0]} server side (`done`): "
                       f"{(min(d) - b_min) / b_min:+.1%} (min) {(median(d) - b_med) / b_med:+.1%} "
                       "(median)")
    print()
    print(f"machine: {other_load()}")
    print(f"shared machine: {quiet.report()}")
    print("SUMMARY stream overhead (stream wall − compute)/compute: " + "; ".join(summary))
    return 0


if __name__ == "__main__":
    t0 = time.time()
    code = main()
    log(f"took {time.time() - t0:.0f} s")
    sys.exit(code)
