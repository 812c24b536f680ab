#!/usr/bin/env python3
"""What the general class costs a system of the paper's class: `step_loop` runs each method
on a built-in class system on its class path (`fast`, what a run of it takes) and forced
through the general path (`as-general`: the method's general-class step on the system seen
through `General`, `nhlab_core::model::mechanical::General`), in turn (class, general, class,
…), each run a process of its own; per system, preset and method the best and the median CPU
time per step of each side, their ratios general / class (target ≤ 2.5 for LF, DLA^½ and DD),
and the geometric means of the ratios.

    cargo build --release -p nhlab-core --example step_loop
    python3 bench/general_ratio.py [--cases knife_edge:0,knife_edge:1,cvt_pendulum:3]
        [--methods 0,3,4] [--paths fast,as-general] [--steps 3000000] [--rounds 5]

A case is SYSTEM:PRESET (preset indices as in `step_loop`); `step_loop list` gives the
method indices (0 DLA^0.5, 3 LF, 4 DD). `--paths fast,general-formulas` compares the class
path with the system's general form compiled instead.
"""

import argparse
import math
import statistics
import subprocess

from formula_ratio import BINARY, cpu_seconds


def geometric_mean(xs):
    return math.exp(sum(map(math.log, xs)) / len(xs))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cases", default="knife_edge:0,knife_edge:1,cvt_pendulum:3")
    p.add_argument("--methods", default="0,3,4")
    p.add_argument("--paths", default="fast,as-general")
    p.add_argument("--steps", type=int, default=3_000_000)
    p.add_argument("--rounds", type=int, default=5)
    a = p.parse_args()
    labels = dict(
        line.split()[:2]
        for line in subprocess.run([BINARY, "list"], check=True, capture_output=True, text=True)
        .stdout.splitlines()
    )
    class_path, general_path = a.paths.split(",")
    print(f"{a.steps} steps, {a.rounds} rounds (CPU ns/step); {general_path} / {class_path}")
    print(f"| system | preset | method | {class_path} best | {general_path} best "
          "| ratio of bests | ratio of medians |\n|---|---|---|---|---|---|---|")
    ratios = {}
    for case in a.cases.split(","):
        system, preset = case.split(":")
        for m in a.methods.split(","):
            times = {class_path: [], general_path: []}
            for _ in range(a.rounds):
                for path in times:
                    args = [system, m, path, str(a.steps), preset]
                    times[path].append(cpu_seconds(args) / a.steps * 1e9)
            c, g = times[class_path], times[general_path]
            best, median = min(g) / min(c), statistics.median(g) / statistics.median(c)
            ratios.setdefault(m, []).append(best)
            print(f"| {system} | {preset} | {labels.get(m, m)} | {min(c):.0f} | {min(g):.0f} "
                  f"| {best:.2f} | {median:.2f} |")
    print("\ngeometric mean of the ratios of bests: "
          + ", ".join(f"{labels.get(m, m)} {geometric_mean(r):.2f}" for m, r in ratios.items())
          + f"; all {geometric_mean([x for r in ratios.values() for x in r]):.2f}")


if __name__ == "__main__":
    main()
