"""The Python functions against the HTTP API's answers to the same requests: equal numbers
(timing aside), equal errors and paths; the interpreter's lock released while nhlab computes;
a fast import."""

import json
import math
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import nhlab

TIMING = {"elapsed_ms", "cpu_ms"}


def untimed(x):
    """`x` without its timing fields, wherever they are."""
    if isinstance(x, dict):
        return {k: untimed(v) for k, v in x.items() if k not in TIMING}
    if isinstance(x, list):
        return [untimed(v) for v in x]
    return x


def column(values):
    return np.array([math.nan if v is None else v for v in values], dtype=np.float64)


def test_systems_equal_the_http_answer(http):
    status, answer = http.call("GET", "/systems")
    assert status == 200
    ours = nhlab.systems()
    # The limits are the in-process server's own (more simulations at once); the rest equal.
    ours.pop("limits"), answer.pop("limits")
    assert ours == answer


def test_observables_are_numpy_columns_in_the_order_asked_for(http):
    observables = {"theta": "zeta", "speed": "x1_dot*cos(zeta) + x2_dot*sin(zeta)", "x": "x1"}
    kwargs = dict(system="knife_edge", preset="paper-perturbed", t_end=100, points=11,
                  methods=["leapfrog"], observables=observables)
    status, answer = http.call("POST", "/simulate", kwargs)
    assert status == 200
    run = nhlab.simulate(**kwargs).runs[0]
    assert list(run.observables) == ["t", "theta", "speed", "x"]
    for name, values in run.observables.items():
        assert values.dtype == np.float64 and len(values) == 11
        np.testing.assert_array_equal(values, column(answer["runs"][0]["observables"][name]))
    # The state after the step nearest each of 11 evenly spread times.
    h, n = answer["scene"]["step"], answer["scene"]["steps"]
    nearest = np.array([round(j * n / 10) for j in range(11)]) * h
    np.testing.assert_allclose(run.observables["t"], nearest, rtol=0, atol=1e-9)
    assert nhlab.simulate("knife_edge", t_end=1, methods=["leapfrog"]).runs[0].observables is None
    section = {"surface": "sin(zeta)", "direction": "up", "plot": ["x1", "theta"]}
    r = nhlab.simulate(**{**kwargs, "section": section}).runs[0]
    assert list(r.section) == ["t", "x1", "theta"] and len(r.section["t"]) > 3
    np.testing.assert_allclose(np.sin(r.section["theta"]), 0, atol=1e-9)
    with pytest.raises(nhlab.InputError) as e:
        nhlab.simulate("knife_edge", t_end=1, observables={"bad": "x1^"})
    assert e.value.path == "observables.bad"


def test_simulate_gives_the_http_numbers_as_numpy_arrays(http):
    kwargs = dict(system="cvt_pendulum", preset="rotating-perturbed", t_end=300, points=200,
                  methods=["leapfrog", {"id": "dla", "alpha": 0.4}, {"id": "dla01", "composition": "p4s3"}])
    status, answer = http.call("POST", "/simulate", kwargs)
    assert status == 200
    r = nhlab.simulate(**kwargs)
    assert r.scene == answer["scene"]
    assert [run.label for run in r.runs] == ["LF", "DLA^0.4", "DLA^{0,1}∘p4s3"]
    for run, theirs in zip(r.runs, answer["runs"]):
        assert (run.method, run.status, run.error, run.steps) == (
            theirs["method"], theirs["status"], theirs["error"], theirs["steps"])
        assert run.cpu_ms > 0
        assert set(run.series) == set(theirs["series"])
        for integral, s in run.series.items():
            t = theirs["series"][integral]
            for name in ("t", "mean", "max"):
                a = getattr(s, name)
                assert a.dtype == np.float64
                np.testing.assert_array_equal(a, column(t[name]))
            assert s.verdict == t["verdict"]
    assert r.run("LF").series["energy"].verdict["kind"] == "bounded"


def test_a_method_given_as_its_tableau_gives_the_http_numbers(http):
    methods = [{"id": "prk", "tableau": "gauss3"},
               {"id": "prk", "tableau": {"a": [[0.5]], "b": [1.0]}, "constraint": "midpoint"}]
    kwargs = dict(system="chaplygin_sleigh", t_end=5, points=5, methods=methods)
    status, answer = http.call("POST", "/simulate", kwargs)
    assert status == 200
    r = nhlab.simulate(**kwargs)
    assert [run.label for run in r.runs] == ["PRK[gauss3]", "PRK[1-stage p2, midpoint]"]
    for run, theirs in zip(r.runs, answer["runs"]):
        assert (run.method, run.status, run.steps) == (theirs["method"], "ok", theirs["steps"])
        np.testing.assert_array_equal(run.series["energy"].max, column(theirs["series"]["energy"]["max"]))
    tableaux = {t["id"]: t for t in nhlab.systems()["tableaux"]}
    assert tableaux["gauss3"]["order"] == 6


def test_a_diverging_run_has_nan_where_http_has_null(http):
    kwargs = dict(system="knife_edge", preset="paper", step=3.0, t_end=3000, methods=["rk4"], points=50)
    _, answer = http.call("POST", "/simulate", kwargs)
    r = nhlab.simulate(**kwargs)
    assert r.runs[0].status == answer["runs"][0]["status"]
    for integral, s in r.runs[0].series.items():
        np.testing.assert_array_equal(s.max, column(answer["runs"][0]["series"][integral]["max"]))


def test_scorecard_and_work_precision_equal_the_http_answers(http):
    body = {"methods": ["leapfrog", "dd"], "scenes": [{"system": "knife_edge", "preset": "paper"}],
            "points": 100}
    status, answer = http.call("POST", "/scorecard", body)
    assert status == 200
    assert untimed(nhlab.scorecard(**body)) == untimed(answer)
    body = dict(system="knife_edge", preset="paper", t_end=10, methods=["leapfrog", "dla01"], levels=3, repeats=1)
    status, answer = http.call("POST", "/work-precision", body)
    assert status == 200
    ours = nhlab.work_precision(**body)
    ours["reference"].pop("cached"), answer["reference"].pop("cached")
    assert untimed(ours) == untimed(answer)


SLEIGH = {"name": "sleigh", "coordinates": ["x", "y", "theta"],
          "parameters": {"m": 2, "I": 0.5, "a": 0.5},
          "mass": ["m", "m", "I"], "potential": "0",
          "constraints": [["-sin(theta)", "cos(theta)", "-a"]],
          "invariants": {"kinetic": "m*(x_dot^2 + y_dot^2)/2 + I*theta_dot^2/2"}}


def test_a_system_in_the_general_form_gives_the_http_numbers(http):
    kwargs = dict(system=SLEIGH, q=[0, 0, 0], v=[0, 0.5, 1], t_end=50, points=100,
                  methods=["dla01", "dd", "rattle", "rk4"])
    status, answer = http.call("POST", "/simulate", kwargs)
    assert status == 200
    r = nhlab.simulate(**kwargs)
    assert r.scene == answer["scene"]
    assert r.scene["paper_class"]["member"] is False
    assert r.scene["integrals"] == ["energy", "constraint", "kinetic"]
    for run, theirs in zip(r.runs, answer["runs"]):
        np.testing.assert_array_equal(run.series["kinetic"].max,
                                      column(theirs["series"]["kinetic"]["max"]))
    assert r.run("DD").series["kinetic"].verdict["kind"] == "exact"
    # DD-AVF has no step outside the paper's class: refused with why, at its method.
    with pytest.raises(nhlab.InputError) as raised:
        nhlab.simulate(SLEIGH, q=[0, 0, 0], v=[0, 0.5, 1], methods=["dd", "dd_avf"])
    assert raised.value.path == "methods[1]"
    assert "paper's class" in raised.value.message


SWEEP = {"system": "cvt_pendulum", "preset": "rotating-perturbed", "t_end": 60, "points": 100,
         "methods": [{"id": "dla", "alpha": 0.5}, "leapfrog"],
         "axes": [{"path": "methods.alpha", "linspace": [0.3, 0.7, 3]},
                  {"path": "params.epsilon", "values": [0, 0.5]}]}


def test_sweep_equals_post_sweep_and_goes_to_pandas(http):
    status, answer = http.call("POST", "/sweep", SWEEP)
    assert status == 200
    rows = nhlab.sweep(SWEEP)
    assert untimed(list(rows)) == untimed(answer["rows"])
    assert rows.head == {k: v for k, v in answer.items() if k != "rows"}
    assert untimed(list(nhlab.sweep(**SWEEP))) == untimed(answer["rows"])
    pd = pytest.importorskip("pandas")
    frame = rows.to_pandas()
    assert isinstance(frame, pd.DataFrame) and len(frame) == 12
    assert list(frame.columns[:5]) == ["cell", "methods.alpha", "params.epsilon", "method_index", "method"]
    assert frame["energy.kind"].tolist() == [r["verdicts"]["energy"]["kind"] for r in answer["rows"]]
    # The columns of the CSV answer, in its order (its last, the simulate body, aside).
    status, csv_text = http.call("POST", "/sweep", SWEEP, accept="text/csv")
    assert status == 200
    assert list(frame.columns) == csv_text.splitlines()[0].split(",")[:-1]


def test_a_sweep_takes_observables_at_t_end_into_its_rows_and_frame(http):
    spec = dict(SWEEP, observables={"x": "x1", "speed": "zeta_dot"})
    status, answer = http.call("POST", "/sweep", spec)
    assert status == 200
    rows = nhlab.sweep(spec)
    assert untimed(list(rows)) == untimed(answer["rows"])
    assert rows.head["observables"] == ["x", "speed"]
    pd = pytest.importorskip("pandas")
    frame = rows.to_pandas()
    assert frame["observables.x"].tolist() == [r["observables"]["x"] for r in answer["rows"]]
    status, csv_text = http.call("POST", "/sweep", spec, accept="text/csv")
    assert list(frame.columns) == csv_text.splitlines()[0].split(",")[:-1]


@pytest.mark.parametrize("call, path, body", [
    (lambda: nhlab.simulate("nope"), "/simulate", {"system": "nope"}),
    (lambda: nhlab.simulate("knife_edge", methods=[{"id": "dla", "alfa": 0.4}]), "/simulate",
     {"system": "knife_edge", "methods": [{"id": "dla", "alfa": 0.4}]}),
    (lambda: nhlab.simulate("knife_edge", q=[0, 0]), "/simulate", {"system": "knife_edge", "q": [0.0, 0.0]}),
    (lambda: nhlab.simulate("knife_edge", points="many"), None, None),
    (lambda: nhlab.scorecard(scenes=[{"system": "knife_edge", "step": -1}]), "/scorecard",
     {"scenes": [{"system": "knife_edge", "step": -1}]}),
    (lambda: nhlab.work_precision("knife_edge", levels=99), "/work-precision", {"system": "knife_edge", "levels": 99}),
    (lambda: nhlab.sweep(system="knife_edge", axes=[{"path": "speed", "values": [1]}]), "/sweep",
     {"system": "knife_edge", "axes": [{"path": "speed", "values": [1]}]}),
    (lambda: nhlab.sweep(system="knife_edge", axes=[{"path": "step", "values": ["a"]}]), "/sweep",
     {"system": "knife_edge", "axes": [{"path": "step", "values": ["a"]}]}),
])
def test_bad_input_raises_value_error_with_the_http_message_and_path(http, call, path, body):
    with pytest.raises(ValueError) as raised:
        call()
    if path is None:
        return  # refused by Python itself (int("many"))
    status, answer = http.call("POST", path, body)
    assert 400 <= status < 500
    e = raised.value
    assert isinstance(e, nhlab.InputError)
    assert (e.status, e.message, e.path) == (status, answer["error"], answer["path"])
    assert str(e) == f"{answer['path']}: {answer['error']}"


def long_call():
    """A call of some tenths of a second (4·10⁶ leap-frog steps)."""
    return nhlab.simulate("cvt_pendulum", preset="rotating-perturbed", t_end=400000,
                          methods=["leapfrog"], points=10)


def in_thread(call):
    """`call` started in a thread; the thread and the list its exception, if any, lands in."""
    raised = []

    def target():
        try:
            call()
        except BaseException as e:  # handed to the test, which fails with it
            raised.append(e)

    thread = threading.Thread(target=target)
    thread.start()
    return thread, raised


def test_lock_released_while_computing():
    """The interpreter's lock is released while nhlab computes: a Python thread keeps running
    beside a long call. Measured as the longest pause of the main thread's loop while the call
    runs in another thread, against the call's length; held, the lock would stop the loop for
    the whole call. No wall-clock ratio of two runs, so a loaded machine does not fail it. The
    loop sleeps between looks, so that it does not take a core from the computation (which
    runs at a lower priority)."""
    long_call()  # warm: the runtime and the latitude axis
    start = time.perf_counter()
    worker, raised = in_thread(long_call)
    last, longest_pause = start, 0.0
    while worker.is_alive():
        time.sleep(0.001)
        now = time.perf_counter()
        longest_pause, last = max(longest_pause, now - last), now
    length = time.perf_counter() - start
    worker.join()
    assert not raised, raised
    assert length > 0.05, length  # long enough for a pause to show
    assert longest_pause < 0.5 * length, (longest_pause, length)


def test_threads_compute_at_once():
    """Two threads' calls compute at the same time, not one after the other: `/health` counts
    two runs active at once while both are in flight. A state seen, not a time measured, so
    the number of free cores does not decide it."""
    calls = [in_thread(long_call) for _ in range(2)]
    most = 0
    while any(thread.is_alive() for thread, _ in calls) and most < 2:
        health = json.loads(nhlab._call("GET", "/health"))
        most = max(most, health["active_runs"])
        time.sleep(0.001)
    for thread, raised in calls:
        thread.join()
        assert not raised, raised
    assert most == 2, f"never two runs at once (at most {most})"


def test_import_is_fast():
    code = "import time; t = time.perf_counter(); import nhlab; print(time.perf_counter() - t)"
    times = [float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                  check=True).stdout) for _ in range(3)]
    assert min(times) < 0.5, times


INTERRUPTED = r"""
import json, os, signal, sys, threading, time
import nhlab
from nhlab import _nhlab
from nhlab.examples import Leapfrog

# Python keeps SIGINT ignored when it starts with it ignored (a background job of a script,
# as CI may run it); a terminal's Ctrl-C raises KeyboardInterrupt: make it so here too.
signal.signal(signal.SIGINT, signal.default_int_handler)

def interrupted(call):
    threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()
    start = time.perf_counter()
    try:
        call()
    except KeyboardInterrupt:
        elapsed = time.perf_counter() - start
        cpu = time.process_time()
        time.sleep(1.0)
        # What the process burns in the second after: the runs were stopped, not left behind.
        return elapsed, time.process_time() - cpu
    raise SystemExit("the call ended without KeyboardInterrupt")

# Each a minute or more uninterrupted: 100 cells of 10^7 steps.
spec = {"system": "knife_edge", "methods": ["dd"], "step": 1e-5, "t_end": 100, "points": 10,
        "axes": [{"path": "params.epsilon", "linspace": [0.01, 0.5, 100]}]}
print(json.dumps({
    "request": interrupted(lambda: nhlab.sweep(spec)),
    "shard": interrupted(lambda: _nhlab.shard(json.dumps(spec), 0, 1, 2)),
    # A method written in Python holds the interpreter's lock while it steps.
    "python": interrupted(lambda: nhlab.simulate("cvt_pendulum", preset="rotating", t_end=1e6,
                                                 methods=[Leapfrog()], points=10)),
    "after": nhlab.simulate("knife_edge", t_end=1, methods=["leapfrog"]).runs[0].status,
}))
"""


def test_ctrl_c_stops_a_long_call_and_its_runs():
    out = subprocess.run([sys.executable, "-c", INTERRUPTED], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    result = json.loads(out.stdout)
    for call in ("request", "shard", "python"):
        elapsed, cpu_after = result[call]
        assert elapsed < 3.0, (call, elapsed)
        # Runs left behind would burn a second or more of CPU each.
        assert cpu_after < 0.6, (call, cpu_after)
    assert result["after"] == "ok"
