#!/usr/bin/env python3
"""What a method written in Python costs (docs/own-methods.md, docs/performance.md).

  overhead     the call into Python per step beyond the user's own function: a step that
               returns its input, against the built-in leap-frog in the same request
               (knife_edge/paper, 63,661 steps), interleaved rounds; the difference of
               cpu_ms per step, minus the function's own time (timed alone with timeit);
  figure set   the paper's six scenes with the docs' leap-frog (nhlab.examples.Leapfrog) in
               place of each of the five methods: 603,180 Python steps, every integral, 1000
               points; Σ cpu_ms (one core's work) and the wall time.

Needs the package installed (`pip install ./python`) or on PYTHONPATH with a release build.

  python3 bench/python_methods.py [--rounds 5]
"""

import argparse
import statistics
import time
import timeit

import numpy as np

import nhlab
from nhlab.examples import Leapfrog


class Still(nhlab.Method):
    name = "still"

    def step(self, system, q, v, h, memory):
        return q, v


def overhead(rounds):
    q = np.zeros(3)
    alone = timeit.timeit(lambda: Still().step(None, q, q, 0.1, {}), number=200_000) / 200_000
    per_step = []
    for _ in range(rounds):
        r = nhlab.simulate("knife_edge", preset="paper", methods=["leapfrog", Still()],
                           t_end=20_000, points=10)
        lf, still = r.runs
        per_step.append((still.cpu_ms - lf.cpu_ms) / still.steps * 1e3)
    call = statistics.median(per_step) - alone * 1e6
    print(f"overhead: {statistics.median(per_step):.3f} µs/step beyond the built-in LF "
          f"(rounds {', '.join(f'{x:.3f}' for x in per_step)}), the function alone "
          f"{alone * 1e6:.3f} µs: the call costs {call:.3f} µs/step")


def figure_set():
    scenes = nhlab.systems()["paper_scenes"]
    steps = cpu = 0
    start = time.perf_counter()
    for s in scenes:
        r = nhlab.simulate(s["system"], preset=s["preset"], methods=[Leapfrog()] * 5)
        steps += sum(run.steps for run in r.runs)
        cpu += sum(run.cpu_ms for run in r.runs)
    wall = time.perf_counter() - start
    print(f"figure set with the Python leap-frog: {steps:,} steps, Σ cpu {cpu / 1e3:.1f} s "
          f"({cpu / steps * 1e3:.1f} µs/step), wall {wall:.1f} s")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    overhead(args.rounds)
    figure_set()
