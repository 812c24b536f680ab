//! Gonzalez's discrete gradient `∇̄V(q₀, q₁) = ∇V(q̄) + c Δq/|Δq|²`, with
//! `c = V(q₁) − V(q₀) − ∇V(q̄)·Δq` (`docs/model.md` §3): DD's discrete gradient, and its
//! derivative with respect to `q̇₁` for Newton.

use crate::model::system::{DriverTerms, System};
use crate::solver::angle_tracker::AngleTracker;
use crate::{Matrix, Vector};

/// Gonzalez's discrete gradient `∇̄V(q₀, q₁)` and its derivative with respect to `q̇₁`
/// (where `q₁ = q₀ + (h/2)(q̇₀ + q̇₁)`, so `dΔq = (h/2) dq̇₁`, `dq̄ = (h/4) dq̇₁`), given the
/// driver's terms at `ζ̄`; those at `ζ₁` come from `end`, which follows ζ₁ along Newton's
/// iterates.
///
/// Where a part of V is quadratic, `V(q₁) − V(q₀) = ∇V(q̄)·Δq` holds exactly for that part,
/// so its share of the correction `c` is only the rounding of `q₁ = q₀ + Δq`. That share is
/// kept in `c`: it feeds the rounding of the positions back into q̇₁, which keeps H
/// consistent with the rounded positions (without it, DD's energy error over 10⁸ knife-edge
/// steps at h = 0.31 grows linearly, to 20× more). But its derivatives are round-off and are
/// left out of the Jacobian, which only Newton's speed depends on: for a quadratic V
/// (knife edge, disk, `cvt`, `particle`) the Jacobian is then that of `∇V(q̄)`, and for
/// quadratic U (every test system) only the driver's share of `dc/dq̇₁` is kept.
#[inline]
pub(crate) fn discrete_gradient<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    (q0, v_q0): (&Vector<N>, f64),
    dq: &Vector<N>,
    h: f64,
    mid: &DriverTerms<N, R>,
    end: &mut AngleTracker,
) -> (Vector<N>, Matrix<N, N>) {
    let value = gonzalez_value(sys, (q0, v_q0), dq, mid, end);
    let hess_mid = mid.hessian(sys, &value.q_mid);
    let Some(Correction { c, u, dq2, q1, at_q1 }) = value.correction else {
        return (value.gradient, hess_mid * (0.25 * h));
    };
    // d(Δq/|Δq|²)/dq̇₁ = (h/2) (I − 2 Δq Δqᵀ/|Δq|²) / |Δq|²
    let du = (Matrix::<N, N>::identity() - 2.0 * (dq * u.transpose())) * (0.5 * h / dq2);
    let mut jac = hess_mid * (0.25 * h) + du * c;
    // dc/dq̇₁ = (h/2) [∇V(q₁) − ∇V(q̄) − ½ ∇²V(q̄) Δq]
    if sys.quadratic_passenger() {
        let dz = dq[N - 1];
        let dc = (at_q1.potential_d1 - mid.potential_d1 - 0.5 * mid.potential_d2 * dz) * (0.5 * h);
        for i in 0..N {
            jac[(i, N - 1)] += u[i] * dc;
        }
    } else {
        let dc = (at_q1.gradient(sys, &q1) - value.g_mid - 0.5 * (hess_mid * dq)) * (0.5 * h);
        jac += u * dc.transpose();
    }
    (value.gradient, jac)
}

/// The value of Gonzalez's discrete gradient at Δq, and what its derivatives are built from.
struct GonzalezValue<const N: usize, const R: usize> {
    /// `∇̄V(q₀, q₀ + Δq) = ∇V(q̄) + c u`.
    gradient: Vector<N>,
    /// `q̄ = q₀ + Δq/2`.
    q_mid: Vector<N>,
    /// `∇V(q̄)`.
    g_mid: Vector<N>,
    /// The correction's parts where its derivatives count: Δq ≠ 0 and V not quadratic.
    correction: Option<Correction<N, R>>,
}

/// Gonzalez's correction `c u` and what its derivatives need.
struct Correction<const N: usize, const R: usize> {
    /// `c = V(q₁) − V(q₀) − ∇V(q̄)·Δq`.
    c: f64,
    /// `u = Δq/|Δq|²`.
    u: Vector<N>,
    /// `|Δq|²`.
    dq2: f64,
    /// `q₁ = q₀ + Δq`.
    q1: Vector<N>,
    /// The driver's terms at ζ₁.
    at_q1: DriverTerms<N, R>,
}

/// Gonzalez's `∇̄V(q₀, q₀ + Δq)` (see [`discrete_gradient`] for the rounding term it keeps),
/// given `V(q₀)` and the driver's terms at ζ̄; those at ζ₁ through `end`.
#[inline]
fn gonzalez_value<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    (q0, v_q0): (&Vector<N>, f64),
    dq: &Vector<N>,
    mid: &DriverTerms<N, R>,
    end: &mut AngleTracker,
) -> GonzalezValue<N, R> {
    let q_mid = q0 + 0.5 * dq;
    let g_mid = mid.gradient(sys, &q_mid);
    let dq2 = dq.norm_squared();
    if dq2 == 0.0 {
        return GonzalezValue { gradient: g_mid, q_mid, g_mid, correction: None };
    }
    let q1 = q0 + dq;
    let u = dq / dq2;
    if sys.quadratic_passenger() && sys.quadratic_driver() {
        let c = sys.potential(&q1) - v_q0 - g_mid.dot(dq);
        return GonzalezValue { gradient: g_mid + c * u, q_mid, g_mid, correction: None };
    }
    let at_q1 = end.terms(sys, q1[N - 1]);
    let (v_q1, g_dq) = (sys.passenger_potential(&q1) + at_q1.potential, g_mid.dot(dq));
    let c = v_q1 - v_q0 - g_dq;
    if is_rounding(c, v_q1.abs() + v_q0.abs() + g_dq.abs()) {
        return GonzalezValue { gradient: g_mid, q_mid, g_mid, correction: None };
    }
    let correction = Some(Correction { c, u, dq2, q1, at_q1 });
    GonzalezValue { gradient: g_mid + c * u, q_mid, g_mid, correction }
}

/// Whether Gonzalez's `c = V(q₁) − V(q₀) − ∇V(q̄)·Δq`, whose terms add up to `size` in
/// absolute value, is its own rounding (c is O(|Δq|³), the rounding of its difference
/// O(ε|V|)). Such a c carries no value, and divided by |Δq|² it does not stay small: at rest at
/// an equilibrium DD's Jacobian came out singular, where every other method stays at rest
/// (`tests/it/at_rest.rs`). There the gradient is `∇V(q̄)`, which c changes by less than the
/// rounding of V.
#[inline]
fn is_rounding(c: f64, size: f64) -> bool {
    c.abs() <= 8.0 * f64::EPSILON * size
}
