//! Measured properties of a method on a system (the scorecard), computed, never declared:
//! reversibility and preservation of the fibration (`docs/model.md` §1, the paper's condition (i)
//! of "Mechanism for near conservation of integrals").
//!
//! - *Reversible*: one step, flip the velocity (λ unchanged), one step, flip back returns
//!   the start to `1e-11 · max(1, |state|)`, from the start and from three later points.
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
    /// All three fibration checks pass.
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

fn run<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    m: &Method,
    (mut st, mut memory): Point<N, R>,
    h: f64,
    steps: usize,
) -> Result<Point<N, R>, StepFailure> {
    for _ in 0..steps {
        m.step(sys, &mut st, &mut memory, h)?;
    }
    Ok((st, memory))
}

fn round_trip<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    m: &Method,
    start: Point<N, R>,
    h: f64,
) -> Result<f64, StepFailure> {
    let (mut st, mut memory) = run(sys, m, start, h, 1)?;
    let start = start.0;
    st.v = -st.v;
    m.step(sys, &mut st, &mut memory, h)?;
    st.v = -st.v;
    Ok((st.q - start.q).amax().max((st.v - start.v).amax()) / scale(&start))
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

/// Measures both properties of `m` on `sys` from `start` with step `h`.
pub fn measure<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    m: &Method,
    start: State<N, R>,
    h: f64,
) -> Result<Properties, StepFailure> {
    let fresh = |st: State<N, R>| (st, m.memory());
    let mut reversibility_defect: f64 = 0.0;
    let mut point = fresh(start);
    for _ in 0..4 {
        reversibility_defect = reversibility_defect.max(round_trip(sys, m, point, h)?);
        point = run(sys, m, point, h, 17)?;
    }

    // 1. Driver blind to the passenger.
    let mut dx = Vector::<N>::from_fn(|i, _| 0.3 - 0.2 * i as f64);
    dx[N - 1] = 0.0;
    let other = moved(sys, &start, &dx, 1.5).ok_or(StepFailure::Singular)?;
    let (a, b) = (run(sys, m, fresh(start), h, STEPS)?.0, run(sys, m, fresh(other), h, STEPS)?.0);
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
        let b = run(sys, m, fresh(shifted), h, STEPS)?.0;
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
    let (mut constraint_defect, (mut st, mut memory)): (f64, _) = (0.0, fresh(start));
    let base = Method { composition: None, ..*m };
    let fractions = m.composition.map_or(&[1.0][..], |c| c.coefficients());
    for _ in 0..MANIFOLD_STEPS {
        for &gamma in fractions {
            let prev = st;
            base.step(sys, &mut st, &mut memory, gamma * h)?;
            let end = sys.constraint_residual(&st.q, &st.v);
            let mid_zeta = 0.5 * (prev.q[N - 1] + st.q[N - 1]);
            let mid = (sys.constraint(mid_zeta) * (prev.v + st.v) * 0.5).norm();
            constraint_defect = constraint_defect.max(end.min(mid) / scale(&st));
        }
    }

    Ok(Properties {
        reversible: reversibility_defect <= REVERSIBLE_TOL,
        reversibility_defect,
        preserves_fibration: driver_coupling <= COUPLING_TOL
            && fiber_coupling <= COUPLING_TOL
            && constraint_defect <= COUPLING_TOL,
        driver_coupling,
        fiber_coupling,
        constraint_defect,
    })
}
