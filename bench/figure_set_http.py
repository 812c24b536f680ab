#!/usr/bin/env python3
"""The paper's whole figure set through POST /simulate.

Six JSON requests, each with the default methods (the paper's five), every integral and
1000 points: the paper's experiments as `GET /systems` lists them (`paper_scenes`: knife_edge
`paper`, `paper-perturbed`; cvt_pendulum `oscillating`, `rotating`, `oscillating-perturbed`,
`rotating-perturbed`). Against the release server on loopback
(ephemeral port unless --port) with default settings (--max-simulations = the number of
cores), per repetition:

  sequential    one request after the other;
  concurrent    as many at once as the server has simulation slots (a client pool of
                `max_simulations` from /health: with the defaults more would get 503);
  six at once   (--six, default on) all six at once, on a second server started with
                --max-simulations 6.

Reported, minimum (and median) over the repetitions: the wall time of the set as the client
sees it; the sum of every run's `elapsed_ms` (30 runs, wall clock); the sum over the six
requests of their longest run (each request's runs compute in parallel); the sum of every run's
`cpu_ms` (its thread's CPU time: the integrators' share); and the server's CPU time per set
(/proc/PID/stat, user + system, averaged over the repetitions; it counts each core's time, so
it is the honest "compute" when runs share cores; minus Σ cpu_ms, it is what the server adds:
checking, JSON, HTTP).

Target (docs/performance.md): the whole figure set through /simulate under 60 ms of compute on this
2-core machine.

  python3 bench/figure_set_http.py                 # 15 repetitions
  python3 bench/figure_set_http.py --reps 30 --no-build --no-six --port 8083
"""

import argparse
import json
import os
import resource
import re
import subprocess
import sys
import threading
import time

from nhlab_bench import ROOT, Quiet, Server, build, cpu_seconds, log, median, other_load



def bodies(server):
    """The six requests, from the server's list of the paper's experiments (`GET /systems`)."""
    return [{"system": s["system"], "preset": s["preset"]}
            for s in server.get("/systems")["paper_scenes"]]


def one(server, body, out, i):
    """Sends one request and reads the whole answer (parsed later, outside the timing)."""
    c = server.connection()
    c.request("POST", "/simulate", json.dumps(body), {"content-type": "application/json"})
    r = c.getresponse()
    raw = r.read()
    c.close()
    if r.status != 200:
        raise RuntimeError(f"{body}: {r.status} {raw[:300]!r}")
    out[i] = raw


def parse(raw):
    js = json.loads(raw)
    runs = js["runs"]
    assert len(runs) == 5 and all(r["status"] == "ok" for r in runs), js
    return ([r["elapsed_ms"] for r in runs], sum(r["steps"] for r in runs), len(raw),
            sum(r["cpu_ms"] for r in runs))


def the_set(server, width, requests):
    """Sends the six requests, `width` at a time; returns (wall s, per-request results)."""
    out = [None] * len(requests)
    if width == 1:
        t0 = time.perf_counter()
        for i, b in enumerate(requests):
            one(server, b, out, i)
        return time.perf_counter() - t0, [parse(raw) for raw in out]
    queue = list(range(len(requests)))
    lock = threading.Lock()
    errors = []
    barrier = threading.Barrier(width + 1)

    def worker():
        barrier.wait()
        while True:
            with lock:
                if not queue:
                    return
                i = queue.pop(0)
            try:
                one(server, requests[i], out, i)
            except Exception as e:  # noqa: BLE001 (reported below)
                errors.append(e)
                return

    threads = [threading.Thread(target=worker) for _ in range(width)]
    for t in threads:
        t.start()
    barrier.wait()
    t0 = time.perf_counter()
    for t in threads:
        t.join()
    wall = time.perf_counter() - t0
    if errors:
        raise errors[0]
    return wall, [parse(raw) for raw in out]


def measure(server, width, reps, quiet):
    requests = bodies(server)
    the_set(server, width, requests)  # warm-up
    walls, sums, maxes, cpus, steps = [], [], [], [], None
    cpu = 0.0
    for _ in range(reps):
        quiet.wait()
        c0 = cpu_seconds(server.pid)
        wall, out = the_set(server, width, requests)
        cpu += cpu_seconds(server.pid) - c0
        walls.append(wall)
        sums.append(sum(sum(ms) for ms, _, _, _ in out) / 1e3)
        maxes.append(sum(max(ms) for ms, _, _, _ in out) / 1e3)
        cpus.append(sum(c for _, _, _, c in out) / 1e3)
        steps = sum(n for _, n, _, _ in out)
        size = sum(b for _, _, b, _ in out)
    cpu /= reps
    return {"wall": walls, "sum": sums, "max": maxes, "runs_cpu": cpus, "cpu": cpu,
            "steps": steps, "bytes": size}


def core_baseline(skip_build, nice):
    """The core alone: core/examples/figure_set.rs (one thread, 20 sets), under `nice`
    like the server's simulation threads; returns (wall s, CPU s) per set."""
    if not skip_build:
        log("building: cargo build --release -p nhlab-core --example figure_set")
        subprocess.run(["cargo", "build", "--release", "--quiet", "-p", "nhlab-core",
                        "--example", "figure_set"], cwd=ROOT, check=True)
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    cmd = [os.path.join(target, "release", "examples", "figure_set")]
    if nice:
        cmd = ["nice", "-n", str(nice), *cmd]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    value, unit = re.search(r"([0-9.]+)(ns|µs|ms|s) wall per set", out).groups()
    scale = {"ns": 1e-9, "µs": 1e-6, "ms": 1e-3, "s": 1.0}[unit]
    return float(value) * scale, cpu / 20


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--port", type=int, default=0)
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument("--reps", type=int, default=15)
    ap.add_argument("--no-six", dest="six", action="store_false")
    ap.add_argument("--no-baseline", dest="baseline", action="store_false",
                    help="skip the core-alone figure_set example")
    ap.add_argument("--baseline-nice", type=int, default=19)
    ap.add_argument("--max-busy", type=float, default=0.15,
                    help="wait before each set until the cores are at most this busy "
                         "(1 = never wait)")
    ap.add_argument("--quiet-timeout", type=float, default=60.0)
    args = ap.parse_args()
    quiet = Quiet(args.max_busy, args.quiet_timeout)

    binary = build(args.no_build)
    base = None
    if args.baseline:
        base = []
        for i in range(3):
            quiet.wait()
            base.append(core_baseline(args.no_build or i > 0, args.baseline_nice))
    rows = []
    server = Server(binary, port=args.port)
    slots = server.get("/health")["max_simulations"]
    log(f"default server: max_simulations = {slots}")
    log("== sequential")
    rows.append(("sequential (default server)", measure(server, 1, args.reps, quiet)))
    log(f"== {slots} at a time")
    rows.append((f"concurrent, {slots} at a time (default server, {slots} slots)",
                 measure(server, slots, args.reps, quiet)))
    server.stop()
    if args.six:
        server = Server(binary, ["--max-simulations", "6"], port=args.port)
        log("== six at once")
        rows.append(("six at once (--max-simulations 6)", measure(server, 6, args.reps, quiet)))
        server.stop()

    def mm(xs):
        return f"{min(xs) * 1e3:.1f} / {median(xs) * 1e3:.1f}"

    print(f"the figure set: 6 requests × 5 methods, {rows[0][1]['steps']} steps, "
          f"{rows[0][1]['bytes']} bytes of JSON; {args.reps} repetitions; ms as min / median")
    print()
    print("| how | wall of the set | Σ elapsed_ms (30 runs) | Σ over requests of the longest "
          "run | Σ cpu_ms (30 runs) | server CPU per set |")
    print("|---|---|---|---|---|---|")
    for label, m in rows:
        print(f"| {label} | {mm(m['wall'])} | {mm(m['sum'])} | {mm(m['max'])} | "
              f"{mm(m['runs_cpu'])} | {m['cpu'] * 1e3:.0f} |")
    if base:
        print(f"| core alone, one thread (figure_set example, nice {args.baseline_nice}, 3 × 20 "
              f"sets) | {min(w for w, _ in base) * 1e3:.1f} / {median([w for w, _ in base]) * 1e3:.1f}"
              f" | – | – | – | {min(c for _, c in base) * 1e3:.0f} |")
    print()
    print(f"machine: {other_load()}")
    print(f"shared machine: {quiet.report()}")
    best = min(rows[1:], key=lambda r: min(r[1]["wall"]))
    print(f"SUMMARY figure set through /simulate: wall {min(best[1]['wall']) * 1e3:.1f} ms "
          f"({best[0]}), sequential {min(rows[0][1]['wall']) * 1e3:.1f} ms; server CPU "
          f"{min(m['cpu'] for _, m in rows) * 1e3:.0f}–{max(m['cpu'] for _, m in rows) * 1e3:.0f}"
          f" ms per set; Σ elapsed_ms ≥ {min(min(m['sum']) for _, m in rows) * 1e3:.1f} ms; "
          f"target < 60 ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
