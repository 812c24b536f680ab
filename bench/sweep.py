#!/usr/bin/env python3
"""The sweep targets of docs/performance.md: a 20 × 20 map of the paper's five methods on the
rotating perturbed CVT to t = 300 (ε × the passenger's initial x: 400 cells, 2,000 runs,
6·10⁶ steps) through `POST /sweep`,

- its wall time against the sum of its runs' CPU (the rows' `cpu_ms`) divided by the cores:
  what the sweep machinery (checking, scheduling, latitude axes, JSON) adds;
- on two cores against one: the release server started under `taskset -c 0,1` and
  `taskset -c 0` (a sweep takes one worker per core it may use), interleaved, rounds × each.

    python3 bench/sweep.py [--rounds 3] [--no-latitude] [--skip-build]

`--no-latitude` measures the four step integrals only: the latitude's monodromy axis is a
Dop853 solve per distinct initial state (here one per cell), work no run's CPU counts.
"""

import argparse
import os
import stat
import tempfile

from nhlab_bench import Server, build, log, post_json


def body(latitude):
    integrals = ["energy", "passenger_energy", "driver_energy", "constraint"]
    return {
        "system": "cvt_pendulum", "preset": "rotating-perturbed", "t_end": 300,
        "integrals": integrals + (["latitude"] if latitude else []),
        "axes": [{"path": "params.epsilon", "linspace": [0, 0.5, 20]},
                 {"path": "q[0]", "linspace": [0.5, 1.5, 20]}],
    }


def pinned(binary, cpus, directory):
    """A wrapper that runs `binary` on `cpus` only (exec: the same pid)."""
    path = os.path.join(directory, f"nhlab-on-{cpus.replace(',', '-')}")
    with open(path, "w") as f:
        f.write(f'#!/bin/sh\nexec taskset -c {cpus} "{binary}" "$@"\n')
    os.chmod(path, os.stat(path).st_mode | stat.S_IEXEC)
    return path


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--no-latitude", action="store_true")
    p.add_argument("--skip-build", action="store_true")
    args = p.parse_args()
    binary = build(args.skip_build)
    req = body(not args.no_latitude)
    with tempfile.TemporaryDirectory() as d:
        servers = {cores: Server(pinned(binary, cpus, d)) for cores, cpus in ((1, "0"), (2, "0,1"))}
        results = {1: [], 2: []}
        for r in range(args.rounds):
            for cores in (2, 1):
                status, answer, wall = post_json(servers[cores], req, "/sweep")
                assert status == 200, answer
                rows = answer["rows"]
                assert len(rows) == 2000 and all(x["status"] == "ok" for x in rows)
                steps = sum(x["steps"] for x in rows)
                cpu = sum(x["cpu_ms"] for x in rows) / 1e3
                results[cores].append((wall, cpu))
                log(f"round {r}, {cores} core(s): {wall:.3f} s wall, runs' CPU {cpu:.3f} s, "
                    f"{steps} steps, wall / (CPU / cores) = {wall / (cpu / cores):.3f}")
    best = {c: min(results[c]) for c in results}
    print(f"| cores | wall s (best of {args.rounds}) | runs' CPU s | wall / (CPU / cores) |")
    print("|---|---|---|---|")
    for c in (1, 2):
        wall, cpu = best[c]
        print(f"| {c} | {wall:.3f} | {cpu:.3f} | {wall / (cpu / c):.3f} |")
    print(f"\ntwo cores against one: {best[1][0] / best[2][0]:.2f}× "
          f"(per round: {', '.join(f'{a[0] / b[0]:.2f}' for a, b in zip(results[1], results[2]))})")


if __name__ == "__main__":
    main()
