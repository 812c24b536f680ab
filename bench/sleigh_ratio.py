#!/usr/bin/env python3
"""nhlab's RATTLE on the Chaplygin sleigh against the same method written by hand in C
(`bench/rattle_sleigh.c`, compiled here with `gcc -O2`): the C loop, nhlab's built-in
`chaplygin_sleigh` and the sleigh given as formulas (its general form compiled) run in turn
(C, built-in, formulas, C, …), each run a process of its own, so that all three see the same
noise; per side the best and the median CPU time per step, and the ratios to C (targets:
built-in ≤ 2×, formulas ≤ 3×). First it checks that the three trajectories agree: the final
q after a few thousand steps from the `inclined` preset, without restarts.

    cargo build --release -p nhlab-core --example step_loop
    python3 bench/sleigh_ratio.py [--steps 3000000] [--restart 1000] [--rounds 7]

`--restart`: steps from the preset's start before starting again (1000: the preset's t = 100
at h = 0.1; the sleigh slides away, and later steps take fewer Newton iterations); 0 never.
"""

import argparse
import os
import re
import statistics
import subprocess

from formula_ratio import BINARY, cpu_seconds

HERE = os.path.dirname(os.path.abspath(__file__))
C_BINARY = os.path.normpath(os.path.join(os.path.dirname(BINARY), "..", "..", "rattle_sleigh"))
GCC = ["gcc", "-O2", "-o", C_BINARY, os.path.join(HERE, "rattle_sleigh.c"), "-lm"]
PRESET = "1"  # inclined
FLOAT = r"-?[0-9.]+(?:e-?[0-9]+)?"


def final_q(command):
    """The q a run prints last (`q = [x, y, θ]`)."""
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    line = [l for l in out.splitlines() if "q = [" in l][-1]
    return [float(x) for x in re.findall(FLOAT, line.split("q = [")[1].split("]")[0])]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", type=int, default=3_000_000)
    p.add_argument("--restart", type=int, default=1000)
    p.add_argument("--rounds", type=int, default=7)
    p.add_argument("--check-steps", type=int, default=5000)
    a = p.parse_args()
    subprocess.run(GCC, check=True)
    print("C:", " ".join(GCC))
    methods = subprocess.run([BINARY, "list"], check=True, capture_output=True, text=True).stdout
    rattle = next(l.split()[0] for l in methods.splitlines() if l.split()[1] == "RATTLE")
    sides = {
        "C": lambda n, r: [C_BINARY, str(n), str(r)],
        "built-in": lambda n, r: [BINARY, "chaplygin_sleigh", rattle, "fast", str(n), PRESET, str(r)],
        "formulas": lambda n, r: [BINARY, "chaplygin_sleigh", rattle, "formulas", str(n), PRESET, str(r)],
    }
    ends = {side: final_q(command(a.check_steps, 0)) for side, command in sides.items()}
    print(f"final q after {a.check_steps} steps (t = {a.check_steps / 10:g}) of the inclined sleigh:")
    for side, q in ends.items():
        diff = max(abs(x - c) / max(1.0, abs(c)) for x, c in zip(q, ends["C"]))
        print(f"  {side:9} {q}" + ("" if side == "C" else f"  max relative difference to C {diff:.1e}"))
    times = {side: [] for side in sides}
    for _ in range(a.rounds):
        for side, command in sides.items():
            binary, *args = command(a.steps, a.restart)
            times[side].append(cpu_seconds(args, binary) / a.steps * 1e9)
    runs = f"from the start again every {a.restart}" if a.restart else "without restarts"
    print(f"\nRATTLE, chaplygin_sleigh/inclined, {a.steps} steps {runs}, {a.rounds} rounds "
          "(CPU ns/step)")
    print("| side | best | median | best / C's | median / C's | target |\n|---|---|---|---|---|---|")
    best_c, median_c = min(times["C"]), statistics.median(times["C"])
    for side, target in zip(sides, ["", "≤ 2", "≤ 3"]):
        best, median = min(times[side]), statistics.median(times[side])
        print(f"| {side} | {best:.1f} | {median:.1f} | {best / best_c:.2f} | {median / median_c:.2f} | {target} |")


if __name__ == "__main__":
    main()
