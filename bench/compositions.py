#!/usr/bin/env python3
"""The work–precision targets of docs/high-order.md: per scene and error level 1e-4 … 1e-10,
the fastest composed (structure-preserving) method, nhlab's RK4 and SciPy's DOP853, each read
on the grid (the fastest run that reached the level) and interpolated on its curve (as
bench/compare.py reads them), and the speed-ups.

    cargo run --release -p nhlab-core --example compositions -- wp > target/wp_compositions.csv
    pip install scipy && python3 bench/scipy_dop853.py > target/wp_scipy.csv
    python3 bench/compositions.py target/wp_compositions.csv target/wp_scipy.csv

With `--spark` (on the CSV of `compositions -- wp spark`): the fastest SPARK beside the fastest
composed method, RK4 and DOP853, on the grid, 1e-6 … 1e-10.
"""
import sys

from compare import fastest, interpolated, rows


def main():
    ours, theirs = list(rows(sys.argv[1])), list(rows(sys.argv[2]))
    composed = [r for r in ours if "∘" in r[1]]
    rk4 = [r for r in ours if r[1] == "RK4"]
    print("| scene | error ≤ | fastest composed | ms | RK4 ms | RK4 / composed | DOP853 ms "
          "| DOP853 / composed | interpolated: composed ms | RK4 ms | DOP853 ms |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    ms = lambda x: f"{x[0]:.2f}" if x else "not reached"
    ratio = lambda a, b: f"{b[0] / a[0]:.2f}×" if a and b else "–"
    for scene in sorted({s for s, *_ in ours}):
        for k in range(4, 11):
            level = 10.0 ** -k
            c, r, d = (fastest(x, scene, level) for x in (composed, rk4, theirs))
            ci, ri, di = (interpolated(x, scene, level) for x in (composed, rk4, theirs))
            print(f"| {scene} | 1e-{k} | {c[1] if c else '–'} | {ms(c)} | {ms(r)} | {ratio(c, r)} "
                  f"| {ms(d)} | {ratio(c, d)} | {ms(ci)} ({ci[1] if ci else '–'}) | {ms(ri)} "
                  f"| {ms(di)} |")


def spark(ours, theirs):
    sparks = [r for r in ours if r[1].startswith("SPARK") and "∘" not in r[1]]
    composed = [r for r in ours if "∘" in r[1]]
    rk4 = [r for r in ours if r[1] == "RK4"]
    print("| scene | error ≤ | fastest SPARK | ms | fastest composed | ms | RK4 ms | DOP853 ms "
          "| composed / SPARK | RK4 / SPARK | DOP853 / SPARK |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    ms = lambda x: f"{x[0]:.2f}" if x else "not reached"
    ratio = lambda a, b: f"{b[0] / a[0]:.2f}×" if a and b else "–"
    for scene in sorted({s for s, *_ in ours}):
        for k in range(6, 11):
            level = 10.0 ** -k
            p, c, r, d = (fastest(x, scene, level) for x in (sparks, composed, rk4, theirs))
            print(f"| {scene} | 1e-{k} | {p[1] if p else '–'} | {ms(p)} | {c[1] if c else '–'} "
                  f"| {ms(c)} | {ms(r)} | {ms(d)} | {ratio(p, c)} | {ratio(p, r)} | {ratio(p, d)} |")


if __name__ == "__main__":
    if "--spark" in sys.argv:
        sys.argv.remove("--spark")
        spark(list(rows(sys.argv[1])), list(rows(sys.argv[2])))
    else:
        main()
