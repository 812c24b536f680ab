#!/usr/bin/env python3
"""Reads the two work–precision CSVs (nhlab's and SciPy's) and prints, per scene and error
level 1e-2 … 1e-8, the fastest run of each that reaches it and the speed-up.

    python3 bench/compare.py target/wp_nhlab.csv target/wp_scipy.csv
"""
import csv
import sys


def rows(path):
    with open(path) as f:
        for r in csv.DictReader(f):
            if r["final_error"] not in ("failed", "nan"):
                yield r["scene"], r["method"], float(r["elapsed_ms"]), float(r["final_error"])


def fastest(data, scene, level):
    hits = [(ms, m) for s, m, ms, e in data if s == scene and e <= level]
    return min(hits) if hits else None


def main():
    ours, theirs = list(rows(sys.argv[1])), list(rows(sys.argv[2]))
    print("| scene | error ≤ | nhlab fastest | ms | SciPy DOP853 ms | speed-up |")
    print("|---|---|---|---|---|---|")
    for scene in sorted({s for s, *_ in ours}):
        for k in range(2, 9):
            level = 10.0 ** -k
            a, b = fastest(ours, scene, level), fastest(theirs, scene, level)
            fmt = lambda x: f"{x[0]:.3f}" if x else "not reached"
            ratio = f"{b[0] / a[0]:.0f}×" if a and b else "–"
            print(f"| {scene} | 1e-{k} | {a[1] if a else '–'} | {fmt(a)} | {fmt(b)} | {ratio} |")


if __name__ == "__main__":
    main()
