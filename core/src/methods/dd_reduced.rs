//! DD's reduced Newton solve on the coupled systems: the same equations as
//! [`discrete_derivative_step`](super::dd::discrete_derivative_step), in two unknowns instead
//! of `N + R`.
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
//! root enters the iteration. Gonzalez's gradient is written here again, with its derivative
//! taken along the two directions of `s` only ([`gonzalez`]): Newton needs no N×N Jacobian.
//!
//! Where V is quadratic (`cvt`, `particle`, the knife edge, the rolling disk) the driver's
//! equation is affine in σ alone and, given σ, F₁ is affine in w: the step has a closed form
//! ([`exact_energy`](super::exact_energy)), and this solve is not used. Where V_d is not
//! quadratic Newton takes two iterations, from the driver's extrapolated speed; that pays on
//! the mobile robot (two constraints, whose `(q̇₁, λ)` solve inverts a dense 4×4 matrix and a
//! 2×2 one on every iteration), not on `cvt_pendulum` (see [`applies`]). Same steps as the
//! general path to 10⁻¹³ (`tests/fast_path.rs`); speed in `docs/benchmarks.md`.

use super::dd::{Correction, gonzalez_value};
use crate::angle_tracker::AngleTracker;
use crate::newton::{NewtonConfig, solve_pair};
use crate::passenger_kernel::{self, kernel, kernel_and_derivative};
use crate::system::{DriverTerms, System};
use crate::{Matrix, State, StepFailure, Vector, linalg};

/// Whether DD takes the reduced solve on a system: U quadratic, two constraints whose
/// passenger kernel [`passenger_kernel`] covers, and V_d not quadratic (where V is quadratic
/// DD's step has a closed form, [`exact_energy`](super::exact_energy)). On `cvt_pendulum`
/// (one constraint) both solves take two iterations and the general one, whose 3×3 saddle
/// solve goes through the adjugate (`newton`), is the faster (the two measured the same before
/// it, 134 against 135 ns/step in `step_loop` on 2026-11-25); on the mobile robot the reduced
/// solve is 1.60× faster (132 against 211 in criterion, 2026-11-25): under issue 4's 2× for a
/// fast path, and kept because it takes DD there under issue 2's 150 ns
/// (`docs/benchmarks.md`).
pub(crate) const fn applies<S: System<N, R>, const N: usize, const R: usize>() -> bool {
    S::QUADRATIC_PASSENGER && !S::QUADRATIC_DRIVER && R == 2 && passenger_kernel::covers::<N, R>()
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

/// One DD step solved in the kernel's two unknowns (see the module's doc). Only where it
/// [`applies`].
#[inline]
pub(crate) fn reduced_step<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    h: f64,
    newton: &NewtonConfig,
) -> Result<(), StepFailure> {
    let (q0, v0) = (st.q, st.v);
    let z0 = q0[N - 1];
    let v_q0 = sys.passenger_potential(&q0) + st.driver_potential_and_constraint(sys).0;
    let (g0, a0) = st.gradient_and_constraint(sys);
    // K, the same at every q where U is quadratic.
    let stiffness = sys.passenger_hessian(&q0);
    let (mut mid, mut end) = (AngleTracker::new(), AngleTracker::new());
    // Given σ, F₁ is affine in w but for Gonzalez's correction: w = k̃·P / (|k̃|² + h²k̃ᵀKk̃/4).
    let passenger = 2.0 * v0 - h * g0;
    let w_for = |k: &Vector<N>| {
        k.dot(&passenger) / (k.norm_squared() + 0.25 * h * h * k.dot(&(stiffness * k)))
    };
    let euler_sigma = 2.0 * v0[N - 1] - h * g0[N - 1];
    // σ from the driver's last steps (`DriverHistory`), Euler's otherwise, and Euler's again if
    // Newton fails from the extrapolated one (as the general path does); w with k̃ at ζ₀,
    // whose A is known, so that the first iteration waits on no sine.
    let w = w_for(&kernel(&a0));
    let euler = Vector::<2>::new(w, euler_sigma);
    let (start, fallback) = match st.driver_history.guess(&q0, &v0, h) {
        Some(zeta_dot) => (Vector::<2>::new(w, v0[N - 1] + zeta_dot), Some(euler)),
        None => (euler, None),
    };
    let mut last = None;
    let mut linearize = |x: &Vector<2>| {
        let (w, sigma) = (x[0], x[1]);
        let at_mid = mid.terms(sys, z0 + 0.25 * h * sigma);
        let (k, dk) = kernel_and_derivative(&at_mid.constraint, &at_mid.constraint_d);
        let mut s = k * w;
        s[N - 1] = sigma;
        // ds/dw = k̃, ds/dσ = (w dk̃/dζ · h/4, 1).
        let mut ds_sigma = dk * (0.25 * h * w);
        ds_sigma[N - 1] = 1.0;
        let dq = s * (0.5 * h);
        let (grad, [j_w, j_sigma]) =
            gonzalez(sys, (&q0, v_q0), &dq, h, &at_mid, &mut end, [&k, &ds_sigma]);
        let residual = s - 2.0 * v0 + h * grad;
        // The residual moves by (I + h ∂∇̄V/∂q̇₁) ds.
        let (dr_w, dr_sigma) = (k + h * j_w, ds_sigma + h * j_sigma);
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
    let (mut x, mut fallback) = (start, fallback);
    // One call site, so that `solve_pair` and the linearization stay inlined.
    let dx = loop {
        match solve_pair(newton, &mut x, &mut linearize) {
            Ok(dx) => break dx,
            Err(_) if fallback.is_some() => (x, fallback) = (fallback.unwrap_or(x), None),
            Err(failure) => return Err(failure),
        }
    };
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
    st.driver_history.record((&q0, &v0), h, (&st.q, &st.v));
    // What the next step starts from and the integrals at q₁ need.
    let at_q1 = end.terms(sys, st.q[N - 1]);
    st.remember_at_end(at_q1.constraint, at_q1.potential, at_q1.potential_d1);
    Ok(())
}

/// Gonzalez's discrete gradient `∇̄V(q₀, q₀ + Δq)` ([`gonzalez_value`], as the general path
/// takes it) and its derivative with respect to q̇₁ along two directions, without forming the
/// N×N matrix: `∂∇̄V/∂q̇₁ · x` for each x. The driver's terms at ζ̄ are given, those at ζ₁
/// come from `end`.
#[inline]
fn gonzalez<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    (q0, v_q0): (&Vector<N>, f64),
    dq: &Vector<N>,
    h: f64,
    mid: &DriverTerms<N, R>,
    end: &mut AngleTracker,
    along: [&Vector<N>; 2],
) -> (Vector<N>, [Vector<N>; 2]) {
    let value = gonzalez_value(sys, (q0, v_q0), dq, mid, end);
    let hessian = mid.hessian(sys, &value.q_mid);
    let mut j = along.map(|x| hessian * x * (0.25 * h));
    if let Some(Correction { c, u, dq2, at_q1, .. }) = value.correction {
        // d(Δq/|Δq|²)/dq̇₁ · x = (h/2) (x − 2 Δq (u·x)) / |Δq|², times c; and u (dc/dq̇₁ · x),
        // where only the driver's share of dc is kept (U is quadratic here, its share
        // rounding): dc/dζ̇₁ = (h/2) [V_d'(ζ₁) − V_d'(ζ̄) − ½ V_d''(ζ̄) Δζ].
        let scale = c * (0.5 * h / dq2);
        let dc = (at_q1.potential_d1 - mid.potential_d1 - 0.5 * mid.potential_d2 * dq[N - 1])
            * (0.5 * h);
        for (j, x) in j.iter_mut().zip(along) {
            *j += (x - dq * (2.0 * u.dot(x))) * scale + u * (dc * x[N - 1]);
        }
    }
    (value.gradient, j)
}
