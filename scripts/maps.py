#!/usr/bin/env python3
"""Draws the page's preset maps as SVG pictures for docs/maps.md.

Each preset of web/src/map/presets.json (the page's Map view offers the same) is computed
with `nhlab sweep` (no server; every core) and drawn as one heat map per method: the verdict
of the preset's integral in each cell, x = the last axis, y = the first, a letter per cell so
that the picture reads without colour. Only the standard library is needed.

    cargo build --release -p nhlab-server
    python3 scripts/maps.py target/release/nhlab docs/maps
"""

import json
import math
import os
import subprocess
import sys
import tempfile

COLOURS = {"exact": "#2563eb", "bounded": "#16a34a", "drift": "#ea580c"}
LETTERS = {"exact": "E", "bounded": "B", "drift": "D", "failed": "✕", "invalid": "⊘"}
CELL, GAP, LEFT, TOP = 22, 28, 70, 40


def sweep(nhlab, spec):
    """POST /sweep's JSON answer for `spec`, computed by `nhlab sweep` and merged."""
    with tempfile.TemporaryDirectory() as d:
        path, rows = os.path.join(d, "spec.json"), os.path.join(d, "rows.jsonl")
        with open(path, "w") as f:
            json.dump(spec, f)
        subprocess.run([nhlab, "sweep", path, "--out", rows], check=True)
        merged = subprocess.run([nhlab, "sweep", "--merge", rows], check=True, capture_output=True)
        return json.loads(merged.stdout)


def label(x):
    return f"{x:.3g}"


def draw(answer, integral, title):
    """One panel per method: a cell per (first axis value, last axis value)."""
    axes = answer["axes"]
    ys, xs = axes[0]["values"], axes[-1]["values"]
    methods = answer["methods"]
    width_panel = len(xs) * CELL
    width = LEFT + len(methods) * (width_panel + GAP) + 10
    height = TOP + len(ys) * CELL + 60
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height + 24}" '
        f'font-family="sans-serif" font-size="11">',
        '<defs><pattern id="hatch" width="4" height="4" patternUnits="userSpaceOnUse">'
        '<path d="M0 4L4 0" stroke="#999"/></pattern></defs>',
        f'<rect width="100%" height="100%" fill="white"/>',
        f'<text x="{LEFT}" y="16" font-size="13" font-weight="bold">{title}</text>',
    ]
    cells = {}
    for row in answer["rows"]:
        cells[(row["cell"], row["method_index"])] = row
    for m, method in enumerate(methods):
        x0 = LEFT + m * (width_panel + GAP)
        own = ("methods", "methods.", f"methods[{m}].")
        swept = [a["path"] for a in axes if a["path"] == "methods" or a["path"].startswith(own[1:])]
        # A method axis changes the method cell by cell: name it by its id (a method written
        # in Python by its name) and the axis.
        name = f'{method.get("name", method["id"])}, {swept[0]} swept' if swept else method["label"]
        out.append(f'<text x="{x0 + width_panel / 2}" y="{TOP - 8}" text-anchor="middle" font-weight="bold">{name}</text>')
        for i, y in enumerate(ys):
            for j, x in enumerate(xs):
                row = cells[(i * len(xs) + j, m)]
                if row["status"] == "ok":
                    kind = row["verdicts"].get(integral, {}).get("kind", "invalid")
                else:
                    kind = row["status"]
                fill = COLOURS.get(kind, "url(#hatch)" if kind == "invalid" else "#9ca3af")
                px, py = x0 + j * CELL, TOP + i * CELL
                tip = f"{axes[0]['path']} = {label(y)}, {axes[-1]['path']} = {label(x)}: {row['method']['label']} {kind}"
                out.append(
                    f'<rect x="{px}" y="{py}" width="{CELL - 1}" height="{CELL - 1}" fill="{fill}">'
                    f"<title>{tip}</title></rect>"
                )
                out.append(
                    f'<text x="{px + CELL / 2 - 0.5}" y="{py + CELL / 2 + 4}" text-anchor="middle" '
                    f'fill="white">{LETTERS.get(kind, "?")}</text>'
                )
        for j, x in enumerate(xs):
            if j % max(1, len(xs) // 6) == 0 or j == len(xs) - 1:
                px = x0 + j * CELL + CELL / 2
                out.append(f'<text x="{px}" y="{TOP + len(ys) * CELL + 14}" text-anchor="middle">{label(x)}</text>')
        out.append(
            f'<text x="{x0 + width_panel / 2}" y="{TOP + len(ys) * CELL + 30}" text-anchor="middle">{axes[-1]["path"]}</text>'
        )
    for i, y in enumerate(ys):
        if i % max(1, len(ys) // 10) == 0 or i == len(ys) - 1:
            out.append(f'<text x="{LEFT - 6}" y="{TOP + i * CELL + CELL / 2 + 4}" text-anchor="end">{label(y)}</text>')
    out.append(
        f'<text x="14" y="{TOP + len(ys) * CELL / 2}" transform="rotate(-90 14 {TOP + len(ys) * CELL / 2})" '
        f'text-anchor="middle">{axes[0]["path"]}</text>'
    )
    legend = "E exact · B bounded · D drift · ✕ failed · ⊘ invalid"
    out.append(f'<text x="{LEFT}" y="{height + 14}">{legend} (verdict of {integral})</text>')
    out.append("</svg>")
    return "\n".join(out)


def main():
    nhlab, out_dir = sys.argv[1], sys.argv[2]
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with open(os.path.join(root, "web", "src", "map", "presets.json")) as f:
        presets = json.load(f)
    for preset in presets:
        spec = dict(preset["scene"], axes=preset["axes"])
        answer = sweep(nhlab, spec)
        svg = draw(answer, preset["integral"], preset["label"])
        with open(os.path.join(out_dir, preset["id"] + ".svg"), "w") as f:
            f.write(svg)
        print(f"{preset['id']}: {answer['cells']} cells, {len(answer['rows'])} rows", file=sys.stderr)


if __name__ == "__main__":
    main()
