#!/usr/bin/env python3
"""A/B of the criterion ns/step table: two builds of `core/benches/steps.rs` run in turn
(A, B, A, B, …) on one machine, so that both see the same noise; per cell the best of each
side's rounds, the ratio B/A, the geometric mean of the ratios and the worst cell.

    cargo bench -p nhlab-core --bench steps --no-run   # prints the binary's path; copy it
    python3 bench/ab_steps.py A_BINARY B_BINARY [--rounds 2] [--filter REGEX]

Cells only one side has (a new system or method) are listed apart.
"""

import argparse
import math
import re
import subprocess

UNITS = {"ps": 1e-3, "ns": 1.0, "µs": 1e3, "us": 1e3, "ms": 1e6, "s": 1e9}
TIME = re.compile(r"time:\s+\[\S+ \S+ (\S+) (\S+) \S+ \S+\]")
STEPS = 10_000  # steps per iteration of `bench_system`


def run(binary, args):
    out = subprocess.run(
        [binary, "--bench", "--measurement-time", str(args.time), "--warm-up-time", "0.5"]
        + ([args.filter] if args.filter else []),
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    cells, name = {}, None
    for line in out.splitlines():
        m = TIME.search(line)
        head = line.split("time:")[0].strip()
        if head and not line.startswith(" "):
            name = head
        if m and name:
            value = float(m.group(1)) * UNITS[m.group(2)]
            cells[name] = value / STEPS if name.startswith("step/") else value / 1e6
    return cells


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("a")
    p.add_argument("b")
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--time", type=float, default=1.0, help="criterion measurement time, s")
    p.add_argument("--filter", default="")
    args = p.parse_args()
    best = {"a": {}, "b": {}}
    for _ in range(args.rounds):
        for side in ("a", "b"):
            for cell, v in run(getattr(args, side), args).items():
                best[side][cell] = min(v, best[side].get(cell, math.inf))
    both = [c for c in best["a"] if c in best["b"]]
    print("| cell | A | B | B/A |\n|---|---|---|---|")
    ratios = []
    for c in both:
        a, b = best["a"][c], best["b"][c]
        unit = "ns/step" if c.startswith("step/") else "ms"
        ratios.append(b / a)
        print(f"| {c} | {a:.1f} | {b:.1f} {unit} | {b / a:.3f} |")
    only = sorted(set(best["a"]) ^ set(best["b"]))
    for c in only:
        side = "A" if c in best["a"] else "B"
        print(f"| {c} | only in {side}: {best[side.lower()][c]:.1f} | | |")
    if ratios:
        geo = math.exp(sum(map(math.log, ratios)) / len(ratios))
        worst = max(zip(ratios, both))
        print(f"\ngeometric mean B/A {geo:.3f} over {len(ratios)} cells; "
              f"worst {worst[1]} {worst[0]:.3f}")


if __name__ == "__main__":
    main()
