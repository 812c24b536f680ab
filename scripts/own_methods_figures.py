#!/usr/bin/env python3
"""Draws the figures of docs/own-methods.md: the docs' two methods written in Python
(nhlab.examples) through simulate, work–precision and a map, as SVG (standard library and
the nhlab package; the map drawn as scripts/maps.py draws the page's presets).

    pip install ./python            # or a release build of the package on PYTHONPATH
    python3 scripts/own_methods_figures.py docs/own-methods
"""

import importlib.util
import math
import os
import sys
import warnings

import nhlab
from nhlab.examples import Leapfrog, ProjectedVerlet

COLOURS = ["#2563eb", "#ea580c", "#16a34a", "#9333ea"]
W, H, LEFT, TOP, RIGHT, BOTTOM = 560, 340, 64, 36, 150, 44


def maps_module():
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "maps.py")
    spec = importlib.util.spec_from_file_location("maps", here)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def decades(lo, hi):
    return range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1)


def loglog(title, lines, xlabel, ylabel):
    """An SVG of `lines` [(label, xs, ys)] on log–log axes, with a decade grid."""
    pts = [(x, y) for _, xs, ys in lines for x, y in zip(xs, ys) if x > 0 and y and y > 0]
    xd = decades(min(p[0] for p in pts), max(p[0] for p in pts))
    yd = decades(min(p[1] for p in pts), max(p[1] for p in pts))
    pw, ph = W - LEFT - RIGHT, H - TOP - BOTTOM
    sx = lambda x: LEFT + (math.log10(x) - xd[0]) / (xd[-1] - xd[0]) * pw
    sy = lambda y: TOP + ph - (math.log10(y) - yd[0]) / (yd[-1] - yd[0]) * ph
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
           'font-family="sans-serif" font-size="11">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<text x="{LEFT}" y="18" font-size="13" font-weight="bold">{title}</text>']
    for d in xd:
        out.append(f'<line x1="{sx(10**d)}" y1="{TOP}" x2="{sx(10**d)}" y2="{TOP + ph}" stroke="#e5e7eb"/>')
        out.append(f'<text x="{sx(10**d)}" y="{TOP + ph + 14}" text-anchor="middle">1e{d}</text>')
    for d in yd:
        out.append(f'<line x1="{LEFT}" y1="{sy(10**d)}" x2="{LEFT + pw}" y2="{sy(10**d)}" stroke="#e5e7eb"/>')
        out.append(f'<text x="{LEFT - 6}" y="{sy(10**d) + 4}" text-anchor="end">1e{d}</text>')
    out.append(f'<text x="{LEFT + pw / 2}" y="{H - 8}" text-anchor="middle">{xlabel}</text>')
    out.append(f'<text x="14" y="{TOP + ph / 2}" transform="rotate(-90 14 {TOP + ph / 2})" '
               f'text-anchor="middle">{ylabel}</text>')
    for k, (label, xs, ys) in enumerate(lines):
        colour = COLOURS[k % len(COLOURS)]
        path = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in zip(xs, ys) if x > 0 and y and y > 0)
        dash = ' stroke-dasharray="5 3"' if k % 2 else ""
        out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="1.6"{dash}/>')
        out.append(f'<line x1="{W - RIGHT + 12}" y1="{TOP + 12 + 18 * k}" x2="{W - RIGHT + 36}" '
                   f'y2="{TOP + 12 + 18 * k}" stroke="{colour}" stroke-width="2"{dash}/>')
        out.append(f'<text x="{W - RIGHT + 42}" y="{TOP + 16 + 18 * k}">{label}</text>')
    out.append("</svg>")
    return "\n".join(out)


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    warnings.simplefilter("ignore")
    methods = ["leapfrog", Leapfrog(), ProjectedVerlet()]
    r = nhlab.simulate("knife_edge", preset="paper-perturbed", methods=methods, points=200)
    lines = [(run.label, run.series["energy"].t, run.series["energy"].max) for run in r.runs]
    svg = loglog("Energy error, perturbed knife edge (h = π/10)", lines, "t", "|H − H(0)|")
    write(out, "energy.svg", svg)

    wp = nhlab.work_precision("knife_edge", preset="paper", t_end=10, levels=6, repeats=1,
                              methods=methods)
    lines = []
    for label in ("LF", "my LF", "projected Verlet"):
        rows = [x for x in wp["rows"] if x["method"]["label"] == label]
        lines.append((label, [x["step"] for x in rows], [x["final_error"] for x in rows]))
    svg = loglog("Error at t = 10 against the step, knife edge", lines, "h", "error in (q, q̇)")
    write(out, "order.svg", svg)

    rows = nhlab.sweep({"system": "cvt_pendulum", "preset": "rotating-perturbed", "t_end": 300,
                        "points": 50, "methods": [ProjectedVerlet(), "leapfrog"],
                        "integrals": ["energy", "constraint"],
                        "axes": [{"path": "methods[0].damping", "linspace": [0, 1, 9]},
                                 {"path": "params.epsilon", "linspace": [0, 0.5, 6]}]})
    answer = {**rows.head, "rows": list(rows)}
    maps = maps_module()
    for integral in ("energy", "constraint"):
        svg = maps.draw(answer, integral, f"Projected Verlet: damping × ε, {integral}")
        write(out, f"map-{integral}.svg", svg)


def write(out, name, svg):
    with open(os.path.join(out, name), "w") as f:
        f.write(svg + "\n")
    print(name, file=sys.stderr)


if __name__ == "__main__":
    main()
