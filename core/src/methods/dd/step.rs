//! The discrete-derivative family's step (`docs/model.md` §3) for a given discrete
//! gradient, solved by Newton in `(q̇₁, λ)`: the general path of DD (Gonzalez's gradient)
//! and DD-AVF (the average vector field), starting from Euler's step with the driver's speed
//! extrapolated from its last steps
//! ([`DriverHistory`](super::driver_history::DriverHistory)).

use super::memory::DdMemory;
use crate::model::system::{DriverTerms, System};
use crate::solver::angle_tracker::AngleTracker;
use crate::solver::newton::{Linearization, NewtonConfig, solve};
use crate::{Matrix, State, StepFailure, Vector};

/// A discrete gradient as the discrete-derivative steps take it: `(Δq, the driver's terms at
/// ζ̄, a tracker of ζ₁) ↦ (∇̄V(q₀, q₀ + Δq), its derivative with respect to q̇₁)`.
pub(crate) trait DiscreteGradient<const N: usize, const R: usize>:
    FnMut(&Vector<N>, &DriverTerms<N, R>, &mut AngleTracker) -> (Vector<N>, Matrix<N, N>)
{
}

impl<F, const N: usize, const R: usize> DiscreteGradient<N, R> for F where
    F: FnMut(&Vector<N>, &DriverTerms<N, R>, &mut AngleTracker) -> (Vector<N>, Matrix<N, N>)
{
}

/// One step of the discrete-derivative family (`docs/model.md` §3) for a given discrete gradient:
/// `gradient(Δq, terms at ζ̄, tracker of ζ₁)` returns `∇̄V(q₀, q₀ + Δq)` and its derivative
/// with respect to `q̇₁`; if it evaluates the driver at ζ₁ through the tracker, the terms at
/// the step's end follow from its last iterate by a tiny rotation. `diagonal_gradient_jacobian`
/// says whether that derivative can be diagonal (then Newton's matrix is checked for the
/// shape that [`linalg::inverse_maybe_bordered`](crate::linalg) inverts cheaply). The
/// general `(q̇₁, λ)` solve, shared by `dd` (Gonzalez) and `dd_avf` (average vector field); DD's
/// faster solves are [`closed_form`](super::closed_form) (DD-AVF's too) and
/// [`reduced`](super::reduced).
#[inline]
pub(crate) fn discrete_derivative_step<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    mem: &mut DdMemory<N, R>,
    h: f64,
    newton: &NewtonConfig,
    diagonal_gradient_jacobian: bool,
    mut gradient: impl DiscreteGradient<N, R>,
) -> Result<(), StepFailure> {
    let (q0, v0) = (st.q, st.v);
    let (g0, a0) = mem.end.gradient_and_constraint(sys, st);
    let euler = (v0 + h * (a0.transpose() * st.lambda - g0), st.lambda);
    let (mut mid, mut end) = (AngleTracker::new(), AngleTracker::new());
    let mut linearize = |v1: &Vector<N>, lambda: &Vector<R>| {
        let s = v0 + v1;
        let dq = s * (0.5 * h);
        let z_mid = q0[N - 1] + 0.5 * dq[N - 1];
        let at_mid = mid.terms(sys, z_mid);
        let (a_mid, da_mid) = (at_mid.constraint, at_mid.constraint_d);
        let (grad, jac) = gradient(&dq, &at_mid, &mut end);
        let mut b = Matrix::<N, N>::identity() + jac * h;
        // −h A(q̄)ᵀλ depends on q̇₁ through ζ̄ (dζ̄ = (h/4) dζ̇₁).
        let dforce = da_mid.transpose() * lambda * (-h * 0.25 * h);
        let mut c = a_mid * 0.5;
        let dcol = da_mid * s * (0.125 * h);
        for i in 0..N {
            b[(i, N - 1)] += dforce[i];
        }
        for r in 0..R {
            c[(r, N - 1)] += dcol[r];
        }
        Linearization {
            f1: v1 - v0 + h * grad - h * (a_mid.transpose() * lambda),
            f2: a_mid * s * 0.5,
            b,
            g: a_mid.transpose() * (-h),
            c,
            b_maybe_bordered: diagonal_gradient_jacobian,
            affine_but_for_the_driver: false,
        }
    };
    // Euler's guess with the driver's speed extrapolated from its last steps where they are
    // known (see `DriverHistory`); Euler's own if Newton fails from it.
    let extrapolated = mem.history.guess(&q0, &v0, h).map(|zeta_dot| {
        let mut v1 = euler.0;
        v1[N - 1] = zeta_dot;
        (v1, euler.1)
    });
    let (mut v1, mut lambda) = extrapolated.unwrap_or(euler);
    let mut fallback = extrapolated.is_some();
    // One call site, so that `solve` and the linearization stay inlined.
    loop {
        match solve(newton, &mut v1, &mut lambda, &mut linearize) {
            Ok(_) => break,
            Err(_) if fallback => (v1, lambda, fallback) = (euler.0, euler.1, false),
            Err(failure) => return Err(failure),
        }
    }
    st.advance_to((v0 + v1) * (0.5 * h), v1);
    st.lambda = lambda;
    mem.history.record((&q0, &v0), h, (&st.q, &st.v));
    // What the next step starts from and the integrals at q₁ need.
    let at_q1 = end.terms(sys, st.q[N - 1]);
    mem.end.remember(st, at_q1.constraint, at_q1.potential, at_q1.potential_d1);
    Ok(())
}
