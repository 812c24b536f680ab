//! Newton's method for the implicit steps, with the exact Jacobian.
//!
//! Every implicit method of `docs/model.md` §3 solves for `(q̇₁, λ)` a system whose Jacobian has
//! the saddle-point form `[[B, G], [C, 0]]` (the constraint equations do not contain λ). It is
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
    /// Stop on Newton's error estimate (`C δ²` after an increment δ, in the quadratic regime)
    /// only below `left_tol · (1 + |unknowns|)`. That error has one sign step after step: at
    /// `tol` (10⁻¹⁴) the energy-conserving methods (DD, DD-AVF) would show it as a drift at
    /// large steps; they take [`NewtonConfig::ENERGY_CONSERVING`].
    pub left_tol: f64,
}

impl Default for NewtonConfig {
    fn default() -> Self {
        Self { tol: 1e-14, stagnation_tol: 1e-10, max_iter: 20, left_tol: 1e-14 }
    }
}

impl NewtonConfig {
    /// DD's and DD-AVF's: the default with `left_tol = 10⁻¹⁷`, below round-off. On
    /// `cvt_pendulum`'s `oscillating-perturbed` scene at h = 0.5, DD's energy error after 10⁶
    /// steps was 3.1·10⁻¹⁰ and growing (verdict `drift`), 1.9·10⁻¹² with it; at the paper's
    /// h = 0.1 it costs an iteration more on some steps, a few percent of those solves' time
    /// (`docs/stability.md`).
    pub const ENERGY_CONSERVING: Self =
        Self { tol: 1e-14, stagnation_tol: 1e-10, max_iter: 20, left_tol: 1e-17 };
}

/// Increments below this (relative) are taken to be in Newton's quadratic regime.
const QUADRATIC_REGIME: f64 = 1e-6;

std::thread_local! {
    /// Newton iterations taken on this thread since the last [`take_iterations`]: a run's cost
    /// in iterations, reported by a sweep, without a counter in every method's memory. Counted
    /// once per solve, on its way out.
    static ITERATIONS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

#[inline]
pub(crate) fn counted<T>(
    iterations: u32,
    result: Result<T, StepFailure>,
) -> Result<T, StepFailure> {
    ITERATIONS.with(|c| c.set(c.get() + u64::from(iterations)));
    result
}

/// The Newton iterations this thread has taken since the last call, and a new count from 0.
/// A run's driver takes it before and after the run ([`PreparedScene::run`]).
///
/// [`PreparedScene::run`]: crate::PreparedScene::run
pub fn take_iterations() -> u64 {
    ITERATIONS.with(|c| c.replace(0))
}

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
    /// Whether the equations are affine in the other unknowns once the driver's speed (the
    /// last component of q̇₁) is fixed: DLA^{0,1}'s, and DLA^α's where U is quadratic, where
    /// ζ₁ enters through A(ζ₁) and V_d(ζ₁) only (with any other U, ∇U(q₁) is not affine in
    /// the passenger's speed, and this estimate stopped DLA^0.5 5·10⁻¹³ short on
    /// `anharmonic_cvt`). Every second derivative then involves the driver's speed, so
    /// an iteration leaves an error of about `K |δζ̇| δ`, with K from the iteration before: a
    /// sharper estimate than Newton's quadratic one when the passenger's and λ's increments
    /// are the larger ([`solve`]). False for DD, whose Gonzalez gradient is not affine in the
    /// passenger.
    pub affine_but_for_the_driver: bool,
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
    let (mut previous, mut previous_driver) = (f64::INFINITY, f64::INFINITY);
    let mut increment = f64::INFINITY;
    for it in 1..=cfg.max_iter {
        let l = linearize(v, lambda);
        let (d_v, d_lambda) = match saddle_increment(&l) {
            Ok(d) => d,
            Err(e) => return counted(it, Err(e)),
        };
        *v += d_v;
        *lambda += d_lambda;
        increment = d_v.amax().max(d_lambda.amax());
        if !increment.is_finite() {
            return counted(it, Err(StepFailure::NonFinite));
        }
        let scale = 1.0 + v.amax().max(lambda.amax());
        let driver = d_v[N - 1].abs();
        // The bilinear estimate needs the last iteration's driver increment: after the first
        // iteration, or one that left the driver's speed as it was, the quadratic one.
        let bilinear =
            l.affine_but_for_the_driver && previous_driver.is_finite() && previous_driver > 0.0;
        let (left, regime) = if bilinear {
            // e_k ≈ K |δζ̇_k| δ_k, with K ≈ δ_k / (|δζ̇_{k−1}| δ_{k−1}) from the last
            // iteration; trusted once the driver's increment, not the whole one, is in the
            // quadratic regime (the rest enters linearly). Where δ_k is mostly the passenger's
            // and λ's, this is ~100× below δ_k³/δ_{k−1}², and in practice it saves the third
            // iteration of DLA^0.5 on most steps of the rotating CVT
            // (`tests/it/newton_stopping.rs` checks the steps it stops at).
            (increment * (increment / previous) * (driver / previous_driver), driver)
        } else {
            (NewtonConfig::left_after(increment, previous), increment)
        };
        if cfg.converged(increment, (left, regime), previous, scale) {
            return counted(it, Ok(it));
        }
        (previous, previous_driver) = (increment, driver);
    }
    counted(cfg.max_iter, Err(StepFailure::NewtonDiverged { iterations: cfg.max_iter, increment }))
}

/// Newton's increment `(δq̇₁, δλ)` from one linearization: `B δq̇₁ + G δλ = −f1`,
/// `C δq̇₁ = −f2`, through the Schur complement `C B⁻¹ G`.
///
/// Where B is dense and 3×3 (DD's Jacobian on `cvt_pendulum`, where Gonzalez's correction fills
/// it), through `B⁻¹ = adj B / det B` with det B cancelled from the Schur equation,
/// `(C adj B G) δλ = det B f2 − C adj B f1`: the iteration then waits on one division (the
/// Schur solve's) where the inverse put the reciprocal of det B before it as well: a shorter chain,
/// which makes DD on `cvt_pendulum` faster. Elsewhere B is inverted: by N divisions where it is
/// diagonal but for its last column, in closed form or by LU otherwise.
#[inline(always)]
fn saddle_increment<const N: usize, const R: usize>(
    l: &Linearization<N, R>,
) -> Result<(Vector<N>, Vector<R>), StepFailure> {
    if !l.b_maybe_bordered
        && let Some((adj, det)) = linalg::adjugate3(&l.b)
    {
        if det == 0.0 || !det.is_finite() {
            return Err(StepFailure::Singular);
        }
        let (adj_f1, adj_g) = (adj * l.f1, adj * l.g);
        let d_lambda = linalg::solve(&(l.c * adj_g), &(l.f2 * det - l.c * adj_f1))
            .ok_or(StepFailure::Singular)?;
        return Ok((-(adj_f1 + adj_g * d_lambda) * (1.0 / det), d_lambda));
    }
    let b_inv = if l.b_maybe_bordered {
        linalg::inverse_maybe_bordered(&l.b)
    } else {
        linalg::inverse(&l.b)
    }
    .ok_or(StepFailure::Singular)?;
    let (b_f1, b_g) = (b_inv * l.f1, b_inv * l.g);
    let d_lambda =
        linalg::solve(&(l.c * b_g), &(l.f2 - l.c * b_f1)).ok_or(StepFailure::Singular)?;
    Ok((-(b_f1 + b_g * d_lambda), d_lambda))
}

/// Solves the one equation `f(x) = 0` from `x`, in place; `f` returns the value and the
/// derivative. Same stopping rule as [`solve`]. Returns the last increment as computed, before
/// its addition to `x` rounded it to `x`'s grid: a caller may apply it to finer quantities
/// derived from `x` at the last evaluation (DD's solve for the driver's speed applies it to
/// q̇₁'s components), which leaves an error of the order of its square and of one sign. So the
/// last increment must also be at most `linear_max · (1 + |x|)`: Newton's error estimate,
/// which `cfg.left_tol` bounds, does not see the other second-order terms of that use.
#[inline]
pub fn solve_one(
    cfg: &NewtonConfig,
    x: &mut f64,
    linear_max: f64,
    mut f: impl FnMut(f64) -> (f64, f64),
) -> Result<f64, StepFailure> {
    let mut previous = f64::INFINITY;
    let mut increment = f64::INFINITY;
    for it in 1..=cfg.max_iter {
        let (value, slope) = f(*x);
        if slope == 0.0 {
            return counted(it, Err(StepFailure::Singular));
        }
        let dx = -value / slope;
        *x += dx;
        increment = dx.abs();
        if !increment.is_finite() {
            return counted(it, Err(StepFailure::NonFinite));
        }
        let (left, scale) = (NewtonConfig::left_after(increment, previous), 1.0 + x.abs());
        if cfg.converged(increment, (left, increment), previous, scale)
            && increment <= linear_max * scale
        {
            return counted(it, Ok(dx));
        }
        previous = increment;
    }
    counted(cfg.max_iter, Err(StepFailure::NewtonDiverged { iterations: cfg.max_iter, increment }))
}

impl NewtonConfig {
    /// The error an iteration whose (max-norm) increment was `increment`, after one of
    /// `previous`, leaves, for Newton's quadratic convergence.
    #[inline]
    fn left_after(increment: f64, previous: f64) -> f64 {
        // e_{k+1} ≈ C e_k² with C ≈ δ_k/δ_{k−1}², so the error left after this update is
        // about δ_k³/δ_{k−1}². After the first iteration there is no δ_{k−1} (previous = ∞)
        // to estimate C from: a lucky small first increment still leaves an error of order
        // C δ₁², taken with C = 1 (the nonlinearities here are scaled by h, so C ≲ 1).
        if previous.is_finite() {
            increment * (increment / previous).powi(2)
        } else {
            increment * increment
        }
    }

    /// Whether an iteration whose (max-norm) increment was `increment`, after one of
    /// `previous`, has converged for unknowns of size `scale`, given the error it is estimated
    /// to leave and the increment whose size says whether that estimate holds (`(left,
    /// regime)`).
    #[inline]
    pub(crate) fn converged(
        &self,
        increment: f64,
        (left, regime): (f64, f64),
        previous: f64,
        scale: f64,
    ) -> bool {
        // Trusting the estimate (only once the increment it rests on is small enough to be in
        // the quadratic regime) saves the iteration that would only verify. Trusting δ₁ itself
        // would accept δ₁ = 10⁻⁶ with an error of 10⁻¹²; never trusting it would make a tiny
        // step (h = 10⁻⁶) iterate into the round-off noise of DD's discrete gradient.
        increment <= self.tol * scale
            || (regime <= QUADRATIC_REGIME * scale && left <= self.left_tol * scale)
            || (increment <= self.stagnation_tol * scale && increment >= 0.5 * previous)
    }
}
