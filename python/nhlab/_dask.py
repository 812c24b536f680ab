"""Sweeps on a Dask cluster: the cells are split into shards (cells c with c mod N = i, as
`nhlab sweep --shard i/N` takes them), each a task that computes its rows in the worker's
process with nhlab's Rust code; the rows are joined by cell and method, exactly as
`POST /sweep` orders them. A task's rows depend on its cells alone, so a task retried on
another worker (its first worker lost) gives the same rows.

Methods written in Python travel with the tasks (pickled): in the worker each is registered
under a handle of that process, the spec is rewritten to name them so, and the rows are
written back with the caller's handles."""

import json

from . import InputError, _nhlab


def _shard(text, index, count, methods=None):
    """One shard's (head, rows): run on a worker. `methods`: the methods written in Python,
    by the caller's handles."""
    if not methods:
        return _shard_alone(text, index, count)
    from ._own import Registered

    with Registered() as own:
        there = {old: own.handle(m) for old, m in methods.items()}
        back = {new: old for old, new in there.items()}
        spec = json.loads(text)
        head, rows = _shard_alone(json.dumps(_rehandle(spec, there)), index, count)
        fixed = []
        for text_row in rows:
            row = _rehandle_all(json.loads(text_row), back)
            row["values"] = [back.get(int(x), x) if _handle_axis(spec, k) else x
                             for k, x in enumerate(row["values"])]
            fixed.append(json.dumps(row))
        return head, fixed


def _shard_alone(text, index, count):
    try:
        head, rows = _nhlab.shard(text, index, count, _threads())
    except ValueError as e:
        message, path = e.args if len(e.args) == 2 else (str(e), None)
        raise InputError(message, path) from None
    return head, rows


def _handle_axis(spec, k):
    axes = spec.get("axes") or []
    return k < len(axes) and str(axes[k].get("path", "")).endswith(".handle")


def _rehandle_method(m, mapping):
    if isinstance(m, dict) and m.get("id") == "python" and "handle" in m:
        handle = int(m["handle"])
        return {**m, "handle": type(m["handle"])(mapping.get(handle, handle))}
    return m


def _rehandle_all(data, mapping):
    """`data` (a row) with every method object's handle mapped."""
    if isinstance(data, list):
        return [_rehandle_all(x, mapping) for x in data]
    if isinstance(data, dict):
        data = _rehandle_method(data, mapping)
        return {k: _rehandle_all(x, mapping) for k, x in data.items()}
    return data


def _rehandle(spec, mapping):
    """`spec` with the handles of its methods and of its handle axes mapped."""
    spec = dict(spec)
    spec["methods"] = [_rehandle_method(m, mapping) for m in spec.get("methods") or []]
    spec["axes"] = [dict(a, values=[mapping.get(int(x), x) for x in a["values"]])
                    if _handle_axis(spec, k) else a for k, a in enumerate(spec.get("axes") or [])]
    return spec


def _portable(methods):
    """Checks that each method written in Python can be pickled for the workers."""
    try:
        import cloudpickle as pickler
    except ImportError:
        import pickle as pickler
    for m in (methods or {}).values():
        try:
            pickler.dumps(m)
        except Exception as e:  # noqa: BLE001 - any pickling failure is the same error
            raise TypeError(f"the method {m.label()} cannot be sent to the Dask workers: "
                            f"it does not pickle ({type(e).__name__}: {e}); define its class "
                            "in a module or at a notebook's top level") from None


def _threads():
    """The cores of this worker's process over the tasks it runs at once."""
    import os

    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    try:
        from distributed import get_worker

        return max(1, (cores or 1) // get_worker().state.nthreads)
    except (ImportError, ValueError, AttributeError):
        return max(1, cores or 1)


def sweep(spec, client, shards=None, methods=None):
    _portable(methods)
    text = json.dumps(spec, allow_nan=False)
    # Checked here first: a bad spec is the caller's error, raised at once, not N times.
    head = _check(text)
    if shards is None:
        workers = len(client.scheduler_info().get("workers", {})) or 1
        shards = max(1, min(head["cells"], 4 * workers))
    methods = dict(methods) if methods else None
    futures = [client.submit(_shard, text, i, shards, methods, pure=False, retries=3)
               for i in range(shards)]
    results = client.gather(futures)
    rows = [json.loads(r) for _, part in results for r in part]
    rows.sort(key=lambda r: (r["cell"], r["method_index"]))
    return head, rows


def _check(text):
    """The head of a sweep, checked (no cell computed)."""
    try:
        return json.loads(_nhlab.check(text))
    except ValueError as e:
        message, path = e.args if len(e.args) == 2 else (str(e), None)
        raise InputError(message, path) from None
