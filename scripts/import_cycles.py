#!/usr/bin/env python3
"""Fails if the modules of a crate import each other in a circle, or if a crate's wings (its
top-level modules) import against their order.

Each `.rs` file under SRC is a module; an edge A → B is a path `crate::…`, `super::…` or
`self::…` in A (in a `use` or inline) that names B or an item of B. Items re-exported by
`pub use` (at the crate root or in a folder's module file) count as edges to the module
that defines them. `mod` declarations are not edges, nor is code under `#[cfg(test)]`.

The wings of each crate are layered (LAYERS, lowest first; docs/architecture.md says why):
a module may import from its own wing and from the layers below, never from above. In the
core: model → solver → methods → measure → catalogue, on the leaves formula, error, linalg.

    python3 scripts/import_cycles.py core/src server/src
"""

import os
import re
import sys


def modules(src):
    """Module path (tuple) → file, for every .rs file under src."""
    out = {}
    for dirpath, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs"):
                continue
            rel = os.path.relpath(os.path.join(dirpath, f), src)[:-3].split(os.sep)
            if rel in (["lib"], ["main"]):
                rel = []
            elif rel[-1] == "mod":
                rel = rel[:-1]
            out[tuple(rel)] = os.path.join(dirpath, f)
    return out


def code(path):
    text = open(path).read()
    cut = text.find("#[cfg(test)]")
    text = text if cut < 0 else text[:cut]
    return "\n".join(l.split("//")[0] for l in text.splitlines())


PATH = re.compile(r"\b(crate|super|self)((?:::[A-Za-z_][A-Za-z0-9_]*)+)")
GROUP = re.compile(r"\b(crate|super|self)((?:::[A-Za-z_][A-Za-z0-9_]*)*)::\{([^{}]*)\}")


def paths(mod, text):
    """Absolute paths (tuples) named in a module's code."""
    found = []

    def absolute(head, rest):
        base = {"crate": (), "super": mod[:-1], "self": mod}[head]
        return base + tuple(p for p in rest.split("::") if p)

    for m in GROUP.finditer(text):
        base = absolute(m.group(1), m.group(2))
        for item in m.group(3).split(","):
            item = item.strip().split(" as ")[0].strip()
            if item and item != "self":
                found.append(base + tuple(item.split("::")))
            elif item == "self":
                found.append(base)
    for m in PATH.finditer(GROUP.sub("", text)):
        found.append(absolute(m.group(1), m.group(2)))
    return found


def reexports(mods):
    """(module, name) → the absolute path a `pub use` there points to."""
    out = {}
    for mod, f in mods.items():
        text = code(f)
        for m in re.finditer(r"pub use ([^;]+);", text):
            body = m.group(1).replace("\n", " ")
            for p in paths(mod, body if body.startswith(("crate", "super", "self")) else "self::" + body):
                out[(mod, p[-1])] = p
    return out


def resolve(path, mods, re_exports, depth=0):
    """The module that defines what `path` names."""
    for k in range(len(path), -1, -1):
        prefix = path[:k]
        if prefix in mods:
            if k < len(path) and (prefix, path[k]) in re_exports and depth < 8:
                return resolve(re_exports[(prefix, path[k])], mods, re_exports, depth + 1)
            return prefix
    return None


def cycles(src):
    mods = modules(src)
    re_exports = reexports(mods)
    edges = {m: set() for m in mods}
    for mod, f in mods.items():
        for p in paths(mod, code(f)):
            target = resolve(p, mods, re_exports)
            if target is not None and target != mod and target != ():
                edges[mod].add(target)
    found, state = [], {}

    def visit(m, stack):
        state[m] = 1
        stack.append(m)
        for n in sorted(edges[m]):
            if state.get(n) == 1:
                found.append(stack[stack.index(n):] + [n])
            elif n not in state:
                visit(n, stack)
        stack.pop()
        state[m] = 2

    for m in sorted(mods):
        if m not in state:
            visit(m, [])
    return found


# The wings of each crate, lowest layer first.
LAYERS = {
    "core/src": [
        ["formula"],
        ["error", "linalg"],
        ["model"],
        ["solver"],
        ["methods"],
        ["measure"],
        ["catalogue"],
    ],
    "server/src": [
        ["config", "error"],
        ["request"],
        ["views"],
        ["compute"],
        ["state", "observers"],
        ["json_object", "serve"],
        ["sweep"],
        ["routes"],
        ["openapi"],
    ],
}


def against_the_order(src):
    """The edges from a wing to a wing of a higher layer, and the wings LAYERS lacks."""
    layers = next((l for k, l in LAYERS.items() if src.rstrip("/").endswith(k)), None)
    if layers is None:
        return [], []
    rank = {wing: i for i, layer in enumerate(layers) for wing in layer}
    mods = modules(src)
    re_exports = reexports(mods)
    bad, unknown = [], sorted({m[0] for m in mods if m and m[0] not in rank and m[0] != "main"})
    for mod, f in mods.items():
        if not mod or mod[0] not in rank:
            continue
        for p in paths(mod, code(f)):
            target = resolve(p, mods, re_exports)
            if target and target[0] in rank and rank[target[0]] > rank[mod[0]]:
                bad.append((mod, target))
    return sorted(set(bad)), unknown


def main():
    bad = False
    for src in sys.argv[1:]:
        for c in cycles(src):
            bad = True
            print(f"{src}: " + " → ".join("::".join(m) or "crate" for m in c))
        edges, unknown = against_the_order(src)
        for a, b in edges:
            bad = True
            print(f"{src}: {'::'.join(a)} → {'::'.join(b)} imports against the wings' order")
        for wing in unknown:
            bad = True
            print(f"{src}: the wing `{wing}` is in no layer of LAYERS")
    if bad:
        sys.exit(1)
    print("no import cycles, and the wings in order, in " + ", ".join(sys.argv[1:]))


if __name__ == "__main__":
    main()
