"""nhlab in Python: the long-time behaviour of nonholonomic integrators (Modin & Verdier).

The functions mirror nhlab's HTTP API (docs/api.md) name for name, default for default, and
run the same Rust code in this process: `systems()`, `simulate(...)`, `scorecard(...)`,
`work_precision(...)` and `sweep(...)` (on a Dask cluster with `client=`). Series come back as
numpy float64 arrays (null values of a diverging run as NaN); bad input raises `InputError`
(a `ValueError`) with the message and the field's `path` that the HTTP API's 4xx gives. The
interpreter's lock is released while nhlab computes: threads run in parallel.

    import nhlab
    r = nhlab.simulate("knife_edge", preset="paper")
    for run in r.runs:
        print(run.label, run.series["energy"].verdict["kind"], run.series["energy"].max.max())

A method written in Python (a subclass of `nhlab.Method`, docs/own-methods.md) may stand
wherever these functions take a method: nhlab runs its step and measures it as its own.
"""

import json as _json

from . import _nhlab
from ._own import Method, NewtonError, Registered as _Registered, newton
from ._own import card_warnings as _card_warnings
from ._own import warn_unless_symmetric as _warn_unless_symmetric

__version__ = _nhlab.__version__
__all__ = [
    "InputError", "ServerBusy", "Simulation", "Run", "Series", "SweepRows", "Method",
    "NewtonError", "newton",
    "systems", "simulate", "scorecard", "work_precision", "sweep",
]


class InputError(ValueError):
    """A request nhlab refuses: `message` says why, `path` names the field (as the HTTP API's
    400 and 422 answers do), `status` is the HTTP status it would have had."""

    def __init__(self, message, path=None, status=422):
        super().__init__(f"{path}: {message}" if path else message)
        self.message, self.path, self.status = message, path, status

    def __reduce__(self):
        # Raised in a Dask worker or a process pool, it arrives with its fields.
        return (InputError, (self.message, self.path, self.status))


class ServerBusy(RuntimeError):
    """Every simulation slot is taken (the HTTP API's 503): retry in a moment."""


def _call(method, path, body=None, accept=None):
    text = None if body is None else _json.dumps(body, allow_nan=False)
    status, kind, answer = _nhlab.request(method, path, text, accept)
    if status == 200:
        return answer
    try:
        error = _json.loads(answer)
    except ValueError:
        error = {"error": answer, "path": None}
    if 400 <= status < 500:
        raise InputError(error.get("error"), error.get("path"), status)
    if status == 503:
        raise ServerBusy(error.get("error"))
    raise RuntimeError(f"nhlab: {status}: {error.get('error')}")


def _post(path, body):
    return _json.loads(_call("POST", path, body))


def _floats(xs):
    return None if xs is None else [float(x) for x in xs]


def _scene(system, preset, params, q, v, step, t_end, integrals):
    """A scene as the HTTP API takes it, leaving out what is not given."""
    body = {"system": system, "preset": preset,
            "params": None if params is None else {k: float(x) for k, x in params.items()},
            "q": _floats(q), "v": _floats(v),
            "step": None if step is None else float(step),
            "t_end": None if t_end is None else float(t_end),
            "integrals": None if integrals is None else list(integrals)}
    return {k: x for k, x in body.items() if x is not None}


def systems():
    """`GET /systems`: systems (parameters, integrals, presets, formula forms), methods,
    compositions, the paper's scenes and the limits, as a dict."""
    return _json.loads(_call("GET", "/systems"))


class Series:
    """One integral's error |I(t) − I(0)|, downsampled into buckets: `t` (the time of each
    bucket's last sample), `mean` and `max` over it, numpy float64 arrays; `verdict` is
    exact / bounded / drift with its numbers (a dict, None for an empty series); `gap` says
    from when and why the series has no values although the run went on (a dict with
    `since`, `reason`, `message`; None for a series without one)."""

    def __init__(self, data):
        import numpy as np

        nan = float("nan")
        col = lambda k: np.array([nan if x is None else x for x in data.get(k, [])], dtype=np.float64)
        self.t, self.mean, self.max = col("t"), col("mean"), col("max")
        self.verdict = data.get("verdict")
        self.gap = data.get("gap")

    def __repr__(self):
        kind = (self.verdict or {}).get("kind")
        return f"Series({len(self.t)} buckets, {kind})"


def _column(values):
    import numpy as np

    return np.array([float("nan") if x is None else x for x in values], dtype=np.float64)


class Run:
    """One method's run: `method` (its id and parameters, a dict), `label`, `status` ("ok" or
    "failed"), `error`, `steps`, `elapsed_ms`, `cpu_ms`, `series` by integral id, and
    `observables` where asked for: {"t": times, name: values, ...}, numpy float64 arrays in
    the order asked for (None otherwise), and `section` likewise: {"t": crossing times,
    quantity: values at the crossings, ...} (None unless a section was asked for)."""

    def __init__(self, data):
        self.method = data["method"]
        self.label = data["method"]["label"]
        self.status, self.error, self.steps = data["status"], data["error"], data["steps"]
        self.elapsed_ms, self.cpu_ms = data["elapsed_ms"], data["cpu_ms"]
        self.series = {k: Series(s) for k, s in data["series"].items()}
        observed = data.get("observables")
        self.observables = None if observed is None else {
            k: _column(v) for k, v in observed.items()}
        crossed = data.get("section")
        self.section = None if crossed is None else {k: _column(v) for k, v in crossed.items()}

    def __repr__(self):
        return f"Run({self.label}, {self.status}, {self.steps} steps)"


class Simulation:
    """`simulate`'s answer: the resolved `scene` (a dict: every value after presets and
    defaults; send it back to reproduce the runs), one `Run` per method, in order, and
    `warnings` (a list of strings: a method written in Python that declares itself
    symmetric and is not)."""

    def __init__(self, data, warnings=()):
        self.scene = data["scene"]
        self.runs = [Run(r) for r in data["runs"]]
        self.warnings = list(warnings)

    def run(self, label):
        """The run of the method labelled `label` (e.g. "LF", "DLA^0.4")."""
        for r in self.runs:
            if r.label == label:
                return r
        raise KeyError(f"no run labelled {label!r}; labels: {[r.label for r in self.runs]}")

    def __repr__(self):
        return f"Simulation({self.scene.get('system')}, runs={[r.label for r in self.runs]})"


def simulate(system, preset=None, params=None, q=None, v=None, step=None, t_end=None,
             methods=None, integrals=None, points=None, observables=None, section=None):
    """`POST /simulate`: runs `methods` (default: the paper's five; each an id such as
    "leapfrog" or a dict {"id": "dla", "alpha": 0.4, "composition": "p4s3"}) on a scene of
    `system` (an id, or a system given as formulas, a dict) and measures each integral's
    error. `preset` fills params, q, v, step and t_end; the others override it; `points` is
    the buckets per series (default 1000). `observables` ({"speed": "x_dot*cos(theta)"}:
    formulas in the coordinates, their velocities `x_dot`, `t` and the parameters) are
    sampled at `points` times along each run, as `Run.observables`. `section` ({"surface":
    "sin(zeta/2)", "direction": "both", "plot": ["x1", "x2"]}) records each run's crossings
    of a Poincaré section, as `Run.section`. Returns a `Simulation`."""
    body = _scene(system, preset, params, q, v, step, t_end, integrals)
    if points is not None:
        body["points"] = int(points)
    if observables is not None:
        body["observables"] = {str(k): str(f) for k, f in dict(observables).items()}
    if section is not None:
        body["section"] = dict(section)
    with _Registered() as own:
        if methods is not None:
            body["methods"] = own.request(methods)
        data = _json.loads(_call("POST", "/simulate", body))
        warned = _warn_unless_symmetric(own, data["scene"], _post)
        return Simulation(own.answer(data), warned)


def scorecard(methods=None, scenes=None, points=None):
    """`POST /scorecard`: the verdict of every method (default: all) on every scene (default:
    the paper's six; each a dict like a `simulate` scene) per integral, and each method's
    measured reversibility and fibration preservation. Returns the answer as a dict; with
    methods written in Python, its `warnings` name those that declare themselves symmetric
    and were measured not to be."""
    body = {}
    if scenes is not None:
        body["scenes"] = list(scenes)
    if points is not None:
        body["points"] = int(points)
    with _Registered() as own:
        if methods is not None:
            body["methods"] = own.request(methods)
        card = _json.loads(_call("POST", "/scorecard", body))
        if own.methods:
            card["warnings"] = _card_warnings(own, card)
        return own.answer(card)


def work_precision(system, preset=None, params=None, q=None, v=None, step=None, t_end=None,
                   methods=None, integrals=None, steps=None, levels=None, repeats=None,
                   observables=None):
    """`POST /work-precision`: each method's final error against a Dop853 reference and its
    run time, at step sizes `steps` (a list) or h, h/2, … (`levels`, default 4), the fastest
    of `repeats` (default 3). `observables` (formulas by name, as for `simulate`) are taken
    at t_end for each row and the reference. Returns the answer as a dict (rows per method ×
    step; with methods written in Python, `warnings` as `Simulation.warnings`)."""
    body = _scene(system, preset, params, q, v, step, t_end, integrals)
    if steps is not None:
        body["steps"] = _floats(steps)
    if levels is not None:
        body["levels"] = int(levels)
    if observables is not None:
        body["observables"] = {str(k): str(f) for k, f in dict(observables).items()}
    if repeats is not None:
        body["repeats"] = int(repeats)
    with _Registered() as own:
        if methods is not None:
            body["methods"] = own.request(methods)
        answer = _json.loads(_call("POST", "/work-precision", body))
        if own.methods:
            answer["warnings"] = _warn_unless_symmetric(own, answer["scene"], _post)
        return own.answer(answer)


class SweepRows(list):
    """`sweep`'s rows (a list of dicts, by cell then method, as `POST /sweep` gives them),
    `head`: the axes with their values, the methods, the integrals, the cell count, and
    `warnings` (a list of strings: methods written in Python that declare themselves
    symmetric and are not, measured on the scene of the first cell that ran)."""

    def __init__(self, rows, head, warnings=()):
        super().__init__(rows)
        self.head = head
        self.warnings = list(warnings)

    def to_json(self, path=None):
        """The sweep as `POST /sweep`'s JSON answer (the head's fields and `rows`), as text,
        also written to `path` if given: the page's Map view opens it (methods written in
        Python included)."""
        text = _json.dumps({**self.head, "rows": list(self)}, allow_nan=False)
        if path is not None:
            with open(path, "w") as f:
                f.write(text)
        return text

    def to_pandas(self):
        """The rows as a tidy pandas DataFrame: a column per axis path, the method's label,
        status, error, steps, cpu_ms, newton_iterations, and `<integral>.kind`, `.max`,
        `.early`, `.late`, `.ratio`, `.gap_since` per integral, and `observables.<name>` per
        observable taken at t_end, as the CSV of `POST /sweep` (`gap_since` is NaN for a series
        with values to the end, an observable NaN for a run that failed; pandas must be
        installed)."""
        import pandas as pd

        paths = [a["path"] for a in self.head["axes"]]
        records = []
        for r in self:
            rec = {"cell": r["cell"], **dict(zip(paths, r["values"])),
                   "method_index": r["method_index"], "method": r["method"]["label"]}
            for k in ("status", "error", "steps", "cpu_ms", "newton_iterations"):
                rec[k] = r[k]
            for i in self.head["integrals"]:
                for f in ("kind", "max", "early", "late", "ratio"):
                    rec[f"{i}.{f}"] = r["verdicts"].get(i, {}).get(f)
                rec[f"{i}.gap_since"] = (r.get("gaps") or {}).get(i, {}).get("since", float("nan"))
            for name in self.head.get("observables", []):
                value = (r.get("observables") or {}).get(name)
                rec[f"observables.{name}"] = float("nan") if value is None else value
            records.append(rec)
        return pd.DataFrame.from_records(records)


def sweep(spec=None, *, client=None, shards=None, **scene):
    """`POST /sweep`: every method on every cell of 1 to 3 `axes` (each {"path":
    "params.epsilon", "values": [...]} or "linspace"/"logspace": [start, stop, n]), a row per
    cell × method with its status, cost and verdicts. `spec` is the request as a dict; or give
    its fields as keywords (`sweep(system="knife_edge", axes=[...])`).

    A method written in Python (`nhlab.Method`) may be among the methods, and an axis may
    take one of its `parameters` (`{"path": "methods[0].theta", "values": [...]}`; one axis
    per such method).

    With `client=` (a `dask.distributed.Client`), the sweep runs as `shards` Dask tasks
    (default: 4 per worker), each computing the cells c with c mod shards = i; the rows are
    the same as without. A worker lost mid-sweep has its tasks retried elsewhere."""
    spec = dict(spec or {}, **scene)
    with _Registered() as own:
        spec, axes = _own_axes(own, spec)
        if client is None:
            head = _json.loads(_call("POST", "/sweep", spec))
            rows = head.pop("rows")
        else:
            from . import _dask

            head, rows = _dask.sweep(spec, client, shards, own.methods)
        head, rows = _own_values(own, axes, head, rows)
        first = next((r["simulate"] for r in rows if r.get("status") == "ok"), None)
        warned = _warn_unless_symmetric(own, first, _post) if first else []
        return SweepRows(own.answer(rows), own.answer(head), warned)


def _own_axes(own, spec):
    """`spec` with its methods written in Python named by handle, and each axis over one of
    their parameters turned into an axis over handles of copies with those values; and
    those axes: {axis index: (path, parameter values)}."""
    import re

    methods = spec.get("methods")
    if methods is None or not any(isinstance(m, Method) or (isinstance(m, dict) and isinstance(
            m.get("id"), Method)) for m in methods):
        return spec, {}
    spec = dict(spec)
    objects = [m if isinstance(m, Method) else m.get("id") if isinstance(m, dict) else None
               for m in methods]
    spec["methods"] = own.request(methods)
    axes, taken = {}, set()
    for k, axis in enumerate(spec.get("axes") or []):
        path = axis.get("path", "") if isinstance(axis, dict) else ""
        found = re.fullmatch(r"methods\[(\d+)\]\.(\w+)", path)
        if not found or int(found[1]) >= len(objects) or not isinstance(
                objects[int(found[1])], Method):
            continue
        i, name = int(found[1]), found[2]
        method = objects[i]
        if i in taken:
            raise InputError(f"{method.label()} may be swept along one axis only", f"axes[{k}]")
        if name not in method.parameters:
            raise InputError(f"{method.label()} has no parameter '{name}'; its parameters: "
                             f"{list(method.parameters)}", f"axes[{k}].path")
        values = _axis_values(axis, k)
        handles = [own.handle(method.with_params(**{name: x})) for x in values]
        # The method as listed never runs with its own value: only its copies are measured.
        own.replaced.add(own.handle(method))
        spec["axes"] = [dict(a) for a in spec["axes"]]
        spec["axes"][k] = {"path": f"methods[{i}].handle", "values": handles}
        axes[k] = (path, values)
        taken.add(i)
    return spec, axes


def _axis_values(axis, k):
    """An axis's values as the core computes them for `POST /sweep`, checks included."""
    try:
        return _nhlab.axis_values(_json.dumps(axis, allow_nan=False), k)
    except ValueError as e:
        message, path = e.args if len(e.args) == 2 else (str(e), f"axes[{k}]")
        raise InputError(message, path) from None


def _own_values(own, axes, head, rows):
    """The head and rows of a sweep whose `axes` (from `_own_axes`) ran over handles, with
    the parameters' paths and values back in place of the handles."""
    if not axes:
        return head, rows
    head = dict(head)
    head["axes"] = [dict(a) for a in head["axes"]]
    by_handle = {}
    for k, (path, values) in axes.items():
        by_handle[k] = {int(h): x for h, x in zip(head["axes"][k]["values"], values)}
        head["axes"][k]["path"], head["axes"][k]["values"] = path, values
    out = []
    for r in rows:
        r = dict(r)
        r["values"] = [by_handle[k][int(x)] if k in by_handle else x
                       for k, x in enumerate(r["values"])]
        out.append(r)
    return head, out
