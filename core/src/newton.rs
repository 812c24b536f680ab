//! Newton's method for the implicit steps, with the exact Jacobian.
//!
//! Every implicit method of MATH.md §3 solves for `(q̇₁, λ)` a system whose Jacobian has the
//! saddle-point form `[[B, G], [C, 0]]` (the constraint equations do not contain λ). It is
//! solved by the Schur complement `S = C B⁻¹ G`, an N×N and an R×R factorization, all on the
//! stack, instead of one (N+R)×(N+R) matrix that const generics cannot size.

use crate::linalg;
use crate::{Matrix, StepFailure, Vector};

/// Newton's stopping rule and iteration budget.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonConfig {
    /// Stop when the increment is below `tol · (1 + |unknowns|)` (max norm). Convergence is
    /// quadratic, so the iterate is then accurate to round-off.
    pub tol: f64,
    /// An increment below this, but no longer shrinking, is round-off: accept it.
    pub stagnation_tol: f64,
    /// Give up after this many iterations.
    pub max_iter: u32,
}

impl Default for NewtonConfig {
    fn default() -> Self {
        Self { tol: 1e-14, stagnation_tol: 1e-10, max_iter: 20 }
    }
}

/// Increments below this (relative) are taken to be in Newton's quadratic regime.
const QUADRATIC_REGIME: f64 = 1e-6;

/// Residuals and Jacobian blocks at the current iterate.
pub struct Linearization<const N: usize, const R: usize> {
    /// Momentum-equation residual (N).
    pub f1: Vector<N>,
    /// Constraint residual (R).
    pub f2: Vector<R>,
    /// `∂f1/∂q̇₁`.
    pub b: Matrix<N, N>,
    /// `∂f1/∂λ`.
    pub g: Matrix<N, R>,
    /// `∂f2/∂q̇₁`.
    pub c: Matrix<R, N>,
    /// Whether `b` may be diagonal but for its last column: then that is checked for, and
    /// such a `b` inverted by N divisions. False where `b` is known to be dense, which skips
    /// the check.
    pub b_maybe_bordered: bool,
}

/// Solves `f(v, λ) = 0` starting from `(v, λ)`, updating them in place; returns the number
/// of iterations.
#[inline]
pub fn solve<const N: usize, const R: usize>(
    cfg: &NewtonConfig,
    v: &mut Vector<N>,
    lambda: &mut Vector<R>,
    mut linearize: impl FnMut(&Vector<N>, &Vector<R>) -> Linearization<N, R>,
) -> Result<u32, StepFailure> {
    let mut previous = f64::INFINITY;
    let mut increment = f64::INFINITY;
    for it in 1..=cfg.max_iter {
        let l = linearize(v, lambda);
        let b_inv = if l.b_maybe_bordered {
            linalg::inverse_maybe_bordered(&l.b)
        } else {
            linalg::inverse(&l.b)
        }
        .ok_or(StepFailure::Singular)?;
        let (b_f1, b_g) = (b_inv * l.f1, b_inv * l.g);
        let d_lambda =
            linalg::solve(&(l.c * b_g), &(l.f2 - l.c * b_f1)).ok_or(StepFailure::Singular)?;
        let d_v = -(b_f1 + b_g * d_lambda);
        *v += d_v;
        *lambda += d_lambda;
        increment = d_v.amax().max(d_lambda.amax());
        if !increment.is_finite() {
            return Err(StepFailure::NonFinite);
        }
        let scale = 1.0 + v.amax().max(lambda.amax());
        if cfg.converged(increment, previous, scale) {
            return Ok(it);
        }
        previous = increment;
    }
    Err(StepFailure::NewtonDiverged { iterations: cfg.max_iter, increment })
}

/// Solves the two equations `f(x) = 0` from `x`, in place; `f` returns the values and the
/// Jacobian. Same stopping rule as [`solve`]. Returns the last increment as computed, before
/// its addition to `x` rounded it to `x`'s grid: a caller may apply it to finer quantities
/// derived from `x` at the last evaluation. DD's reduced path uses it for the two
/// coordinates of `q̇₀ + q̇₁` in the kernel of `A(q̄)`.
#[inline]
pub fn solve_pair(
    cfg: &NewtonConfig,
    x: &mut Vector<2>,
    mut f: impl FnMut(&Vector<2>) -> (Vector<2>, Matrix<2, 2>),
) -> Result<Vector<2>, StepFailure> {
    let mut previous = f64::INFINITY;
    let mut increment = f64::INFINITY;
    for _ in 0..cfg.max_iter {
        let (value, j) = f(x);
        let det = j[(0, 0)] * j[(1, 1)] - j[(0, 1)] * j[(1, 0)];
        if det == 0.0 {
            return Err(StepFailure::Singular);
        }
        // Cramer's rule: the reciprocal of the determinant is computed beside the numerators.
        let numerators = Vector::<2>::new(
            j[(0, 1)] * value[1] - j[(1, 1)] * value[0],
            j[(1, 0)] * value[0] - j[(0, 0)] * value[1],
        );
        let dx = numerators * (1.0 / det);
        *x += dx;
        increment = dx.amax();
        if !increment.is_finite() {
            return Err(StepFailure::NonFinite);
        }
        if cfg.converged(increment, previous, 1.0 + x.amax()) {
            return Ok(dx);
        }
        previous = increment;
    }
    Err(StepFailure::NewtonDiverged { iterations: cfg.max_iter, increment })
}

/// One Newton step for the scalar equation `f(x) = 0`, in place: the solution when `f` is
/// affine (then the step is exact, and a second one would only confirm it).
#[inline]
pub fn solve_affine_scalar(
    x: &mut f64,
    mut f: impl FnMut(f64) -> (f64, f64),
) -> Result<(), StepFailure> {
    let (value, slope) = f(*x);
    if slope == 0.0 {
        return Err(StepFailure::Singular);
    }
    *x -= value / slope;
    if x.is_finite() { Ok(()) } else { Err(StepFailure::NonFinite) }
}

impl NewtonConfig {
    /// Whether an iteration whose (max-norm) increment was `increment`, after one of
    /// `previous`, has converged for unknowns of size `scale`.
    #[inline]
    pub(crate) fn converged(&self, increment: f64, previous: f64, scale: f64) -> bool {
        // Quadratic convergence: e_{k+1} ≈ C e_k² with C ≈ δ_k/δ_{k−1}², so the error left
        // after this update is about δ_k³/δ_{k−1}². Trusting it (only once δ_k is small
        // enough to be in the quadratic regime) saves the iteration that would only verify.
        // After the first iteration there is no δ_{k−1} (previous = ∞) to estimate C from: a
        // lucky small first increment still leaves an error of order C δ₁², taken with
        // C = 1 (the nonlinearities here are scaled by h, so C ≲ 1). Trusting δ₁ itself
        // would accept δ₁ = 10⁻⁶ with an error of 10⁻¹²; never trusting it would make a
        // tiny step (h = 10⁻⁶) iterate into the round-off noise of DD's discrete gradient.
        let predicted = if previous.is_finite() {
            increment * (increment / previous).powi(2)
        } else {
            increment * increment
        };
        increment <= self.tol * scale
            || (increment <= QUADRATIC_REGIME * scale && predicted <= self.tol * scale)
            || (increment <= self.stagnation_tol * scale && increment >= 0.5 * previous)
    }
}
