//! Symmetric compositions of the symmetric methods: the observed order (least-squares slope of
//! log global error against log h, above the round-off plateau) on the knife edge's and the
//! rolling disk's exact solutions and against the reference solve on the CVT; and the
//! structure each sub-step keeps, kept by the whole step (`properties`, DD's and DD-AVF's
//! energy).

use crate::common::{self, disk_exact, knife_exact};
use nhlab_core::measure::properties;
use nhlab_core::measure::reference::reference;
use nhlab_core::model::mechanical::General;
use nhlab_core::systems::{Cvt, KnifeEdge, RollingDisk};
use nhlab_core::{
    BuiltIn, Collect, Composition, InputError, Integral, Method, MethodSpec, PAPER_SCENES,
    Properties, RunConfig, Scene, SceneRequest, State, System, Vector,
};

/// Where the errors are measured: long enough that p8s15 meets 1e-4 with tens of steps, not
/// two or four (where its error constants still move).
const T_END: f64 = 10.0;

/// Errors below this are round-off (or the reference's own error) and left out of the fit.
const FLOOR: f64 = 2e-12;

/// Every symmetric method of the list taken in every composition.
fn composed() -> Vec<Method> {
    let symmetric: Vec<Method> = Method::all().into_iter().filter(|m| m.base.symmetric()).collect();
    let ids: Vec<&str> = symmetric.iter().map(|m| m.info().id).collect();
    assert_eq!(ids, ["dla", "dla01", "leapfrog", "dd", "dd_avf", "rattle", "spark"]);
    symmetric.into_iter().flat_map(|m| Composition::ALL.map(|c| m.composed(c).unwrap())).collect()
}

/// What an error is measured on.
#[derive(Debug, Clone, Copy, PartialEq)]
enum On {
    /// q and q̇.
    State,
    /// q and q̇ projected onto the constraint manifold, `q̇ − Aᵀ(AAᵀ)⁻¹A q̇` at q.
    Projected,
}

/// Max-norm error after `n` steps to `t_end`.
#[allow(clippy::too_many_arguments, reason = "a test's scene, spelled out")]
fn error<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    m: &Method,
    (q0, v0): (Vector<N>, Vector<N>),
    t_end: f64,
    n: u32,
    (q, v): (Vector<N>, Vector<N>),
    on: On,
) -> f64 {
    let mut st = State::with_continuous_multiplier(sys, q0, v0).unwrap();
    let (h, mut memory) = (t_end / n as f64, m.memory());
    for _ in 0..n {
        m.step(sys, &mut st, &mut memory, h).unwrap();
    }
    let mut v1 = st.v;
    if on == On::Projected {
        let a = sys.constraint(st.q[N - 1]);
        v1 -= a.transpose() * (a * a.transpose()).try_inverse().unwrap() * (a * st.v);
    }
    (st.q - q).amax().max((v1 - v).amax())
}

/// The observed order of `m`, expected to be `order`: from the fewest steps (a power of 2)
/// that bring the error under 10^{−2−order/2} (1e-4 at order 4, 1e-6 at order 8: above, the
/// 15-stage compositions' error is not yet its leading term on the CVT), even step counts (the leap-frog's error differs between
/// odd and even counts) growing by 10^{1/(2·order)} (half a decade of error each) until the
/// error reaches the floor.
fn observed_order<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    (m, order, points): (&Method, u32, usize),
    start: (Vector<N>, Vector<N>),
    t_end: f64,
    end: (Vector<N>, Vector<N>),
    on: On,
) -> (f64, Vec<(u32, f64)>) {
    let err = |n: u32| error(sys, m, start, t_end, n, end, on);
    let start_below = 10f64.powf(-2.0 - order as f64 / 2.0);
    let mut n = 2;
    while err(n) > start_below {
        n *= 2;
        assert!(n <= 1 << 14, "{}: no error under {start_below:e} with 2^14 steps", m.label());
    }
    let ratio = 10f64.powf(0.5 / order as f64);
    let (mut hs, mut errors) = (Vec::new(), Vec::new());
    let mut steps = n as f64;
    while errors.last().is_none_or(|&e| e > FLOOR) && hs.len() < points {
        n = n.max(2 * (steps / 2.0).round() as u32);
        hs.push(t_end / n as f64);
        errors.push(err(n));
        (n, steps) = (n + 2, steps * ratio);
    }
    let steps = hs.iter().map(|h| (t_end / h).round() as u32);
    (common::slope(&hs, &errors, FLOOR), steps.zip(errors.iter().copied()).collect())
}

/// How far from its order a composition may be observed: the tolerance.
fn tolerance(order: u32) -> f64 {
    match order {
        4 => 0.15,
        6 => 0.2,
        _ => 0.3,
    }
}

/// The orders measured, and on what (`docs/high-order.md`, "Orders").
///
/// - DLA^½ and DLA^{0,1} reach every composition's order in q and q̇.
/// - The leap-frog reaches order 4 with every composition, not 6 or 8. Its step carries λ
///   from the last step: with λ as a variable the step is symmetric, but it is not near the
///   identity as h → 0 (λ₁ lands near λ(q₁, q̇₁), wherever λ₀ was), so the composition
///   theory, which expands Φ_h about the identity, does not apply beyond what order 4 cancels.
/// - DD and DD-AVF impose the constraint at the step's midpoint, so q̇₁ leaves the constraint
///   manifold by O(h²) at the end of every (sub-)step and the next step turns that component
///   back (the zigzag): again a step not near the identity off the manifold. In q and in q̇
///   projected onto the manifold they reach order 4 with every composition; in q̇ itself the
///   O(h²) component off the manifold stays, so the error in q̇ is of order 2.
fn measured(m: &Method) -> (u32, On) {
    let c = m.composition.expect("composed");
    let measured = match m.info().id {
        "leapfrog" => (4, On::State),
        "dd" | "dd_avf" => (4, On::Projected),
        // SPARK (order 4 with its default 3 stages) keeps its own order under p4s3 and p4s5.
        _ => (c.order().max(m.base.order()), On::State),
    };
    assert_eq!(m.order(), measured.0, "{}: the order it declares", m.label());
    measured
}

fn check<S: System<N, R>, const N: usize, const R: usize>(
    name: &str,
    sys: &S,
    start: (Vector<N>, Vector<N>),
    t_end: f64,
    end: (Vector<N>, Vector<N>),
) {
    let mut failures = Vec::new();
    for m in composed() {
        let (order, on) = measured(&m);
        let mut check_one = |order: u32, on: On, tolerance: f64, points: usize| {
            let (p, errors) = observed_order(sys, (&m, order, points), start, t_end, end, on);
            let shown: Vec<String> = errors.iter().map(|(n, e)| format!("{n}: {e:.1e}")).collect();
            println!("{name} {} on {on:?}: order {p:.2}, errors {shown:?}", m.label());
            if (p - order as f64).abs() > tolerance {
                failures.push(format!("{} on {on:?}: {p:.2}, expected {order}", m.label()));
            }
        };
        // On the CVT, DLA^½∘p8s15's slope falls towards 8 as h shrinks (8.40 over errors down
        // to 7e-12, 8.31 down to 7e-13) but is still above 8.3 where the reference resolves
        // the error: its leading error term is small there. Measured, so asserted as such.
        // SPARK3∘p8s15 reads 8.54 there: its base is of order 4, its leading term smaller still.
        let slack = match (name, m.label().as_str()) {
            ("cvt", "DLA^0.5∘p8s15") => 0.1,
            ("cvt", "SPARK3∘p8s15") => 0.3,
            _ => 0.0,
        };
        check_one(order, on, tolerance(order) + slack, 20);
        if on == On::Projected {
            // The component off the manifold: order 2 in q̇ whatever the composition.
            check_one(2, On::State, 0.1, 6);
        }
    }
    assert!(failures.is_empty(), "{name}: observed orders off: {failures:?}");
}

#[test]
fn compositions_reach_their_order_on_the_knife_edge() {
    check("knife_edge", &KnifeEdge::new(&[0.0]), knife_exact(0.0), T_END, knife_exact(T_END));
}

#[test]
fn compositions_reach_their_order_on_the_rolling_disk() {
    check("rolling_disk", &RollingDisk::new(&[]), disk_exact(0.0), T_END, disk_exact(T_END));
}

#[test]
fn compositions_reach_their_order_on_the_cvt() {
    let (sys, st, _) = common::preset_start::<Cvt, 3, 1>(0);
    let r = reference(&General(&sys), &st.q, &st.v, T_END, 1e-15).unwrap();
    check("cvt", &sys, (st.q, st.v), T_END, (r.q, r.v));
}

#[test]
fn only_symmetric_methods_compose() {
    let composed = |spec: MethodSpec| Method::from_spec(&spec.composed("p4s3"));
    for (spec, why) in [
        (MethodSpec::new("rk4"), "not symmetric"),
        (MethodSpec::new("dla").with("alpha", 0.4), "only for α = 0.5"),
    ] {
        let e = composed(spec).unwrap_err();
        assert!(matches!(&e, InputError::Composition { field, .. } if field == "composition"));
        assert!(e.to_string().contains(why), "{e}");
    }
    let e = Method::from_spec(&MethodSpec::new("leapfrog").composed("p5s3")).unwrap_err();
    assert!(e.to_string().contains("unknown composition 'p5s3'"), "{e}");
    let lf = composed(MethodSpec::new("leapfrog")).unwrap();
    assert_eq!((lf.label().as_str(), lf.order(), lf.stages()), ("LF∘p4s3", 4, 3));
}

fn paper_scene(system: &str, preset: &str) -> Scene {
    let req =
        SceneRequest { system: system.into(), preset: Some(preset.into()), ..Default::default() };
    Scene::resolve(&req).unwrap()
}

#[test]
fn composed_methods_are_as_reversible_and_fibration_preserving_as_their_base() {
    for (system, preset) in PAPER_SCENES {
        let scene = paper_scene(system, preset);
        for base in Method::all().into_iter().filter(|m| m.base.symmetric()) {
            let b = scene.properties(&base).unwrap();
            for c in Composition::ALL {
                let m = base.composed(c).unwrap();
                let p = scene.properties(&m).unwrap();
                println!("{system}/{preset} {}: {p:?}", m.label());
                // The discrete constraint (check 3 of `properties`) on its own too: DD's
                // `preserves_fibration` is false for its driver coupling whatever check 3 says.
                let on_manifold = |p: &Properties| p.constraint_defect <= properties::COUPLING_TOL;
                assert_eq!(
                    (p.reversible, p.preserves_fibration, on_manifold(&p)),
                    (b.reversible, b.preserves_fibration, on_manifold(&b)),
                    "{system}/{preset} {}: {p:?}, base {b:?}",
                    m.label()
                );
            }
        }
    }
}

/// DD and DD-AVF keep H at round-off (DD-AVF E and h too, being fibration-preserving) when
/// composed, on every paper scene, to its t_end: each sub-step keeps them.
#[test]
fn composed_dd_and_dd_avf_keep_the_energy_on_every_paper_scene() {
    for (system, preset) in PAPER_SCENES {
        let scene = paper_scene(system, preset);
        let names = ["energy", "passenger_energy", "driver_energy"].map(String::from);
        let prepared = scene.prepare(Some(&names)).unwrap();
        for id in ["dd", "dd_avf"] {
            for c in Composition::ALL {
                let m = Method::from_spec(&MethodSpec::new(id).composed(c.id())).unwrap();
                let mut series = Collect::default();
                let out =
                    prepared.run(&m, &RunConfig { points: 100, ..Default::default() }, &mut series);
                assert_eq!(out.error, None, "{system}/{preset} {}", m.label());
                let kept: &[Integral] = if id == "dd" {
                    &[Integral::Energy]
                } else {
                    &[Integral::Energy, Integral::PassengerEnergy, Integral::DriverEnergy]
                };
                for integral in kept {
                    let worst = series.series[integral].iter().map(|b| b.max).fold(0.0, f64::max);
                    let rel = worst / series.initial[&Integral::Energy].abs();
                    println!("{system}/{preset} {} {}: {rel:.1e}", m.label(), integral.id());
                    assert!(
                        rel < 1e-12,
                        "{system}/{preset} {} {}: {rel:e}",
                        m.label(),
                        integral.id()
                    );
                }
            }
        }
    }
}

/// What `GET /systems` says of where a method is symmetric is what its step does: symmetric
/// (so composable) at that value with its listed order, not elsewhere, at the order said.
#[test]
fn symmetric_at_says_where_a_method_may_be_composed() {
    let mut checked = 0;
    for info in nhlab_core::method_infos() {
        let Some(at) = info.symmetric_at else { continue };
        let spec = |v: f64| MethodSpec::new(info.id).with(at.param, v);
        let there = Method::from_spec(&spec(at.value)).unwrap();
        assert!(there.base.symmetric() && there.order() == info.order, "{}", info.id);
        assert!(there.composed(Composition::ALL[0]).is_ok());
        let p = info.params.iter().find(|p| p.name == at.param).unwrap();
        for v in [p.min + 0.25 * (p.max - p.min), p.min + 0.9 * (p.max - p.min)] {
            let elsewhere = Method::from_spec(&spec(v)).unwrap();
            assert!(!elsewhere.base.symmetric(), "{} at {v}", info.id);
            assert_eq!(elsewhere.order(), at.order_elsewhere, "{} at {v}", info.id);
            assert!(elsewhere.composed(Composition::ALL[0]).is_err());
        }
        checked += 1;
    }
    assert!(checked >= 1, "DLA^α says where it is symmetric");
}
