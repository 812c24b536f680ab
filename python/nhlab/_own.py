"""Methods written in Python (docs/own-methods.md): `Method`, the base class of a
researcher's integrator; `newton`, the solve an implicit step usually needs; and how a
request carries such methods. Each `Method` object among a call's methods is registered with
nhlab's core for the duration of the call and named in the request by its handle
(`{"id": "python", "handle": k}`); the answer names it back by its name and parameters."""

import copy
import warnings

from . import _nhlab


class Method:
    """A one-step method for nonholonomic systems, written in Python. Subclass it and write
    `step`; nhlab runs the loop and measures it as it measures its own methods.

    - `name`: its label in tables and plots (default: the class's name);
    - `order`: the order you claim (work–precision measures it);
    - `symmetric`: declare True to let nhlab compose it (p4s3 ... p8s15); the scorecard
      measures whether it is, and an answer warns where it is not;
    - `parameters`: names of numeric attributes that a sweep may take as an axis
      (`methods[0].theta`).

    `step(system, q, v, h, memory)` returns the state one step h later, `(q1, v1)`.
    `system` gives M, V, A and their derivatives as calls on numpy arrays (`system.M()`,
    `system.grad_V(q)`, `system.A(q)`, `system.jac_Av(q, v)`, ...), the paper's pieces for a
    system of its class (`system.U`, `system.V_d`, `system.A_x`, `system.zeta_index`), its
    energy and invariants (`system.energy(q, v)`, `system.invariants(q, v)`, a dict by
    name), and the helpers `system.multiplier(q, v)`, `system.project(q, v)` and
    `system.newton(residual, jacobian, x0)`. `memory` is a dict the step may keep things in
    between steps of one run: a shallow copy of what the step before left (so replace its
    values rather than change them in place), empty when the step starts from another
    configuration q than the last step returned (a velocity flipped from outside keeps it,
    as it keeps the built-ins' λ)."""

    name = None
    order = 1
    symmetric = False
    parameters = ()

    def step(self, system, q, v, h, memory):
        raise NotImplementedError("a Method subclass writes step(system, q, v, h, memory)")

    def label(self):
        """Its label: `name`, else the class's name."""
        return self.name if self.name is not None else type(self).__name__

    def params(self):
        """Its parameters' values by name."""
        return {p: float(getattr(self, p)) for p in self.parameters}

    def composed(self, composition):
        """The method taken in a symmetric composition (e.g. "p4s3"), for `methods=[...]`."""
        return {"id": self, "composition": composition}

    def with_params(self, **values):
        """A copy with other parameter values (what a sweep's axis does)."""
        unknown = sorted(set(values) - set(self.parameters))
        if unknown:
            raise ValueError(f"{self.label()} has no parameter {unknown[0]!r}; "
                             f"its parameters: {list(self.parameters)}")
        other = copy.copy(self)
        for k, x in values.items():
            setattr(other, k, x)
        return other

    def __repr__(self):
        params = ", ".join(f"{k}={x}" for k, x in self.params().items())
        return f"{type(self).__name__}({params})"


class NewtonError(ArithmeticError):
    """`newton` did not converge."""


def newton(residual, jacobian, x0, tol=1e-14, max_iter=50):
    """Newton's method for residual(x) = 0 from x0, with the Jacobian jacobian(x): stops
    when an increment is below tol·max(1, |x|) (max norms); raises `NewtonError` after
    max_iter iterations."""
    import numpy as np

    x = np.array(x0, dtype=np.float64)
    step = np.inf
    for _ in range(int(max_iter)):
        dx = np.linalg.solve(np.asarray(jacobian(x), dtype=np.float64),
                             np.asarray(residual(x), dtype=np.float64))
        x = x - dx
        step = float(np.max(np.abs(dx))) if dx.size else 0.0
        if step <= tol * max(1.0, float(np.max(np.abs(x)))):
            return x
    raise NewtonError(f"Newton did not converge in {max_iter} iterations "
                      f"(last increment {step:.3e})")


def _check(method):
    if not callable(getattr(method, "step", None)):
        raise TypeError(f"{method!r} has no step(system, q, v, h, memory)")
    order = method.order
    if not isinstance(order, int) or isinstance(order, bool) or order < 1:
        raise TypeError(f"{method.label()}: order must be a whole number ≥ 1, got {order!r}")
    for p in method.parameters:
        value = getattr(method, p, None)
        if not isinstance(value, (int, float)) or isinstance(value, bool):
            raise TypeError(f"{method.label()}: parameter {p!r} must be a number, got {value!r}")


class Registered:
    """The `Method` objects of one call, registered for its duration (a context manager)."""

    def __init__(self):
        self.methods = {}
        # Handles of methods a sweep's axis replaced by copies: never run as listed.
        self.replaced = set()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        for handle in self.methods:
            _nhlab.unregister(handle)
        self.methods.clear()

    def handle(self, method):
        """Registers `method` (once per object) and returns its handle."""
        for h, m in self.methods.items():
            if m is method:
                return h
        _check(method)
        h = _nhlab.register(method, str(method.label()), int(method.order),
                            bool(method.symmetric))
        self.methods[h] = method
        return h

    def request(self, methods):
        """A request's `methods` with each `Method` (alone, or as the `id` of a dict) named
        by its handle."""
        if methods is None:
            return None
        out = []
        for i, m in enumerate(methods):
            if isinstance(m, Method):
                m = {"id": m}
            if isinstance(m, dict) and isinstance(m.get("id"), Method):
                m = dict(m)
                obj = m.pop("id")
                # Its parameters given beside it, flat or under "params", as for a built-in.
                given = {**m.pop("params", {}), **{k: m.pop(k) for k in list(m)
                                                   if k != "composition"}}
                if given:
                    from . import InputError

                    unknown = sorted(set(given) - set(obj.parameters))
                    if unknown:
                        raise InputError(f"{obj.label()} has no parameter '{unknown[0]}'; its "
                                         f"parameters: {list(obj.parameters)}",
                                         f"methods[{i}].{unknown[0]}")
                    obj = obj.with_params(**given)
                m = {"id": "python", "handle": self.handle(obj), **m}
            out.append(m)
        return out

    def answer(self, data):
        """`data` (a JSON answer) with each method object that names a handle of this call
        naming the method instead: {"id": "python", "name": ..., its parameters, "label"}."""
        if isinstance(data, list):
            return [self.answer(x) for x in data]
        if not isinstance(data, dict):
            return data
        if data.get("id") == "python" and "handle" in data:
            method = self.methods.get(int(data["handle"]))
            if method is not None:
                data = {k: x for k, x in data.items() if k != "handle"}
                data = {"id": "python", "name": method.label(), **method.params(), **data}
                data.pop("id", None)
                return {"id": "python", **data}
        return {k: self.answer(x) for k, x in data.items()}

    def symmetric(self):
        """The methods of this call that declare themselves symmetric and run, by handle."""
        return {h: m for h, m in self.methods.items() if m.symmetric and h not in self.replaced}


def warn_unless_symmetric(registered, scene, call):
    """For each method of `registered` that declares itself symmetric, measures whether it
    is (the scorecard's symmetry check, on `scene`: one step h then one step −h returns the
    start) and returns a warning for each that is not (also issued with `warnings.warn`).
    `call` posts a request and returns the parsed answer."""
    out = []
    declared = registered.symmetric()
    probe = {k: scene[k] for k in ("system", "params", "q", "v", "step") if k in scene}
    probe["t_end"] = 4 * float(scene["step"])
    system = scene.get("system")
    where = system if isinstance(system, str) else "the system"
    handles = list(declared)
    for first in range(0, len(handles), 8):  # within any server's max_methods
        batch = handles[first:first + 8]
        try:
            card = call("/scorecard", {"methods": [{"id": "python", "handle": h} for h in batch],
                                       "scenes": [probe], "points": 4})
        except Exception as e:  # noqa: BLE001 - the runs are done; say so, do not lose them
            out.append(f"the symmetry of {', '.join(declared[h].label() for h in batch)} "
                       f"could not be checked: {e}")
            warnings.warn(out[-1], stacklevel=3)
            continue
        out += [w for w in card_warnings(registered, card, where, stacklevel=4) if w not in out]
    return out


def card_warnings(registered, card, where=None, stacklevel=3):
    """The warnings of a scorecard answer `card`: each method of `registered` that declares
    itself symmetric and was measured not to be, on `where` (else the scene's id); each
    also issued with `warnings.warn`."""
    out = []
    for p in card.get("properties", []):
        m = p.get("method", {})
        method = registered.methods.get(int(m["handle"])) if m.get("id") == "python" else None
        if method is None or not method.symmetric or p.get("symmetric") is not False:
            continue
        params = ", ".join(f"{k} = {x:g}" for k, x in method.params().items())
        name = f"{method.label()} ({params})" if params else method.label()
        defect = p.get("symmetry_defect")
        text = (f"{name} declares itself symmetric but is not: one step h then one step −h "
                "misses the start" + (f" by {defect:.3e}" if defect is not None else "")
                + f" on {where or p['scene']}; its compositions do not raise its order")
        if text not in out:
            warnings.warn(text, stacklevel=stacklevel)
            out.append(text)
    return out
