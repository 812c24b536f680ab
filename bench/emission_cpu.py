#!/usr/bin/env python3
"""What writing a dense answer costs the server's CPU, beside the compute (the streaming
overhead, measured without the wall clock's noise).

A wall-clock ratio on a run of ~12 ms on two shared cores moves by tens of percent between
two runs of the same binary (docs/performance.md, "How to measure"). This script counts CPU instead:
the server's threads' CPU time per request, read exactly from /proc/PID/task/*/schedstat, over
blocks of back-to-back requests, for one scene answered

  - as a stream or as JSON, and
  - with `points` 1000 (the default: 75,000 numbers for the CVT preset) or 10 (the same
    runs, the same per-step work, almost nothing to write).

From these:
  compute     the runs' own CPU (Σ `cpu_ms` of the runs) with points = 10;
  dense       server CPU(points 1000) − server CPU(points 10), per delivery: what the 1000
              points cost to bucket, keep, format and send;
  streaming   server CPU(stream, 1000) − server CPU(JSON, 1000): what a stream costs beyond
              the same numbers as one JSON document;
each also as a fraction of compute. The blocking pool keeps its threads between
back-to-back requests; a block during which a thread ended is measured again.

  python3 bench/emission_cpu.py                 # CVT preset, 5 rounds of 20 requests each
  python3 bench/emission_cpu.py --scene long --reps 3 --no-build
"""

import argparse
import json
import statistics
import time

from nhlab_bench import Server, build, log, stream, thread_cpu_ns

SCENES = {
    "cvt": {
        "label": "cvt_pendulum/rotating-perturbed, the paper's five, 30,000 steps, all integrals",
        "body": {"system": "cvt_pendulum", "preset": "rotating-perturbed"},
    },
    "long": {
        "label": "knife_edge/paper, leapfrog, 10⁷ steps",
        "body": {"system": "knife_edge", "preset": "paper", "methods": ["leapfrog"]},
        "steps": 10**7,  # t_end from the preset's step, read from /systems
    },
}


def one(server, body, delivery):
    """One request: (Σ of its runs' cpu_ms, bytes of the answer)."""
    if delivery == "json":
        c = server.connection()
        c.request("POST", "/simulate", json.dumps(body).encode(),
                  {"content-type": "application/json"})
        r = c.getresponse()
        raw = r.read()
        c.close()
        assert r.status == 200, raw[:500]
        return sum(run["cpu_ms"] for run in json.loads(raw)["runs"]), len(raw)
    res = stream(server, body, parse=False)
    assert res.events and res.events[-1][0] == "done", res.events[-1:]
    runs = [json.loads(d) for n, d in res.events if n == "run"]
    return sum(r["cpu_ms"] for r in runs), res.bytes


def block(server, body, delivery, reps):
    """CPU per request of the server over `reps` back-to-back requests (after one warm-up)."""
    for _ in range(5):
        one(server, body, delivery)
        c0, tids0 = thread_cpu_ns(server.pid)
        runs, size = 0.0, 0
        for _ in range(reps):
            r, size = one(server, body, delivery)
            runs += r
        c1, tids1 = thread_cpu_ns(server.pid)
        if tids0 <= tids1:
            return (c1 - c0) / reps / 1e6, runs / reps, size
        log("  a thread ended during the block: measuring it again")
    raise RuntimeError("the server's threads kept changing")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", choices=sorted(SCENES), default="cvt")
    ap.add_argument("--reps", type=int, default=20, help="requests per block")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--port", type=int, default=0)
    ap.add_argument("--no-build", action="store_true")
    args = ap.parse_args()
    scene = SCENES[args.scene]
    server = Server(build(args.no_build), port=args.port)
    body = dict(scene["body"])
    if "steps" in scene:
        system = next(s for s in server.get("/systems")["systems"] if s["id"] == body["system"])
        step = next(p for p in system["presets"] if p["id"] == body["preset"])["step"]
        body["t_end"] = (scene["steps"] + 0.5) * step
    conditions = [(d, p) for d in ("stream", "json") for p in (10, 1000)]
    cpu = {c: [] for c in conditions}
    runs = {c: [] for c in conditions}
    size = {}
    for i in range(args.rounds):
        for d, p in conditions:
            c, r, n = block(server, {**body, "points": p}, d, args.reps)
            cpu[(d, p)].append(c)
            runs[(d, p)].append(r)
            size[(d, p)] = n
            log(f"round {i + 1}: {d} points={p}: server {c:.2f} ms, runs {r:.2f} ms per request")
    med = {c: statistics.median(v) for c, v in cpu.items()}
    compute = statistics.median(runs[("json", 10)] + runs[("stream", 10)])

    def fmt(xs):
        return f"{min(xs):.2f} / {statistics.median(xs):.2f}"

    print(f"{scene['label']}: {args.rounds} rounds × {args.reps} requests, ms per request as "
          "min / median over the rounds")
    print()
    print("| delivery | points | server CPU | the runs' CPU (Σ cpu_ms) | bytes |")
    print("|---|---|---|---|---|")
    for d, p in conditions:
        print(f"| {d} | {p} | {fmt(cpu[(d, p)])} | {fmt(runs[(d, p)])} | {size[(d, p)]:,} |")
    dense_stream = med[("stream", 1000)] - med[("stream", 10)]
    dense_json = med[("json", 1000)] - med[("json", 10)]
    streaming = med[("stream", 1000)] - med[("json", 1000)]
    print()
    summary = (
        f"compute {compute:.2f} ms; dense output: stream {dense_stream:+.2f} ms "
        f"({dense_stream / compute:+.1%}), JSON {dense_json:+.2f} ms ({dense_json / compute:+.1%}); "
        f"stream beyond JSON {streaming:+.2f} ms ({streaming / compute:+.1%})"
    )
    print("SUMMARY " + summary)
    return 0


if __name__ == "__main__":
    t0 = time.time()
    code = main()
    log(f"took {time.time() - t0:.0f} s")
    raise SystemExit(code)
