"""Sweeps on a Dask cluster of two worker processes: the rows equal `POST /sweep`'s, also
when a worker is killed while the sweep runs."""

import os
import signal
import threading
import time

import pytest

import nhlab

distributed = pytest.importorskip("distributed")

SPEC = {"system": "cvt_pendulum", "preset": "rotating-perturbed", "t_end": 150, "points": 100,
        "observables": {"x": "x1", "e": "epsilon*x2"},
        "methods": [{"id": "dla", "alpha": 0.5}, "leapfrog", "dd"],
        "axes": [{"path": "methods.alpha", "linspace": [0.3, 0.7, 6]},
                 {"path": "params.epsilon", "linspace": [0, 0.5, 4]}]}


def untimed(rows):
    return [{k: v for k, v in r.items() if k != "cpu_ms"} for r in rows]


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_a_dask_sweep_equals_post_sweep(http, client):
    status, answer = http.call("POST", "/sweep", SPEC)
    assert status == 200
    rows = nhlab.sweep(SPEC, client=client)
    assert untimed(rows) == untimed(answer["rows"])
    assert rows.head == {k: v for k, v in answer.items() if k != "rows"}


def test_a_worker_killed_mid_sweep_changes_nothing(http, client):
    spec = dict(SPEC, t_end=6000)  # seconds of work for two workers
    _, answer = http.call("POST", "/sweep", spec)
    victim = sorted(client.run(os.getpid).values())[0]
    killed = []

    def kill_once_computing():
        # As soon as the scheduler has handed out tasks: mid-sweep on any machine.
        while not any(client.processing().values()):
            time.sleep(0.01)
        os.kill(victim, signal.SIGKILL)
        killed.append(time.perf_counter())

    killer = threading.Thread(target=kill_once_computing, daemon=True)
    killer.start()
    rows = nhlab.sweep(spec, client=client, shards=24)
    ended = time.perf_counter()
    killer.join(timeout=10)
    assert killed and killed[0] < ended, "the worker was killed while the sweep ran"
    assert victim not in client.run(os.getpid).values(), "the worker was killed (and replaced)"
    assert untimed(rows) == untimed(answer["rows"])


def test_a_bad_spec_raises_at_once(client):
    with pytest.raises(nhlab.InputError) as e:
        nhlab.sweep(dict(SPEC, axes=[{"path": "params.nope", "values": [1]}]), client=client)
    assert e.value.path == "axes[0].path"


def test_a_method_written_in_python_travels_to_the_workers(client):
    from nhlab.examples import ProjectedVerlet

    spec = {"system": "knife_edge", "preset": "paper-perturbed", "t_end": 30, "points": 20,
            "methods": ["leapfrog", ProjectedVerlet()],
            "axes": [{"path": "methods[1].damping", "values": [0.0, 0.5, 1.0]},
                     {"path": "params.epsilon", "values": [0.0, 0.1]}]}
    here = nhlab.sweep(spec)
    there = nhlab.sweep(spec, client=client)
    assert untimed(there) == untimed(here) and there.head == here.head
    assert {r["method"]["label"] for r in there} == {"LF", "projected Verlet"}

    class Local(nhlab.Method):
        def __init__(self):
            self.lock = threading.Lock()  # does not pickle

        def step(self, system, q, v, h, memory):
            return q, v

    with pytest.raises(TypeError, match="cannot be sent to the Dask workers"):
        nhlab.sweep(dict(spec, methods=[Local()]), client=client)
