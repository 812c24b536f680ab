#!/usr/bin/env python3
"""What a SPARK step costs against DLA^½'s on the same system (target: at most 1.5(s − 1) DLA^½
steps, docs/high-order.md): `step_loop` runs of DLA^½ (its fastest path, and its general-class
step `as-general` on a class system) and of SPARK with s = 2 … 5, each run a process of its
own, interleaved over the rounds; per side the median CPU ns/step, and SPARK's ratio to DLA^½'s.

    cargo build --release -p nhlab-core --example step_loop
    python3 bench/spark_cost.py [--steps 2000000] [--rounds 5]
"""

import argparse
import statistics

from formula_ratio import cpu_seconds

SCENES = [("chaplygin_sleigh", "1"), ("knife_edge", "0"), ("cvt_pendulum", "1")]
SIDES = [("DLA^½", "0", "fast"), ("DLA^½ general", "0", "as-general")] + [
    (f"SPARK{s}", f"spark:stages={s}", "fast") for s in range(2, 6)
]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", type=int, default=2_000_000)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--restart", type=int, default=1000)
    a = p.parse_args()
    print("| scene | " + " | ".join(name for name, *_ in SIDES) + " |")
    print("|---|" + "---|" * len(SIDES))
    for system, preset in SCENES:
        # The sleigh is no class system: its DLA^½ has one path.
        sides = [s for s in SIDES if not (system == "chaplygin_sleigh" and s[2] == "as-general")]
        times = {name: [] for name, *_ in sides}
        for _ in range(a.rounds):
            for name, method, path in sides:
                args = [system, method, path, str(a.steps), preset, str(a.restart)]
                times[name].append(cpu_seconds(args) / a.steps * 1e9)
        ns = {name: statistics.median(t) for name, t in times.items()}
        cells = []
        for name, *_ in SIDES:
            if name not in ns:
                cells.append("–")
            elif name.startswith("SPARK"):
                s = int(name[5:])
                cells.append(f"{ns[name]:.0f} ({ns[name] / ns['DLA^½']:.2f}×, target {1.5 * (s - 1):.1f}×)")
            else:
                cells.append(f"{ns[name]:.0f}")
        print(f"| {system} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
