"""Sweeps on a Dask cluster: the cells are split into shards (cells c with c mod N = i, as
`nhlab sweep --shard i/N` takes them), each a task that computes its rows in the worker's
process with nhlab's Rust code; the rows are joined by cell and method, exactly as
`POST /sweep` orders them. A task's rows depend on its cells alone, so a task retried on
another worker (its first worker lost) gives the same rows."""

import json

from . import InputError, _nhlab


def _shard(text, index, count):
    """One shard's (head, rows): run on a worker."""
    try:
        head, rows = _nhlab.shard(text, index, count, _threads())
    except ValueError as e:
        message, path = e.args if len(e.args) == 2 else (str(e), None)
        raise InputError(message, path) from None
    return head, rows


def _threads():
    """The cores of this worker's process over the tasks it runs at once."""
    import os

    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    try:
        from distributed import get_worker

        return max(1, (cores or 1) // get_worker().state.nthreads)
    except (ImportError, ValueError, AttributeError):
        return max(1, cores or 1)


def sweep(spec, client, shards=None):
    text = json.dumps(spec, allow_nan=False)
    # Checked here first: a bad spec is the caller's error, raised at once, not N times.
    head = _check(text)
    if shards is None:
        workers = len(client.scheduler_info().get("workers", {})) or 1
        shards = max(1, min(head["cells"], 4 * workers))
    futures = [client.submit(_shard, text, i, shards, pure=False, retries=3)
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
