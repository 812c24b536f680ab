//! Reference solutions: the constrained ODE with the multiplier eliminated (MATH.md §1),
//! `q̈ = −∇V + Aᵀλ(q, q̇)`, solved by Dop853 (ode_solvers) at a tight tolerance.
//!
//! The reference is what work–precision diagrams measure errors against; its own accuracy is
//! tested against the exact knife-edge solution and by tolerance halving. It drifts off the
//! constraint like any non-geometric method, so its constraint residual is reported with it.

use crate::Vector;
use crate::system::System;
use nalgebra::DVector;
use ode_solvers::dop_shared::OutputType;
use ode_solvers::dop853::Dop853;

/// Default relative and absolute tolerance.
pub const TOL: f64 = 1e-13;

/// Why a reference solve failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReferenceError {
    /// Dop853 gave up (step size underflow, too many steps, stiffness).
    #[error("reference solve failed: {0}")]
    Solver(String),
    /// The solution became non-finite.
    #[error("reference solve diverged")]
    Diverged,
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
}

struct Ode<'a, S, const N: usize, const R: usize> {
    sys: &'a S,
}

impl<S: System<N, R>, const N: usize, const R: usize> ode_solvers::System<f64, DVector<f64>>
    for Ode<'_, S, N, R>
{
    fn system(&self, _t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        let q = Vector::<N>::from_fn(|i, _| y[i]);
        let v = Vector::<N>::from_fn(|i, _| y[N + i]);
        // A singular A Aᵀ cannot occur for the registered systems (full row rank); NaN makes
        // the solver fail loudly rather than return a wrong reference.
        let a = self.sys.acceleration(&q, &v).map_or(Vector::<N>::repeat(f64::NAN), |(a, _)| a);
        for i in 0..N {
            dy[i] = v[i];
            dy[N + i] = a[i];
        }
    }
}

/// Solves from `(q, v)` at t = 0 to `t_end` with tolerance `tol`.
pub fn reference<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    q: &Vector<N>,
    v: &Vector<N>,
    t_end: f64,
    tol: f64,
) -> Result<Reference<N>, ReferenceError> {
    let y0 = DVector::from_iterator(2 * N, q.iter().chain(v.iter()).copied());
    let mut solver = Dop853::new(Ode::<S, N, R> { sys }, 0.0, t_end, t_end, y0, tol, tol);
    solver.set_output(OutputType::Sparse);
    let stats = solver.integrate().map_err(|e| ReferenceError::Solver(e.to_string()))?;
    let y = solver.y_out().last().cloned().unwrap_or_default();
    if y.len() != 2 * N || y.iter().any(|x| !x.is_finite()) {
        return Err(ReferenceError::Diverged);
    }
    let (qe, ve) = (Vector::<N>::from_fn(|i, _| y[i]), Vector::<N>::from_fn(|i, _| y[N + i]));
    Ok(Reference {
        q: qe,
        v: ve,
        constraint_residual: sys.constraint_residual(&qe, &ve),
        evaluations: stats.num_eval,
        steps: stats.accepted_steps,
    })
}
