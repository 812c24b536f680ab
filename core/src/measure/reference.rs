//! Reference solutions: the constrained ODE with the multiplier eliminated (`docs/model.md` §1),
//! `q̈ = −∇V + Aᵀλ(q, q̇)`, solved by Dop853 (ode_solvers) at a tight tolerance.
//!
//! The reference is what work–precision diagrams measure errors against; its own accuracy is
//! tested against the exact knife-edge solution and by tolerance halving. It drifts off the
//! constraint like any non-geometric method, so its constraint residual is reported with it.
//!
//! Any [`Mechanical`] system (a class system through [`General`](crate::model::mechanical::General),
//! whose acceleration is the class's own). Where a coordinate is an angle
//! ([`Mechanical::angle`]: the class's ζ where it is one) the solve restarts every [`SEGMENT`]
//! time units with it brought back near 0 by whole turns (counted, and added back at the end). A
//! rotating driver otherwise reaches ζ ≈ 7000 on the paper's rotating CVT: each step then
//! rounds ζ to 10⁻¹², and a relative tolerance on ζ lets 10⁻⁹ per step through; together
//! they held the reference at ~10⁻⁷ at t = 3000, where this one agrees with tighter solves to
//! ~10⁻⁹ (`tests/it/reference.rs`).
//!
//! Memory does not grow with the number of steps. Dop853 keeps every accepted step in its
//! output (its dense mode, which keeps fewer, costs three more evaluations per step and misplaces
//! a point at the end of the interval), so each solver runs at most [`CHUNK`] steps: `solout`
//! stops it there and a new one continues from the last state with the last step size. A caller
//! that must be able to stop (a server whose client went away) passes a `stop` flag to
//! [`reference_until`], looked at in `solout` about every [`AIM`] (the accepted steps between
//! two looks sized by a [`Pace`]: a step of a system given as formulas may cost a
//! millisecond).

use crate::Short;
use crate::Vector;
#[cfg(doc)]
use crate::measure::pace::AIM;
use crate::measure::pace::Pace;
use crate::model::mechanical::Mechanical;
use crate::solver::reduced_ode;
use nalgebra::DVector;
use ode_solvers::dop_shared::IntegrationError;
use std::cell::RefCell;
use std::f64::consts::TAU;

/// Default relative and absolute tolerance.
pub use crate::solver::reduced_ode::TOL;

/// Time between restarts that bring an angle ζ back near 0.
pub const SEGMENT: f64 = 1.0;

/// Most Dop853 steps per reference solve: beyond, the solve fails rather than hold a thread.
pub const MAX_STEPS: u32 = 2_000_000;

/// Most accepted steps of one Dop853 solver, which keeps them all: beyond, a new solver
/// continues.
pub const CHUNK: u32 = 1000;

/// Why a reference solve failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReferenceError {
    /// The solve needs more than [`MAX_STEPS`] steps to reach t_end.
    #[error(
        "the reference solve (Dop853) needs more than {} steps to reach t_end = {}: it stopped \
         at t = {}",
        Short(f64::from(*limit)),
        Short(*t_end),
        Short(*t)
    )]
    TooManySteps {
        /// The limit, [`MAX_STEPS`].
        limit: u32,
        /// Where it stopped.
        t: f64,
        /// Where it was to go.
        t_end: f64,
    },
    /// Dop853 gave up otherwise: its step size underflowed, or the problem became stiff.
    #[error("the reference solve (Dop853) stopped at t = {}: {why}", Short(*t))]
    Solver {
        /// Where it stopped.
        t: f64,
        /// Why, in words.
        why: String,
    },
    /// The solution became non-finite.
    #[error("reference solve diverged")]
    Diverged,
    /// The caller's stop flag turned true.
    #[error("the reference solve (Dop853) was stopped at t = {}", Short(*t))]
    Cancelled {
        /// Where it stopped.
        t: f64,
    },
}

/// A reference solution at `t_end`.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference<const N: usize> {
    /// Configuration at t_end.
    pub q: Vector<N>,
    /// Velocity at t_end.
    pub v: Vector<N>,
    /// Constraint residual `|A(q) q̇|` at t_end.
    pub constraint_residual: f64,
    /// Right-hand-side evaluations.
    pub evaluations: u32,
    /// Accepted steps.
    pub steps: u32,
    /// Most states one Dop853 solver kept: at most [`CHUNK`] + 1, whatever the number of
    /// steps.
    pub stored: usize,
}

/// What `solout` counts and decides across the solvers of one solve.
struct Track {
    /// When to look at the stop flag.
    pace: Pace,
    /// Accepted steps over all solvers.
    steps: u32,
    /// Accepted steps of the current solver.
    chunk: u32,
    /// The current solver stopped at [`CHUNK`] steps, before its end.
    paused: bool,
    /// Where the stop flag was found set, if it was.
    cancelled: Option<f64>,
}

struct Ode<'a, S, const N: usize, const R: usize> {
    sys: &'a S,
    /// The end of the current solver's interval.
    t1: f64,
    track: &'a RefCell<Track>,
    stop: &'a dyn Fn() -> bool,
}

impl<S: Mechanical<N, R>, const N: usize, const R: usize> ode_solvers::System<f64, DVector<f64>>
    for Ode<'_, S, N, R>
{
    fn system(&self, _t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        reduced_ode::rhs(self.sys, y, dy);
    }

    /// Called after each accepted step, ending at `x`; returning true ends `integrate`.
    fn solout(&mut self, x: f64, _y: &DVector<f64>, _dy: &DVector<f64>) -> bool {
        let mut track = self.track.borrow_mut();
        track.steps += 1;
        track.chunk += 1;
        if track.pace.tick().is_some() && (self.stop)() {
            track.cancelled = Some(x);
            return true;
        }
        if track.chunk >= CHUNK && x < self.t1 {
            track.paused = true;
            return true;
        }
        false
    }
}

/// Solves from `(q, v)` at t = 0 to `t_end` with relative and absolute tolerance `tol`.
pub fn reference<S: Mechanical<N, R>, const N: usize, const R: usize>(
    sys: &S,
    q: &Vector<N>,
    v: &Vector<N>,
    t_end: f64,
    tol: f64,
) -> Result<Reference<N>, ReferenceError> {
    reference_until(sys, q, v, t_end, tol, &|| false)
}

/// [`reference`], stopped with [`ReferenceError::Cancelled`] when `stop()` turns true; it is
/// looked at about every [`AIM`] (every few accepted steps).
pub fn reference_until<S: Mechanical<N, R>, const N: usize, const R: usize>(
    sys: &S,
    q: &Vector<N>,
    v: &Vector<N>,
    t_end: f64,
    tol: f64,
    stop: &dyn Fn() -> bool,
) -> Result<Reference<N>, ReferenceError> {
    let mut y = DVector::from_iterator(2 * N, q.iter().chain(v.iter()).copied());
    let angle = sys.angle();
    let track = RefCell::new(Track {
        pace: Pace::default(),
        steps: 0,
        chunk: 0,
        paused: false,
        cancelled: None,
    });
    let (mut t, mut turns, mut evaluations, mut steps, mut stored) = (0.0, 0.0, 0, 0, 0);
    while t < t_end {
        let t1 = if angle.is_some() { (t + SEGMENT).min(t_end) } else { t_end };
        // Dop853 picks the first step of a segment; a solver that continues one takes the
        // last step size.
        let (mut x, mut h) = (t, 0.0);
        loop {
            let budget = MAX_STEPS.saturating_sub(steps);
            if budget == 0 {
                return Err(ReferenceError::TooManySteps { limit: MAX_STEPS, t: x, t_end });
            }
            {
                let mut tracked = track.borrow_mut();
                (tracked.chunk, tracked.paused) = (0, false);
            }
            // Steps at most the segment, the first the last one's (0 at a segment's start).
            let ode = Ode::<S, N, R> { sys, t1, track: &track, stop };
            let mut solver = reduced_ode::dop853(ode, (x, t1), y, tol, t1 - t, h, budget);
            let stats = solver.integrate().map_err(|e| match e {
                // The budget handed to this solver is what the solve has left of MAX_STEPS.
                IntegrationError::MaxNumStepReached { x, .. } => {
                    ReferenceError::TooManySteps { limit: MAX_STEPS, t: x, t_end }
                }
                IntegrationError::StepSizeUnderflow { x } => {
                    ReferenceError::Solver { t: x, why: "its step size underflowed".into() }
                }
                IntegrationError::StiffnessDetected { x } => ReferenceError::Solver {
                    t: x,
                    why: "the problem became stiff for an explicit solver".into(),
                },
            })?;
            (evaluations, steps) = (evaluations + stats.num_eval, steps + stats.accepted_steps);
            let (xs, ys) = (solver.x_out(), solver.y_out());
            stored = stored.max(ys.len());
            y = ys.last().cloned().unwrap_or_default();
            if y.len() != 2 * N || y.iter().any(|x| !x.is_finite()) {
                return Err(ReferenceError::Diverged);
            }
            let tracked = track.borrow();
            if let Some(t) = tracked.cancelled {
                return Err(ReferenceError::Cancelled { t });
            }
            if !tracked.paused {
                break;
            }
            (x, h) = (xs[xs.len() - 1], xs[xs.len() - 1] - xs[xs.len() - 2]);
        }
        if let Some(i) = angle {
            let k = (y[i] / TAU).round();
            y[i] -= k * TAU;
            turns += k;
        }
        t = t1;
    }
    if let Some(i) = angle {
        y[i] += turns * TAU;
    }
    let (qe, ve) = (Vector::<N>::from_fn(|i, _| y[i]), Vector::<N>::from_fn(|i, _| y[N + i]));
    Ok(Reference {
        q: qe,
        v: ve,
        constraint_residual: sys.constraint_residual(&qe, &ve),
        evaluations,
        steps,
        stored,
    })
}
