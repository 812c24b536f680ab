#!/usr/bin/env python3
"""Reads the two work–precision CSVs (nhlab's and SciPy's) and prints, per scene and error
level 1e-2 … 1e-8, the fastest run of each that reaches it and the speed-up — on the grid
(a run that reached the level) and interpolated (each method's or tolerance ladder's
work–precision curve, log–log linear between the two runs that bracket the level, so that
neither side's grid spacing decides the answer; the same rule for both sides).

    python3 bench/compare.py target/wp_nhlab.csv target/wp_scipy.csv
    python3 bench/compare.py --tables target/wp_nhlab.csv   # nhlab's rows, one table per scene
"""
import csv
import math
import sys


def rows(path):
    with open(path) as f:
        for r in csv.DictReader(f):
            if r["final_error"] not in ("failed", "nan"):
                yield r["scene"], r["method"], float(r["elapsed_ms"]), float(r["final_error"])


def fastest(data, scene, level):
    hits = [(ms, m) for s, m, ms, e in data if s == scene and e <= level]
    return min(hits) if hits else None


def tables(path):
    """nhlab's work–precision rows as Markdown: one row per step, one column per method."""
    with open(path) as f:
        data = list(csv.DictReader(f))
    for scene in dict.fromkeys(r["scene"] for r in data):
        rs = [r for r in data if r["scene"] == scene]
        methods = list(dict.fromkeys(r["method"] for r in rs))
        steps = sorted({float(r["step"]) for r in rs}, reverse=True)
        print(f"**{scene}** — final error ‖(q, q̇)(t_end) − reference‖∞ · run time (ms, min of 5)\n")
        print("| h | " + " | ".join(methods) + " |")
        print("|---" * (len(methods) + 1) + "|")
        for h in steps:
            cells = []
            for m in methods:
                r = next((r for r in rs if r["method"] == m and float(r["step"]) == h), None)
                if r is None:
                    cells.append("–")
                elif r["final_error"] in ("failed", "nan"):
                    cells.append(f"failed · {float(r['elapsed_ms']):.2f}")
                else:
                    cells.append(f"{float(r['final_error']):.1e} · {float(r['elapsed_ms']):.2f}")
            print(f"| {h:.4g} | " + " | ".join(cells) + " |")
        print()


def interpolated(data, scene, level):
    """Fastest (ms, method) over each method's curve, read at `level` by log–log interpolation
    between consecutive runs (ordered by cost) whose errors bracket it."""
    best = None
    for method in {m for s, m, *_ in data if s == scene}:
        curve = sorted((ms, e) for s, m, ms, e in data if s == scene and m == method)
        for (t0, e0), (t1, e1) in zip(curve, curve[1:]):
            if e0 > level >= e1 > 0:
                f = math.log(e0 / level) / math.log(e0 / e1)
                t = t0 * (t1 / t0) ** f
                if best is None or t < best[0]:
                    best = (t, method)
                break
        first = curve[0] if curve else None
        if first and first[1] <= level and (best is None or first[0] < best[0]):
            best = first[0], method
    return best


def main():
    if sys.argv[1] == "--tables":
        tables(sys.argv[2])
        return
    ours, theirs = list(rows(sys.argv[1])), list(rows(sys.argv[2]))
    print("| scene | error ≤ | nhlab fastest | ms | SciPy DOP853 ms | speed-up "
          "| interpolated: nhlab ms | SciPy ms | speed-up |")
    print("|---|---|---|---|---|---|---|---|---|")
    fmt = lambda x: f"{x[0]:.3f}" if x else "not reached"
    ratio = lambda a, b: f"{b[0] / a[0]:.0f}×" if a and b else "–"
    for scene in sorted({s for s, *_ in ours}):
        for k in range(2, 9):
            level = 10.0 ** -k
            a, b = fastest(ours, scene, level), fastest(theirs, scene, level)
            ai, bi = interpolated(ours, scene, level), interpolated(theirs, scene, level)
            print(f"| {scene} | 1e-{k} | {a[1] if a else '–'} | {fmt(a)} | {fmt(b)} | {ratio(a, b)} "
                  f"| {fmt(ai)} | {fmt(bi)} | {ratio(ai, bi)} |")


if __name__ == "__main__":
    main()
