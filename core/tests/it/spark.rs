//! The SPARK methods (`docs/model.md` §3): the observed order 2s − 2, in q and in q̇, on the
//! knife edge's and the rolling disk's exact solutions and on the Chaplygin sleigh against the
//! reference solve; the end point on the constraint, symmetry and reversibility to round-off,
//! on the paper's class and on the general one.

use crate::common::{self, disk_exact, knife_exact};
use nhlab_core::measure::reference::reference;
use nhlab_core::methods::Spark;
use nhlab_core::model::mechanical::GeneralBuiltIn;
use nhlab_core::systems::{ChaplyginSleigh, KnifeEdge, RollingDisk};
use nhlab_core::{
    BuiltIn, GeneralMemory, InputError, Mechanical, Method, MethodSpec, State, System, Vector,
};

/// Errors below this are round-off (or the reference's own error), left out of the fit.
const FLOOR: f64 = 1e-12;

fn spark(stages: u8) -> Method {
    Method::from_spec(&MethodSpec::new("spark").with("stages", f64::from(stages))).unwrap()
}

/// The observed order of `err(n)`, the error after n steps: from the first power of 2 whose
/// error is below 10^{−1−order/2}, step counts growing by 10^{1/(2·order)} (half a decade of
/// error each) until the error reaches the floor; the slope over those points. Infinite
/// where two steps are exact to round-off already (the rolling disk's q̇).
pub(crate) fn observed(order: u32, t_end: f64, err: impl Fn(u32) -> f64) -> (f64, Vec<(u32, f64)>) {
    if err(2) <= FLOOR {
        return (f64::INFINITY, vec![(2, err(2))]);
    }
    let mut n = 2;
    while err(n) > 10f64.powf(-1.0 - order as f64 / 2.0) {
        n *= 2;
        assert!(n <= 1 << 12, "no small error with 2^12 steps");
    }
    let ratio = 10f64.powf(0.5 / order as f64);
    let (mut hs, mut errors, mut steps) = (Vec::new(), Vec::new(), n as f64);
    while errors.last().is_none_or(|&e| e > FLOOR) && hs.len() < 8 {
        let k = (steps.round() as u32).max(n);
        hs.push(t_end / k as f64);
        errors.push(err(k));
        (n, steps) = (k + 1, steps * ratio);
    }
    let shown = hs.iter().map(|h| (t_end / h).round() as u32).zip(errors.iter().copied()).collect();
    (common::slope(&hs, &errors, FLOOR), shown)
}

/// The error in q and in q̇ after n steps of `m` on a class system.
fn class_error<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    m: &Method,
    (q0, v0): (Vector<N>, Vector<N>),
    (q, v): (Vector<N>, Vector<N>),
    t_end: f64,
    n: u32,
) -> (f64, f64) {
    let mut st = State::with_continuous_multiplier(sys, q0, v0).unwrap();
    let mut memory = m.memory();
    for _ in 0..n {
        m.step(sys, &mut st, &mut memory, t_end / n as f64).unwrap();
    }
    ((st.q - q).amax(), (st.v - v).amax())
}

fn check_orders<S: System<N, R>, const N: usize, const R: usize>(
    name: &str,
    sys: &S,
    start: (Vector<N>, Vector<N>),
    end: (Vector<N>, Vector<N>),
) {
    let mut failures = Vec::new();
    for s in 2..=5 {
        let m = spark(s);
        let order = m.order();
        assert_eq!(order, 2 * u32::from(s) - 2);
        for (what, pick) in [("q", 0), ("q̇", 1)] {
            let err = |n| {
                let e = class_error(sys, &m, start, end, 10.0, n);
                if pick == 0 { e.0 } else { e.1 }
            };
            let (p, shown) = observed(order, 10.0, err);
            println!("{name} {} in {what}: order {p:.2}, errors {shown:?}", m.label());
            if p.is_finite() && (p - order as f64).abs() > 0.2 + 0.05 * order as f64 {
                failures.push(format!("{} in {what}: {p:.2}, expected {order}", m.label()));
            }
        }
    }
    assert!(failures.is_empty(), "{name}: {failures:?}");
}

#[test]
fn spark_reaches_order_2s_minus_2_on_the_knife_edge() {
    check_orders("knife_edge", &KnifeEdge::new(&[0.0]), knife_exact(0.0), knife_exact(10.0));
}

#[test]
fn spark_reaches_order_2s_minus_2_on_the_rolling_disk() {
    check_orders("rolling_disk", &RollingDisk::new(&[]), disk_exact(0.0), disk_exact(10.0));
}

/// The sleigh's first preset, from a consistent start.
pub(crate) fn sleigh() -> (ChaplyginSleigh, State<3, 1>) {
    let info = <ChaplyginSleigh as GeneralBuiltIn<3, 1>>::info();
    let p = &info.presets[0];
    let sys = <ChaplyginSleigh as GeneralBuiltIn<3, 1>>::new(&info.preset_params(p));
    let (q, v) = (Vector::<3>::from_column_slice(p.q), Vector::<3>::from_column_slice(p.v));
    let start = State::general_start(&sys, q, v).unwrap();
    (sys, start)
}

/// The largest error in (q, q̇) after n steps of `m` from `start` to `t_end` on `sys`, against
/// the reference's end `(q, v)`.
pub(crate) fn sleigh_error(
    sys: &ChaplyginSleigh,
    m: &Method,
    start: &State<3, 1>,
    (q, v): (&Vector<3>, &Vector<3>),
    t_end: f64,
    n: u32,
) -> f64 {
    let (mut st, mut memory) = (*start, GeneralMemory::empty());
    for _ in 0..n {
        m.step_general(sys, &mut st, &mut memory, t_end / n as f64).unwrap();
    }
    (st.q - q).amax().max((st.v - v).amax())
}

#[test]
fn spark_reaches_order_2s_minus_2_on_the_chaplygin_sleigh() {
    let (sys, start) = sleigh();
    let t_end = 5.0;
    let r = reference(&sys, &start.q, &start.v, t_end, 1e-15).unwrap();
    let mut failures = Vec::new();
    for s in 2..=5 {
        let m = spark(s);
        let order = m.order();
        let err = |n| sleigh_error(&sys, &m, &start, (&r.q, &r.v), t_end, n);
        let (p, shown) = observed(order, t_end, err);
        println!("chaplygin_sleigh {}: order {p:.2}, errors {shown:?}", m.label());
        if (p - order as f64).abs() > 0.2 + 0.05 * order as f64 {
            failures.push(format!("{}: {p:.2}, expected {order}", m.label()));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

#[test]
fn spark_ends_on_the_constraint_and_is_symmetric_and_reversible() {
    let (sys, start) = sleigh();
    for s in 2..=5 {
        let m = spark(s);
        for h in [0.05, 0.2, 0.5] {
            let step = |st: &mut State<3, 1>, h: f64| {
                m.step_general(&sys, st, &mut GeneralMemory::empty(), h).unwrap();
            };
            let mut st = start;
            step(&mut st, h);
            let residual = (sys.constraint(&st.q) * st.v).amax();
            assert!(residual < 1e-15, "{} h = {h}: A(q₁) q̇₁ = {residual:e}", m.label());
            let mut back = st;
            step(&mut back, -h);
            let symmetric = (back.q - start.q).amax().max((back.v - start.v).amax());
            assert!(symmetric < 1e-14, "{} h = {h}: Φ₋ₕ∘Φₕ off by {symmetric:e}", m.label());
            let mut flipped = State::general_start(&sys, st.q, -st.v).unwrap();
            step(&mut flipped, h);
            let reversed = (flipped.q - start.q).amax().max((-flipped.v - start.v).amax());
            assert!(reversed < 1e-14, "{} h = {h}: ρΦₕρΦₕ off by {reversed:e}", m.label());
        }
    }
}

#[test]
fn stages_outside_2_to_5_are_refused_at_their_field() {
    for bad in [1.0, 2.5, 6.0] {
        let spec = MethodSpec::new("spark").with("stages", bad);
        let e = Method::from_spec(&spec).unwrap_err();
        assert!(
            matches!(&e, InputError::ParamOutOfRange { field, .. } if field == "stages"),
            "{e}"
        );
    }
}

/// The structured solve (a Schur complement on the multipliers) against the dense solve of the
/// whole Newton system: the same steps to round-off, from small steps to ones large enough
/// that the structured solve hands over to the dense one.
#[test]
fn the_structured_solve_is_the_dense_one() {
    let (sys, start) = sleigh();
    for s in 2..=5 {
        let (fast, dense) = (
            Method::from(Spark { stages: s, ..Spark::default() }),
            Method::from(Spark { stages: s, fast_path: false, ..Spark::default() }),
        );
        for h in [0.01, 0.1, 0.5, 2.0] {
            let (mut a, mut b) = (start, start);
            for _ in 0..20 {
                fast.step_general(&sys, &mut a, &mut GeneralMemory::empty(), h).unwrap();
                dense.step_general(&sys, &mut b, &mut GeneralMemory::empty(), h).unwrap();
            }
            let size = 1.0 + b.q.amax().max(b.v.amax());
            let off = (a.q - b.q).amax().max((a.v - b.v).amax()) / size;
            assert!(off < 1e-13, "SPARK{s} h = {h}: structured and dense differ by {off:e}");
        }
    }
}
