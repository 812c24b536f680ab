"""Methods written in Python (`nhlab.Method`): the docs' leap-frog equals the built-in on
every paper scene; every instrument measures a user's method as a built-in (scorecard,
work–precision, compositions, sweeps with its parameters as an axis); a failing step ends its
run as `failed` with why, where; and a server never runs one."""

import json
import warnings

import numpy as np
import pytest

import nhlab
from nhlab.examples import Leapfrog, ProjectedVerlet


def coordinates(system):
    [entry] = [s for s in nhlab.systems()["systems"] if s["id"] == system]
    return entry["general"]["coordinates"]


@pytest.mark.parametrize("scene", [(s["system"], s["preset"])
                                   for s in nhlab.systems()["paper_scenes"]])
def test_the_docs_leapfrog_is_the_built_in_over_ten_thousand_steps(scene):
    system, preset = scene
    names = coordinates(system)
    observed = {**{c: c for c in names}, **{f"{c}_dot": f"{c}_dot" for c in names}}
    first = nhlab.simulate(system, preset=preset, methods=["leapfrog"], points=2)
    step = first.scene["step"]
    r = nhlab.simulate(system, preset=preset, methods=["leapfrog", Leapfrog()],
                       t_end=10_000 * step, points=200, observables=observed)
    built_in, own = r.runs
    assert own.status == "ok" and own.steps == built_in.steps >= 10_000
    assert own.method == {"id": "python", "name": "my LF", "label": "my LF"}
    # Relative to the state's size, as the scorecard's checks measure (ζ grows to 2,400 on
    # the rotating CVT, x to 13,000 on the perturbed knife edge).
    scale = max(1.0, *(np.max(np.abs(built_in.observables[name])) for name in observed))
    for name in observed:
        a, b = built_in.observables[name], own.observables[name]
        assert np.max(np.abs(a - b)) <= 1e-12 * scale, (scene, name)
    for integral, series in built_in.series.items():
        assert series.verdict["kind"] == own.series[integral].verdict["kind"], integral


def test_the_scorecard_measures_a_users_method_beside_the_built_ins():
    scenes = [{"system": "knife_edge", "preset": "paper-perturbed", "t_end": 20},
              {"system": "chaplygin_sleigh", "t_end": 20}]
    card = nhlab.scorecard(methods=["leapfrog", Leapfrog(), ProjectedVerlet()], scenes=scenes)
    props = {(p["method"]["label"], p["scene"]): p for p in card["properties"]}
    for scene in ("knife_edge/paper-perturbed", "chaplygin_sleigh/free"):
        lf, mine, projected = (props[(m, scene)] for m in ("LF", "my LF", "projected Verlet"))
        assert lf["reversible"] and mine["reversible"] and mine["symmetric"]
        assert mine["constraint_defect"] < 1e-12
        assert not projected["symmetric"] and not projected["reversible"]
        assert projected["constraint_defect"] < 1e-12
    assert props[("my LF", "knife_edge/paper-perturbed")]["preserves_fibration"]
    assert card["warnings"] == []
    runs = {r["method"]["label"]: r for r in card["scenes"][0]["runs"]}
    assert {k: v["kind"] for k, v in runs["my LF"]["verdicts"].items()} == {
        k: v["kind"] for k, v in runs["LF"]["verdicts"].items()}


class Liar(ProjectedVerlet):
    name = "liar"
    symmetric = True


def test_a_method_that_declares_itself_symmetric_and_is_not_is_warned_of():
    with pytest.warns(UserWarning, match=r"liar \(damping = 1\) declares itself symmetric but is not"):
        r = nhlab.simulate("knife_edge", preset="paper", methods=[Liar().composed("p4s3")],
                           t_end=10)
    assert r.runs[0].label == "liar∘p4s3" and r.runs[0].status == "ok"
    assert len(r.warnings) == 1
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert nhlab.simulate("knife_edge", preset="paper", methods=[Leapfrog()],
                              t_end=10).warnings == []
    with pytest.raises(nhlab.InputError, match="does not declare itself symmetric") as e:
        nhlab.simulate("knife_edge", preset="paper", methods=[ProjectedVerlet().composed("p4s3")])
    assert e.value.path == "methods[0].composition"


def slope(rows, label, key="final_error"):
    pts = [(r["step"], r[key]) for r in rows if r["method"]["label"] == label and r[key]]
    (h0, e0), (h1, e1) = pts[0], pts[-1]
    return np.log(e0 / e1) / np.log(h0 / h1)


def test_work_precision_measures_a_users_order_and_its_compositions():
    wp = nhlab.work_precision("knife_edge", preset="paper", t_end=4,
                              steps=[0.1, 0.05, 0.025], repeats=1,
                              methods=["leapfrog", Leapfrog(), Leapfrog().composed("p4s3")])
    rows = wp["rows"]
    assert abs(slope(rows, "LF") - slope(rows, "my LF")) < 1e-6
    assert 1.8 < slope(rows, "my LF") < 2.2
    assert 3.6 < slope(rows, "my LF∘p4s3") < 4.4


def test_a_sweep_takes_a_users_parameter_as_an_axis():
    spec = {"system": "knife_edge", "preset": "paper-perturbed", "t_end": 50, "points": 50,
            "methods": [ProjectedVerlet(), "leapfrog"],
            "axes": [{"path": "methods[0].damping", "values": [0.0, 0.5, 1.0]},
                     {"path": "params.epsilon", "values": [0.0, 0.1]}]}
    rows = nhlab.sweep(spec)
    assert rows.head["axes"][0] == {"path": "methods[0].damping", "values": [0.0, 0.5, 1.0]}
    mine = [r for r in rows if r["method_index"] == 0]
    assert [r["values"] for r in mine] == [[d, e] for d in (0.0, 0.5, 1.0) for e in (0.0, 0.1)]
    assert {r["method"]["damping"] for r in mine} == {0.0, 0.5, 1.0}
    assert all(r["method"]["label"] == "projected Verlet" for r in mine)
    # Without the projection (damping 0) the constraint is lost; with it, kept.
    kinds = {tuple(r["values"]): r["verdicts"]["constraint"]["kind"] for r in mine}
    assert kinds[(1.0, 0.1)] == "exact" and kinds[(0.0, 0.1)] != "exact"
    frame = rows.to_pandas()
    assert list(frame["methods[0].damping"][:2]) == [0.0, 0.0]
    # A spaced axis over its parameter takes the core's values, checks included.
    spaced = nhlab.sweep(dict(spec, axes=[{"path": "methods[0].damping",
                                           "linspace": [0.1, 0.3, 3]}]))
    assert spaced.head["axes"][0]["values"] == [0.1, 0.2, 0.3]
    with pytest.raises(nhlab.InputError) as e:
        nhlab.sweep(dict(spec, axes=[{"path": "methods[0].damping", "logspace": [0, 1, 3]}]))
    assert e.value.path == "axes[0].logspace"
    # Its parameters given beside it, as for a built-in.
    given = nhlab.simulate("knife_edge", t_end=1, methods=[{"id": ProjectedVerlet(),
                                                             "params": {"damping": 0.5}}])
    assert given.runs[0].method["damping"] == 0.5
    assert rows.warnings == []
    saved = json.loads(rows.to_json())
    assert saved["rows"] == list(rows) and saved["axes"] == rows.head["axes"]


def test_a_sweep_warns_of_a_method_that_is_not_symmetric_at_each_value():
    with pytest.warns(UserWarning):
        rows = nhlab.sweep(system="knife_edge", preset="paper", t_end=5, points=10,
                           methods=[Liar()],
                           axes=[{"path": "methods[0].damping",
                                  "values": [0.1 * k for k in range(1, 21)]}])
    # Each value run is measured, in batches within max_methods; the listed 1.0 never ran.
    assert len(rows.warnings) == 20
    assert "liar (damping = 0.1)" in rows.warnings[0]


class Raises(nhlab.Method):
    name = "raises"

    def step(self, system, q, v, h, memory):
        memory["n"] = memory.get("n", 0) + 1
        if memory["n"] == 3:
            raise ZeroDivisionError("on purpose")
        return q + h * v, v


class Short(nhlab.Method):
    def step(self, system, q, v, h, memory):
        return q[:-1], v


class Diverges(nhlab.Method):
    def step(self, system, q, v, h, memory):
        return q * np.nan, v


def test_a_failing_step_ends_its_run_as_failed_with_why_and_where():
    r = nhlab.simulate("knife_edge", preset="paper", t_end=5,
                       methods=[Raises(), Short(), Diverges(), "leapfrog"])
    raised, short, diverged, lf = r.runs
    assert raised.status == "failed" and raised.steps == 2
    assert "step 3 (t = 0.6" in raised.error and "ZeroDivisionError: on purpose" in raised.error
    assert short.status == "failed" and "q1 returned has 2 entries" in short.error
    assert short.method["label"] == "Short"
    assert diverged.status == "failed" and "non-finite" in diverged.error
    assert lf.status == "ok"


def test_the_system_is_refused_outside_a_step_and_a_method_is_checked():
    kept = []

    class Keeps(nhlab.Method):
        def step(self, system, q, v, h, memory):
            kept.append(system)
            assert system.n == 3 and system.r == 1 and system.in_paper_class
            assert np.allclose(system.A(q) @ system.project(q, v + 1), 0, atol=1e-14)
            assert system.zeta_index == 2 and system.A_x(q[2]).shape == (1, 3)
            assert system.energy(q, v) == pytest.approx(0.5 * v @ system.M() @ v + system.V(q))
            return q, v

    r = nhlab.simulate("knife_edge", preset="paper", t_end=1, methods=[Keeps()])
    assert r.runs[0].status == "ok", r.runs[0].error
    with pytest.raises(RuntimeError, match="only inside the method's step"):
        kept[0].V(np.zeros(3))

    class NoOrder(nhlab.Method):
        order = 1.5

    with pytest.raises(TypeError, match="order must be a whole number"):
        nhlab.simulate("knife_edge", methods=[NoOrder()])


class ReadsInvariants(nhlab.Method):
    """Keeps what `system` gives of the invariants at each step's start, with (q, v)."""

    def __init__(self):
        self.seen = []

    def step(self, system, q, v, h, memory):
        self.seen.append((system.invariant_names, system.invariants(q, v), q.copy(), v.copy()))
        return q + h * v, v


def invariants_seen(*args, **kwargs):
    method = ReadsInvariants()
    r = nhlab.simulate(*args, t_end=2, points=4, methods=[method], **kwargs)
    assert r.runs[0].status == "ok", r.runs[0].error
    assert len(method.seen) >= 3
    return method.seen


SLEIGH = {"name": "sleigh", "coordinates": ["x", "y", "theta"],
          "parameters": {"m": 2, "I": 0.5, "a": 0.5},
          "mass": ["m", "m", "I"], "potential": "0",
          "constraints": [["-sin(theta)", "cos(theta)", "-a"]],
          "invariants": {"kinetic": "m*(x_dot^2 + y_dot^2)/2 + I*theta_dot^2/2"}}


def test_the_system_gives_its_invariants_inside_a_step():
    close = dict(rel=1e-14, abs=1e-14)
    # Declared in the general form, at the parameters' values of the run (m = 3).
    for names, values, q, v in invariants_seen(SLEIGH, params={"m": 3}, q=[0, 0, 0],
                                               v=[0, 0.5, 1]):
        assert names == ["kinetic"] and list(values) == names
        assert values["kinetic"] == pytest.approx(3 * (v[0]**2 + v[1]**2) / 2 + 0.5 * v[2]**2 / 2,
                                                  **close)
    # The contact oscillator's H_y, found in the paper's class with y the driver: the run
    # holds (x, z, y), and E and h come first.
    for names, values, q, v in invariants_seen("contact_oscillator", preset="mp"):
        assert names == ["passenger_energy", "driver_energy", "H_y"] and list(values) == names
        (x, z, y), (xd, zd, yd) = q, v
        assert values["H_y"] == pytest.approx((y**2 + yd**2) / 2, **close)
        assert values["driver_energy"] == pytest.approx(values["H_y"], **close)
        passenger = (xd**2 + zd**2) / 2 + (x**2 + z**2) / 2 + 0.3 * x**2 * z**2 / 2
        assert values["passenger_energy"] == pytest.approx(passenger, **close)
    # A built-in of the class declares none; one of the general class has none.
    names, values, _, _ = invariants_seen("knife_edge", preset="paper")[0]
    assert names == ["passenger_energy", "driver_energy"] and list(values) == names
    assert all(seen[:2] == ([], {}) for seen in invariants_seen("chaplygin_sleigh"))


def test_a_general_system_is_seen_whole(http):
    sleigh = {"system": "chaplygin_sleigh", "t_end": 30}
    r = nhlab.simulate(**sleigh, methods=["leapfrog", Leapfrog()], points=20,
                       observables={"th": "theta_dot"})
    lf, mine = r.runs
    assert np.max(np.abs(lf.observables["th"] - mine.observables["th"])) < 1e-12


def test_a_server_never_runs_a_method_written_in_python(http):
    status, answer = http.call("POST", "/simulate", {"system": "knife_edge",
                                                     "methods": [{"id": "python", "handle": 1}]})
    assert status == 422 and answer["path"] == "methods[0]"
    assert "only in the nhlab Python package" in answer["error"]
    _, listing = http.call("GET", "/systems")
    assert "python" not in [m["id"] for m in listing["methods"]]


def test_runs_of_one_method_at_once_each_keep_their_memory():
    # Five runs of one object share its registration; each steps with its own memory,
    # however the interpreter's lock is handed between them.
    r = nhlab.simulate("cvt_pendulum", preset="rotating", t_end=1000, points=20,
                       methods=[Leapfrog()] * 5, observables={"z": "zeta"})
    assert [run.status for run in r.runs] == ["ok"] * 5, [run.error for run in r.runs]
    for run in r.runs[1:]:
        assert np.array_equal(run.observables["z"], r.runs[0].observables["z"])
