#!/usr/bin/env python3
"""What a system given as formulas costs: `step_loop` runs each method on a built-in system
and on the same system given as formulas (`FormulaSpec::of`, what `GET /systems` lists), in
turn (built-in, formulas, built-in, …), each run a process of its own, so that both sides see
the same noise and the compiled formulas land at a new address each time; per method the
best and the median CPU time of each side and their ratios formulas / built-in.

    cargo build --release -p nhlab-core --example step_loop
    python3 bench/formula_ratio.py [--system cvt_pendulum] [--preset 3] [--methods 3,4]
                                   [--steps 3000000] [--rounds 7]

The defaults are the targets' case: `cvt_pendulum`, rotating with ε = 0.5, leap-frog (3) and
DD (4); `step_loop list` gives the method indices.
"""

import argparse
import os
import resource
import statistics
import subprocess

BINARY = os.path.join(os.environ.get("CARGO_TARGET_DIR", "target"), "release/examples/step_loop")


def cpu_seconds(args, binary=BINARY):
    """CPU time of one `step_loop` run (or of `binary`'s), from the children's resource usage."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([binary] + args, check=True, stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--system", default="cvt_pendulum")
    p.add_argument("--preset", default="3")
    p.add_argument("--methods", default="3,4")
    p.add_argument("--steps", type=int, default=3_000_000)
    p.add_argument("--rounds", type=int, default=7)
    a = p.parse_args()
    labels = dict(
        line.split()[:2]
        for line in subprocess.run([BINARY, "list"], check=True, capture_output=True, text=True)
        .stdout.splitlines()
    )
    print(f"{a.system}, preset {a.preset}, {a.steps} steps, {a.rounds} rounds (ns/step)")
    print("| method | built-in best | formulas best | ratio of bests | ratio of medians |")
    print("|---|---|---|---|---|")
    for m in a.methods.split(","):
        times = {"fast": [], "formulas": []}
        for _ in range(a.rounds):
            for path in times:
                args = [a.system, m, path, str(a.steps), a.preset]
                times[path].append(cpu_seconds(args) / a.steps * 1e9)
        b, f = times["fast"], times["formulas"]
        print(
            f"| {labels.get(m, m)} | {min(b):.0f} | {min(f):.0f} | {min(f) / min(b):.2f} "
            f"| {statistics.median(f) / statistics.median(b):.2f} |"
        )


if __name__ == "__main__":
    main()
