//! Measured properties of a method on a system (the scorecard), computed, never declared:
//! reversibility, symmetry and preservation of the fibration (`docs/model.md` §1 and §9, the
//! paper's condition (i) of "Mechanism for near conservation of integrals").
//!
//! - *Reversible*: one step, flip the velocity (λ unchanged), one step, flip back returns
//!   the start to `1e-11 · max(1, |state|)`, from the start and from three later points.
//! - *Symmetric*: one step h, then one step −h, returns the start to the same tolerance,
//!   from the same points (`Φ_{−h} ∘ Φ_h = id`, what a composition needs).
//! - On the general class ([`measure_general`]) the fibration is not defined; the constraint
//!   check (3. below) is made as on the class.
//! - *Preserves the fibration*, three numerical checks from the scene's start, each over
//!   [`STEPS`] steps:
//!   1. the driver is blind to the passenger: a second start with the same `(ζ, ζ̇)` and a
//!      different passenger (shifted x, scaled v, still on the constraint manifold) must give
//!      the same `(ζ, ζ̇)` to `1e-12` (this catches DD, whose discrete gradient mixes them);
//!   2. the reduced update is blind to the fiber: a second start shifted along each force-free
//!      passenger axis (`∇U(x + e_i) = ∇U(x)`, the kernel of κ) must give the same reduced
//!      state `(y, v, ζ, ζ̇)` to `1e-12`, y being the coordinates off those axes;
//!   3. the method stays on the constraint manifold as a discrete method can: at every one
//!      of [`MANIFOLD_STEPS`] steps it imposes the constraint either at the step's end,
//!      `|A(q₁) q̇₁|`, or at its midpoint, `|A(q̄)(q̇₀ + q̇₁)/2|` (the DD family), to `1e-12`
//!      (this catches RK4, which imposes neither and drifts off); a composed method at every
//!      sub-step, as its base method does.
//!
//! A caller that must be able to stop (a server whose client went away) passes a `stop` flag,
//! looked at before every step: the measurement then ends with [`StepFailure::Stopped`].

use crate::methods::GeneralMemory;
use crate::model::mechanical::Mechanical;
use crate::model::system::System;
use crate::{Method, MethodMemory, State, StepFailure, Vector};

/// Steps of the coupling checks.
pub const STEPS: usize = 5;
/// Steps of the manifold check.
pub const MANIFOLD_STEPS: usize = 200;
/// Tolerance of the reversibility check (relative).
pub const REVERSIBLE_TOL: f64 = 1e-11;
/// Tolerance of the coupling checks (relative).
pub const COUPLING_TOL: f64 = 1e-12;

/// What was measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Properties {
    /// Round trip returns the start.
    pub reversible: bool,
    /// Largest round-trip defect.
    pub reversibility_defect: f64,
    /// A step back with −h returns the start.
    pub symmetric: bool,
    /// Largest `Φ_{−h} ∘ Φ_h` defect.
    pub symmetry_defect: f64,
    /// Whether the fibration is defined for the system (the paper's class), and so measured.
    pub fibration_measured: bool,
    /// All three fibration checks pass (false where it is not measured).
    pub preserves_fibration: bool,
    /// Largest driver difference caused by a passenger change (check 1).
    pub driver_coupling: f64,
    /// Largest reduced-state difference caused by a fiber shift (check 2; 0 when the
    /// fiber is trivial, as for the CVT).
    pub fiber_coupling: f64,
    /// Largest discrete-constraint residual, the smaller of end and midpoint (check 3).
    pub constraint_defect: f64,
}

fn scale<const N: usize, const R: usize>(st: &State<N, R>) -> f64 {
    st.q.amax().max(st.v.amax()).max(1.0)
}

/// A state with the method's memory of how it got there (empty for a fresh start).
type Point<const N: usize, const R: usize> = (State<N, R>, MethodMemory<N, R>);

fn run<const N: usize, const R: usize>(
    step: &dyn Fn(&mut State<N, R>, &mut MethodMemory<N, R>, f64) -> Result<(), StepFailure>,
    (mut st, mut memory): Point<N, R>,
    h: f64,
    steps: usize,
) -> Result<Point<N, R>, StepFailure> {
    for _ in 0..steps {
        step(&mut st, &mut memory, h)?;
    }
    Ok((st, memory))
}

/// The largest defects of the velocity-flip round trip and of the step back with −h, from the
/// start and three later points, for a method's step `step` (class or general) with memories
/// of type `M`.
fn round_trips<M: Copy, const N: usize, const R: usize>(
    step: &dyn Fn(&mut State<N, R>, &mut M, f64) -> Result<(), StepFailure>,
    mut point: (State<N, R>, M),
    h: f64,
) -> Result<(f64, f64), StepFailure> {
    let (mut reversibility, mut symmetry): (f64, f64) = (0.0, 0.0);
    let defect =
        |a: &State<N, R>, b: &State<N, R>| (a.q - b.q).amax().max((a.v - b.v).amax()) / scale(b);
    for _ in 0..4 {
        let (start, memory) = point;
        let (mut st, mut mem) = (start, memory);
        step(&mut st, &mut mem, h)?;
        let after = (st, mem);
        st.v = -st.v;
        step(&mut st, &mut mem, h)?;
        st.v = -st.v;
        reversibility = reversibility.max(defect(&st, &start));
        let (mut st, mut mem) = after;
        step(&mut st, &mut mem, -h)?;
        symmetry = symmetry.max(defect(&st, &start));
        point = (start, memory);
        for _ in 0..17 {
            step(&mut point.0, &mut point.1, h)?;
        }
    }
    Ok((reversibility, symmetry))
}

/// Check 3: the largest discrete-constraint residual over [`MANIFOLD_STEPS`] steps of `m`
/// (relative), the smaller of `defects(before, after)`'s end and midpoint residuals at each
/// step; a composed method imposes its base method's at every sub-step, so it is checked
/// there (`base_step` is its base method's step).
fn constraint_defect<M: Copy, const N: usize, const R: usize>(
    m: &Method,
    base_step: &dyn Fn(&mut State<N, R>, &mut M, f64) -> Result<(), StepFailure>,
    defects: &dyn Fn(&State<N, R>, &State<N, R>) -> (f64, f64),
    (mut st, mut memory): (State<N, R>, M),
    h: f64,
) -> Result<f64, StepFailure> {
    let fractions = m.composition.map_or(&[1.0][..], |c| c.coefficients());
    let mut worst: f64 = 0.0;
    for _ in 0..MANIFOLD_STEPS {
        for &gamma in fractions {
            let prev = st;
            base_step(&mut st, &mut memory, gamma * h)?;
            let (end, mid) = defects(&prev, &st);
            worst = worst.max(end.min(mid) / scale(&st));
        }
    }
    Ok(worst)
}

/// A start on the constraint manifold with the passenger moved to `x + dx` and its reduced
/// velocity scaled by `factor`.
fn moved<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &State<N, R>,
    dx: &Vector<N>,
    factor: f64,
) -> Option<State<N, R>> {
    let zeta = st.q[N - 1];
    let k = sys.kernel(zeta);
    let mut v = k * (k.dot(&st.v) * factor + 0.25 * (1.0 - factor));
    v[N - 1] = st.v[N - 1];
    State::with_continuous_multiplier(sys, st.q + dx, v)
}

/// Measures both properties of `m` on `sys` from `start` with step `h`, ended with
/// [`StepFailure::Stopped`] once `stop()` turns true (looked at before every step).
pub fn measure<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    m: &Method,
    start: State<N, R>,
    h: f64,
    stop: &dyn Fn() -> bool,
) -> Result<Properties, StepFailure> {
    let fresh = |st: State<N, R>| (st, m.memory());
    let step = |st: &mut State<N, R>, mem: &mut MethodMemory<N, R>, h| {
        if stop() {
            return Err(StepFailure::Stopped);
        }
        m.step(sys, st, mem, h)
    };
    let (reversibility_defect, symmetry_defect) = round_trips(&step, fresh(start), h)?;

    // 1. Driver blind to the passenger.
    let mut dx = Vector::<N>::from_fn(|i, _| 0.3 - 0.2 * i as f64);
    dx[N - 1] = 0.0;
    let other = moved(sys, &start, &dx, 1.5).ok_or(StepFailure::Singular)?;
    let (a, b) = (run(&step, fresh(start), h, STEPS)?.0, run(&step, fresh(other), h, STEPS)?.0);
    let driver_coupling =
        (a.q[N - 1] - b.q[N - 1]).abs().max((a.v[N - 1] - b.v[N - 1]).abs()) / scale(&a);

    // 2. Reduced state blind to shifts along force-free passenger axes.
    let g0 = sys.passenger_gradient(&start.q);
    let free: Vec<usize> = (0..N - 1)
        .filter(|&i| {
            let mut e = Vector::<N>::zeros();
            e[i] = 1.0;
            (sys.passenger_gradient(&(start.q + e)) - g0).amax() == 0.0
        })
        .collect();
    let mut fiber_coupling: f64 = 0.0;
    for &i in &free {
        let mut e = Vector::<N>::zeros();
        e[i] = 0.7;
        let shifted = moved(sys, &start, &e, 1.0).ok_or(StepFailure::Singular)?;
        let b = run(&step, fresh(shifted), h, STEPS)?.0;
        let k = |st: &State<N, R>| sys.kernel(st.q[N - 1]).dot(&st.v);
        let mut d = (k(&a) - k(&b)).abs();
        d = d.max((a.q[N - 1] - b.q[N - 1]).abs()).max((a.v[N - 1] - b.v[N - 1]).abs());
        for j in (0..N - 1).filter(|j| !free.contains(j)) {
            d = d.max((a.q[j] - b.q[j]).abs());
        }
        fiber_coupling = fiber_coupling.max(d / scale(&a));
    }

    // 3. A discrete constraint at every step; a composed method imposes its base method's at
    // every sub-step, so it is checked there.
    let base = Method { composition: None, ..*m };
    let base_step = |st: &mut State<N, R>, mem: &mut MethodMemory<N, R>, h| {
        if stop() {
            return Err(StepFailure::Stopped);
        }
        base.step(sys, st, mem, h)
    };
    let defects = |prev: &State<N, R>, st: &State<N, R>| {
        let mid_zeta = 0.5 * (prev.q[N - 1] + st.q[N - 1]);
        let mid = (sys.constraint(mid_zeta) * (prev.v + st.v) * 0.5).norm();
        (sys.constraint_residual(&st.q, &st.v), mid)
    };
    let constraint_defect = constraint_defect(m, &base_step, &defects, fresh(start), h)?;

    Ok(Properties {
        reversible: reversibility_defect <= REVERSIBLE_TOL,
        reversibility_defect,
        symmetric: symmetry_defect <= REVERSIBLE_TOL,
        symmetry_defect,
        fibration_measured: true,
        preserves_fibration: driver_coupling <= COUPLING_TOL
            && fiber_coupling <= COUPLING_TOL
            && constraint_defect <= COUPLING_TOL,
        driver_coupling,
        fiber_coupling,
        constraint_defect,
    })
}

/// Measures reversibility, symmetry and the discrete constraint (check 3) of `m`'s general
/// step on `sys` from `start` with step `h`; the fibration is not defined there. Ended with
/// [`StepFailure::Stopped`] once `stop()` turns true (looked at before every step).
pub fn measure_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
    sys: &S,
    m: &Method,
    start: State<N, R>,
    h: f64,
    stop: &dyn Fn() -> bool,
) -> Result<Properties, StepFailure> {
    let step = |st: &mut State<N, R>, mem: &mut GeneralMemory<N, R>, h| {
        if stop() {
            return Err(StepFailure::Stopped);
        }
        m.step_general(sys, st, mem, h)
    };
    let (reversibility_defect, symmetry_defect) =
        round_trips(&step, (start, GeneralMemory::empty()), h)?;
    let base = Method { composition: None, ..*m };
    let base_step = |st: &mut State<N, R>, mem: &mut GeneralMemory<N, R>, h| {
        if stop() {
            return Err(StepFailure::Stopped);
        }
        base.step_general(sys, st, mem, h)
    };
    let defects = |prev: &State<N, R>, st: &State<N, R>| {
        let mid = (sys.constraint(&(0.5 * (prev.q + st.q))) * (prev.v + st.v) * 0.5).norm();
        (sys.constraint_residual(&st.q, &st.v), mid)
    };
    let start = (start, GeneralMemory::empty());
    let constraint_defect = constraint_defect(m, &base_step, &defects, start, h)?;
    Ok(Properties {
        reversible: reversibility_defect <= REVERSIBLE_TOL,
        reversibility_defect,
        symmetric: symmetry_defect <= REVERSIBLE_TOL,
        symmetry_defect,
        fibration_measured: false,
        preserves_fibration: false,
        driver_coupling: f64::NAN,
        fiber_coupling: f64::NAN,
        constraint_defect,
    })
}
