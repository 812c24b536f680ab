//! The constrained equations of motion with the multiplier eliminated (`docs/model.md` §1),
//! `M q̈ = −∇V + Aᵀλ(q, q̇)`, as the first-order system y = (q, q̇) that ode_solvers' Dop853
//! integrates: what the reference solve to t_end
//! ([`measure::reference`](crate::measure::reference)) and the `reference` method, which takes
//! one such solve per step ([`ReferenceStep`](crate::methods::ReferenceStep)), share.

use crate::model::mechanical::Mechanical;
use crate::{StepFailure, Vector};
use nalgebra::DVector;
use ode_solvers::dop_shared::{IntegrationError, OutputType};
use ode_solvers::dop853::Dop853;
use std::f64::consts::TAU;

/// The reference's relative and absolute tolerance.
pub const TOL: f64 = 1e-15;

/// Most Dop853 steps inside one step of the `reference` method.
pub const MAX_INNER_STEPS: u32 = 100_000;

/// dy = f(y) for y = (q, q̇): q̇ and the acceleration. A singular `A M⁻¹ Aᵀ` cannot occur
/// for a checked system (A of full rank); NaN there makes the solver fail loudly rather than
/// return a wrong state.
pub(crate) fn rhs<S: Mechanical<N, R>, const N: usize, const R: usize>(
    sys: &S,
    y: &DVector<f64>,
    dy: &mut DVector<f64>,
) {
    let q = Vector::<N>::from_fn(|i, _| y[i]);
    let v = Vector::<N>::from_fn(|i, _| y[N + i]);
    let a = sys.acceleration(&q, &v).map_or(Vector::<N>::repeat(f64::NAN), |(a, _)| a);
    for i in 0..N {
        dy[i] = v[i];
        dy[N + i] = a[i];
    }
}

/// A Dop853 solver of `f` from x to `x_end` at relative and absolute tolerance `tol`, its steps
/// at most `h_max`, its first `h` (0: chosen by the solver), at most `n_max` steps, keeping
/// each accepted step (ode_solvers' other parameters at their defaults: safety factor 0.9,
/// β = 0, step ratio within [0.333, 6], stiffness tested every 1000 steps). The reference
/// solve and the `reference` method's step both make theirs here.
pub(crate) fn dop853<F: ode_solvers::System<f64, DVector<f64>>>(
    f: F,
    (x, x_end): (f64, f64),
    y: DVector<f64>,
    tol: f64,
    h_max: f64,
    h: f64,
    n_max: u32,
) -> Dop853<f64, DVector<f64>, F> {
    let dx = x_end - x;
    Dop853::from_param(
        f,
        x,
        x_end,
        dx,
        y,
        tol,
        tol,
        0.9,
        0.0,
        0.333,
        6.0,
        h_max,
        h,
        n_max,
        1000,
        OutputType::Sparse,
    )
}

/// The system as ode_solvers sees it.
struct Reduced<'a, S, const N: usize, const R: usize>(&'a S);

impl<S: Mechanical<N, R>, const N: usize, const R: usize> ode_solvers::System<f64, DVector<f64>>
    for Reduced<'_, S, N, R>
{
    fn system(&self, _t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        rhs(self.0, y, dy);
    }
}

/// The state a time `h` after (q, q̇) (h < 0: before), by Dop853 at relative and absolute
/// tolerance `tol`. Where a coordinate is an angle ([`Mechanical::angle`]) the solve starts
/// from it brought near 0 by whole turns, added back at the end: the relative tolerance then
/// does not loosen as the angle grows.
pub fn dop853_step<S: Mechanical<N, R>, const N: usize, const R: usize>(
    sys: &S,
    q: &Vector<N>,
    v: &Vector<N>,
    h: f64,
    tol: f64,
) -> Result<(Vector<N>, Vector<N>), StepFailure> {
    let turns = sys.angle().map(|i| (i, (q[i] / TAU).round() * TAU));
    let mut y = DVector::from_iterator(2 * N, q.iter().chain(v.iter()).copied());
    if let Some((i, turns)) = turns {
        y[i] -= turns;
    }
    // Steps at most h, the first chosen by the solver.
    let mut solver =
        dop853(Reduced::<S, N, R>(sys), (0.0, h), y, tol, h.abs(), 0.0, MAX_INNER_STEPS);
    solver.integrate().map_err(|e| {
        StepFailure::AdaptiveSolve(match e {
            IntegrationError::MaxNumStepReached { .. } => "it needed too many steps",
            IntegrationError::StepSizeUnderflow { .. } => "its step size underflowed",
            IntegrationError::StiffnessDetected { .. } => "the problem became stiff",
        })
    })?;
    let y = solver.y_out().last().ok_or(StepFailure::NonFinite)?;
    if y.len() != 2 * N {
        return Err(StepFailure::NonFinite);
    }
    let mut q1 = Vector::<N>::from_fn(|i, _| y[i]);
    let v1 = Vector::<N>::from_fn(|i, _| y[N + i]);
    if let Some((i, turns)) = turns {
        q1[i] += turns;
    }
    Ok((q1, v1))
}
