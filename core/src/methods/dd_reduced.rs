//! DD's reduced Newton solve where V is quadratic (DD-AVF has its own split,
//! `dd_avf_coupled`, which needs no Newton for the passenger): the same equations as [`discrete_derivative_step`](super::dd::discrete_derivative_step), in two
//! unknowns instead of `N + R`.
//!
//! The midpoint constraint `A(q̄)(q̇₀ + q̇₁) = 0` says that `s = q̇₀ + q̇₁` lies in the kernel of
//! `A(ζ̄) = [A_x(ζ̄) | 0]`, which on a coupled system is spanned by `(k̃(ζ̄), 0)` and the
//! driver's axis (MATH.md §1). So `s = (w k̃(ζ̄), σ)` with two unknowns `(w, σ)`, the
//! constraint holds by construction (to round-off), and projecting the momentum equation
//! `s − 2q̇₀ + h∇̄V = h A(q̄)ᵀλ` on the two kernel directions removes λ:
//!
//! ```text
//! F₁ = k̃ · (s − 2q̇₀ + h∇̄V) = 0,   F₂ = σ − 2ζ̇₀ + h ∂_ζ∇̄V = 0,   ζ̄ = ζ₀ + hσ/4.
//! ```
//!
//! Newton then factors a 2×2 matrix, where the general path forms and inverts an N×N one and
//! an R×R Schur complement on every iteration; λ follows once, from the residual the
//! projection removed. `k̃` is not normalized: its components are the entries of `A`
//! (`(−a₂, a₁)` for one constraint, the cross product of the two rows for two), so no square
//! root enters the iteration.
//!
//! Used where V is quadratic (`cvt`, `particle`, the knife edge, the rolling disk): there the
//! driver's equation is affine in σ alone and, given σ, F₁ is affine in w, so Newton starts
//! from the exact solution up to DD's rounding term and takes one iteration. Same steps as
//! the general path to 10⁻¹³ (`tests/fast_path.rs`); speed in `docs/benchmarks.md`.

use super::dd::DiscreteGradient;
use crate::angle_tracker::AngleTracker;
use crate::newton::{NewtonConfig, solve_pair};
use crate::system::System;
use crate::{Matrix, State, StepFailure, Vector, linalg};

/// Whether the reduced solve applies to a system: V quadratic (then Newton's first guess is
/// exact), and a one-dimensional passenger kernel (`N = R + 2`) with one or two constraints,
/// which [`passenger_kernel`] covers. Where V_d is not quadratic (`cvt_pendulum`, the mobile
/// robot) both solves take two iterations, and the reduced one measured no faster.
pub(crate) const fn applies<S: System<N, R>, const N: usize, const R: usize>() -> bool {
    S::QUADRATIC_PASSENGER && S::QUADRATIC_DRIVER && N == R + 2 && (R == 1 || R == 2)
}

/// `(k̃, dk̃/dζ)`: a vector spanning the kernel of `A_x`, with zero driver component, from the
/// entries of `A = [A_x | 0]` and of `dA/dζ` (where it [`applies`]).
#[inline]
fn passenger_kernel<const N: usize, const R: usize>(
    a: &Matrix<R, N>,
    da: &Matrix<R, N>,
) -> (Vector<N>, Vector<N>) {
    let (mut k, mut dk) = (Vector::<N>::zeros(), Vector::<N>::zeros());
    if R == 1 {
        (k[0], k[1]) = (-a[(0, 1)], a[(0, 0)]);
        (dk[0], dk[1]) = (-da[(0, 1)], da[(0, 0)]);
    } else if R == 2 {
        let cross = |u: [f64; 3], v: [f64; 3]| {
            [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        };
        let row = |m: &Matrix<R, N>, r: usize| [m[(r, 0)], m[(r, 1)], m[(r, 2)]];
        let c = cross(row(a, 0), row(a, 1));
        let (d1, d2) = (cross(row(da, 0), row(a, 1)), cross(row(a, 0), row(da, 1)));
        for i in 0..3 {
            (k[i], dk[i]) = (c[i], d1[i] + d2[i]);
        }
    }
    (k, dk)
}

/// What the last Newton linearization computed, from which the step's q̇₁ and λ follow.
struct Last<const N: usize> {
    /// `q̇₀ + q̇₁` there.
    s: Vector<N>,
    /// Its derivatives with respect to w and σ.
    ds: [Vector<N>; 2],
    /// `s − 2q̇₀ + h∇̄V`, which is `h A(q̄)ᵀλ` at the solution.
    residual: Vector<N>,
    /// Its derivatives with respect to w and σ.
    d_residual: [Vector<N>; 2],
}

/// One step of the discrete-derivative family, solved in the kernel's two unknowns (see the
/// module's doc); `gradient` as for the general path. Only where it [`applies`].
#[inline]
pub(crate) fn reduced_step<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    h: f64,
    newton: &NewtonConfig,
    mut gradient: impl DiscreteGradient<N, R>,
) -> Result<(), StepFailure> {
    let (q0, v0) = (st.q, st.v);
    let z0 = q0[N - 1];
    let (mut mid, mut end) = (AngleTracker::new(), AngleTracker::new());
    // Newton's first guess: the solution of the equations with ∇̄V replaced by ∇V(q̄), which
    // differs from DD's only by Gonzalez's rounding term, so that
    // Newton's first increment is round-off and one iteration suffices. σ first, from the
    // driver's affine equation `σ − 2ζ̇₀ + h V_d'(ζ₀ + hσ/4) = 0`; then w from F₁, affine in w.
    let sigma = (2.0 * v0[N - 1] - h * st.gradient(sys)[N - 1])
        / (1.0 + 0.25 * h * h * sys.driver_potential_d2(z0));
    let at_mid = mid.terms(sys, z0 + 0.25 * h * sigma);
    let (k, _) = passenger_kernel(&at_mid.constraint, &at_mid.constraint_d);
    let slope = k.norm_squared() + 0.25 * h * h * k.dot(&(sys.passenger_hessian(&q0) * k));
    let passenger = 2.0 * v0 - h * sys.passenger_gradient(&q0);
    let mut x = Vector::<2>::new(k.dot(&passenger) / slope, sigma);
    let mut last = None;
    let mut linearize = |x: &Vector<2>| {
        let (w, sigma) = (x[0], x[1]);
        let at_mid = mid.terms(sys, z0 + 0.25 * h * sigma);
        let (k, dk) = passenger_kernel(&at_mid.constraint, &at_mid.constraint_d);
        let mut s = k * w;
        s[N - 1] = sigma;
        let (grad, jac) = gradient(&(s * (0.5 * h)), &at_mid, &mut end);
        let residual = s - 2.0 * v0 + h * grad;
        // ds/dw = k̃, ds/dσ = (w dk̃/dζ · h/4, 1); the residual moves by (I + h jac) ds.
        let mut ds_sigma = dk * (0.25 * h * w);
        ds_sigma[N - 1] = 1.0;
        let (dr_w, dr_sigma) = (k + h * (jac * k), ds_sigma + h * (jac * ds_sigma));
        let value = Vector::<2>::new(k.dot(&residual), residual[N - 1]);
        let j = Matrix::<2, 2>::new(
            k.dot(&dr_w),
            k.dot(&dr_sigma) + 0.25 * h * dk.dot(&residual),
            dr_w[N - 1],
            dr_sigma[N - 1],
        );
        last = Some(Last { s, ds: [k, ds_sigma], residual, d_residual: [dr_w, dr_sigma] });
        (value, j)
    };
    let dx = solve_pair(newton, &mut x, &mut linearize)?;
    let Last { s: s_lin, ds: [ds_w, ds_sigma], residual, d_residual: [dr_w, dr_sigma] } =
        last.ok_or(StepFailure::Singular)?;
    // Newton's last increment, as solved, applied to q̇₁'s components rather than to the
    // rounded (w, σ): added to w, it would be rounded to w's grid, whose ulp is that of
    // |q̇₀ + q̇₁|, and that rounding, left in the energy balance, made DD's energy drift
    // linearly on the knife edge (2·10⁻¹⁸ per step; `dd_roundoff`). The general path rounds
    // q̇₁'s own components, a finer grid, and so does this.
    let v1 = (s_lin - v0) + (ds_w * dx[0] + ds_sigma * dx[1]);
    // h A(q̄)ᵀλ is the residual, taken from the last linearization to the solution.
    let force = (residual + dr_w * dx[0] + dr_sigma * dx[1]) * (1.0 / h);
    // With A(ζ̄) at the solution (a rotation by Newton's last increment in σ): the last
    // linearization's is off by that increment, which would show in λ.
    let a = mid.terms(sys, z0 + 0.25 * h * x[1]).constraint;
    st.lambda = linalg::solve(&(a * a.transpose()), &(a * force)).ok_or(StepFailure::Singular)?;
    st.advance_to((v0 + v1) * (0.5 * h), v1);
    // What the next step starts from and the integrals at q₁ need.
    let at_q1 = end.terms(sys, st.q[N - 1]);
    st.remember_at_end(at_q1.gradient(sys, &st.q), at_q1.constraint, at_q1.potential);
    Ok(())
}
