#!/usr/bin/env python3
"""Long runs through the stream: memory stays flat and the series is exact.

Starts the release server on loopback (ephemeral port unless --port), then on the knife edge
(preset `paper`, h = π/10) streams, one request per method (Accept: text/event-stream,
every event read and parsed):

  leapfrog for N = 10⁸ steps, and dla α=0.5, dla α=0.4, dla01, dd for N = 10⁷ steps,
  each with P = 1000 points, every integral of the system;

and for each the same run with N/10 steps and P/10 points. While a run streams, the
server's VmRSS (/proc/PID/status) is sampled every --interval seconds; VmHWM (peak RSS, reset
through /proc/PID/clear_refs before each run) catches peaks between samples.

Exactness: bucket j of a series of `total` samples in B buckets ends at sample
⌊(j+1)·total/B⌋ (core/src/measure/bucket.rs). With N divisible by 10·P, both runs end bucket j at
(j+1)·N/P, so the first P/10 buckets of the long run must equal the short run's buckets
bitwise (t, mean, max of every integral). The short run is also fetched as JSON and must equal
its stream exactly. t_end is sent as (N + ½)·h, so ⌊t_end/h + 10⁻⁹⌋ = N without rounding
doubts; the scene event's `steps` is checked.

  python3 bench/long_runs.py                 # the full measurement (~1 min of compute)
  python3 bench/long_runs.py --scale 0.01    # 100× fewer steps: a quick check
  python3 bench/long_runs.py --no-build --port 8081 --interval 0.5

Exit status 1 if any check fails. Prints a Markdown table and a summary line.
"""

import argparse
import struct
import sys

from nhlab_bench import RssSampler, Server, build, hwm_kib, log, other_load, post_json, reset_hwm
from nhlab_bench import rss_kib, stream

METHODS = [
    ({"id": "leapfrog"}, "LF", 10**8),
    ({"id": "dla", "alpha": 0.5}, "DLA^0.5", 10**7),
    ({"id": "dla", "alpha": 0.4}, "DLA^0.4", 10**7),
    ({"id": "dla01"}, "DLA^{0,1}", 10**7),
    ({"id": "dd"}, "DD", 10**7),
]


def bits(x):
    return None if x is None else struct.pack("<d", x)


def same(a, b):
    return len(a) == len(b) and all(bits(x) == bits(y) for x, y in zip(a, b))


def body(method, steps, h, points):
    return {
        "system": "knife_edge",
        "preset": "paper",
        "t_end": (steps + 0.5) * h,
        "methods": [method],
        "points": points,
    }


def streamed(server, req, interval):
    reset_ok = reset_hwm(server.pid)
    sampler = RssSampler(server.pid, interval)
    res = stream(server, req)
    samples = sampler.stop()
    kib = [k for _, k in samples]
    mem = {
        "start": kib[0],
        "peak": max(kib),
        "end": kib[-1],
        "hwm": hwm_kib(server.pid) if reset_ok else None,
        "samples": len(kib),
        "trace": kib,
    }
    return res, mem


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--port", type=int, default=0, help="loopback port (default: ephemeral)")
    ap.add_argument("--no-build", action="store_true", help="use target/release/nhlab as is")
    ap.add_argument("--interval", type=float, default=1.0, help="RSS sampling period, s")
    ap.add_argument("--points", type=int, default=1000)
    ap.add_argument("--scale", type=float, default=1.0, help="multiply every step count")
    args = ap.parse_args()

    server = Server(build(args.no_build), port=args.port)
    info = server.get("/systems")
    knife = next(s for s in info["systems"] if s["id"] == "knife_edge")
    h = next(p for p in knife["presets"] if p["id"] == "paper")["step"]
    log(f"knife_edge/paper: h = {h!r}; server RSS at rest {rss_kib(server.pid)} KiB")
    P = args.points
    ok = True
    rows = []
    for method, label, n in METHODS:
        N = int(round(n * args.scale))
        if N % (10 * P) or P % 10:
            sys.exit(f"N = {N} must be divisible by 10·P = {10 * P} (and P by 10)")
        log(f"== {label}: {N} steps, {P} points, then {N // 10} steps, {P // 10} points")
        long_res, long_mem = streamed(server, body(method, N, h, P), args.interval)
        short_req = body(method, N // 10, h, P // 10)
        short_res, short_mem = streamed(server, short_req, args.interval)
        checks = []
        for res, steps, points in ((long_res, N, P), (short_res, N // 10, P // 10)):
            scene = res.of("scene")[0]
            run = res.of("run")[0]
            done = res.of("done")
            checks.append(scene["steps"] == steps and scene["points"] == points)
            checks.append(run["status"] == "ok" and run["steps"] == steps and len(done) == 1)
        long_s, short_s = long_res.series(0), short_res.series(0)
        integrals = sorted(short_s)
        exact = bool(integrals) and sorted(long_s) == integrals
        # The comparison has teeth: how many compared values are nonzero.
        nonzero = sum(1 for i in integrals for x in short_s[i]["max"] if x)
        for name in integrals:
            for k in ("t", "mean", "max"):
                if len(long_s[name][k]) != P or len(short_s[name][k]) != P // 10:
                    exact = False
                    log(f"  {name}.{k}: {len(long_s[name][k])} / {len(short_s[name][k])} buckets")
                elif not same(long_s[name][k][: P // 10], short_s[name][k]):
                    exact = False
                    log(f"  {name}.{k}: the first {P // 10} buckets differ")
        json_same = True
        if N // 10 <= 20_000_000:
            status, js, _ = post_json(server, short_req)
            series = js["runs"][0]["series"] if status == 200 else {}
            json_same = status == 200 and sorted(series) == integrals and all(
                same(series[i][k], short_s[i][k]) for i in integrals for k in ("t", "mean", "max")
            )
        run = long_res.of("run")[0]
        row = {
            "label": label,
            "N": N,
            "elapsed_ms": run["elapsed_ms"],
            "wall_s": long_res.wall,
            "events": len(long_res.events),
            "bytes": long_res.bytes,
            "mem": long_mem,
            "short_mem": short_mem,
            "short_elapsed_ms": short_res.of("run")[0]["elapsed_ms"],
            "integrals": integrals,
            "exact": exact,
            "nonzero": nonzero,
            "json_same": json_same,
            "checks": all(checks),
        }
        rows.append(row)
        ok &= exact and json_same and all(checks)
        log(
            f"  {N} steps: {run['elapsed_ms']:.0f} ms compute, {long_res.wall:.2f} s stream, "
            f"RSS start/peak/end {long_mem['start']}/{long_mem['peak']}/{long_mem['end']} KiB "
            f"(VmHWM {long_mem['hwm']}, {long_mem['samples']} samples); "
            f"short run peak {short_mem['peak']} KiB (VmHWM {short_mem['hwm']}); "
            f"first {P // 10} buckets equal: {exact}; JSON = stream: {json_same}"
        )

    print(f"knife_edge/paper, h = {h}, P = {P} points (short runs: N/10 steps, P/10 points)")
    print(f"integrals compared: {', '.join(rows[0]['integrals'])}")
    print()
    print(
        "| method | steps N | compute (run elapsed_ms) | stream wall | events | RSS start / peak / "
        "end (KiB) | VmHWM (KiB) | N/10-step run: peak RSS, VmHWM (KiB) | first P/10 buckets "
        "= N/10 run | N/10 JSON = stream |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        m, s = r["mem"], r["short_mem"]
        print(
            f"| {r['label']} | {r['N']:.0e} | {r['elapsed_ms'] / 1e3:.2f} s | {r['wall_s']:.2f} s "
            f"| {r['events']} | {m['start']} / {m['peak']} / {m['end']} | {m['hwm']} "
            f"| {s['peak']}, {s['hwm']} | {'bitwise equal' if r['exact'] else 'DIFFERENT'} "
            f"| {'equal' if r['json_same'] else 'DIFFERENT'} |"
        )
    print()
    for r in rows:
        print(f"{r['label']}, {r['N']:.0e} steps: RSS every {args.interval} s (KiB): "
              + " ".join(map(str, r["mem"]["trace"]))
              + f"; nonzero max values among the compared buckets: {r['nonzero']}")
    starts = [r["mem"]["start"] for r in rows]
    peaks = [max(r["mem"]["peak"], r["mem"]["hwm"] or 0) for r in rows]
    print()
    print(f"machine: {other_load()}")
    print(
        f"SUMMARY long runs: {'all checks passed' if ok else 'SOME CHECKS FAILED'}; server RSS "
        f"{min(starts)}–{max(starts)} KiB before a run, peak {max(peaks)} KiB "
        f"(largest rise during a run {max(p - s for p, s in zip(peaks, starts))} KiB); "
        f"first P/10 buckets bitwise equal to the N/10-step run for "
        f"{sum(r['exact'] for r in rows)}/{len(rows)} methods"
    )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
