//! DD on the general class (`docs/model.md` §3): with M and A(q), unknowns `(q̇₁, λ)`,
//! `s = q̇₀ + q̇₁`, `Δq = (h/2) s`, `q̄ = q₀ + Δq/2`,
//!
//! ```text
//! M (q̇₁ − q̇₀) = h (−∇̄V(q₀, q₁) + A(q̄)ᵀ λ),     q₁ = q₀ + Δq,     0 = A(q̄) s / 2
//! ```
//!
//! with Gonzalez's discrete gradient `∇̄V = ∇V(q̄) + c Δq/|Δq|²`, `c = V(q₁) − V(q₀) − ∇V(q̄)·Δq`.
//! `H = ½ q̇ᵀM q̇ + V` is conserved exactly: `H₁ − H₀ = (h/2) λ·A(q̄)s = 0`. Solved by Newton
//! with the exact Jacobian, at DD's tighter stopping rule.

use super::Dd;
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::GeneralStepper;
use crate::model::mechanical::Mechanical;
use crate::solver::newton::{Linearization, solve};
use crate::{Matrix, State, StepFailure, Vector};

impl GeneralStepper for Dd {
    #[inline]
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let mass = sys.mass();
        let (q0, v0) = (st.q, st.v);
        let f0 = mem.forces(sys, &q0);
        let v_q0 = mem.potential(sys, &q0);
        let m = mass.matrix();
        let momentum0 = mass.times(&v0);
        let quadratic = sys.quadratic_potential();
        let linearize = |v1: &Vector<N>, lambda: &Vector<R>| {
            let s = v0 + v1;
            let dq = s * (0.5 * h);
            let q_mid = q0 + 0.5 * dq;
            let (mid, d_mid) = sys.forces_and_derivatives(&q_mid);
            let (grad, jac) =
                gonzalez(sys, (&q0, v_q0), &dq, h, (&mid, &d_mid.hessian), quadratic);
            let a_mid = mid.constraint;
            Linearization {
                f1: mass.times(v1) - momentum0 + h * grad - h * (a_mid.transpose() * lambda),
                f2: a_mid * s * 0.5,
                // −h A(q̄)ᵀλ depends on q̇₁ through q̄ (dq̄ = (h/4) dq̇₁).
                b: m + jac * h - d_mid.force_jacobian(lambda) * (0.25 * h * h),
                g: a_mid.transpose() * (-h),
                c: a_mid * 0.5 + d_mid.constraint_jacobian(&s) * (0.125 * h),
                b_maybe_bordered: false,
                affine_but_for_the_driver: false,
            }
        };
        let mut v1 = v0 + h * mass.solve(&(f0.constraint.transpose() * st.lambda - f0.gradient));
        let mut lambda = st.lambda;
        solve(&self.newton, &mut v1, &mut lambda, linearize)?;
        st.advance_to((v0 + v1) * (0.5 * h), v1);
        st.lambda = lambda;
        mem.remember(&st.q, sys.forces(&st.q));
        mem.remember_potential(&st.q, sys.potential(&st.q));
        Ok(())
    }
}

/// Gonzalez's `∇̄V(q₀, q₀ + Δq)` and its derivative with respect to q̇₁ (`dΔq = (h/2) dq̇₁`,
/// `dq̄ = (h/4) dq̇₁`), given `∇V(q̄)` and `∇²V(q̄)`. As on the class (`gonzalez.rs`): where
/// V is quadratic, c is only the rounding of `q₁ = q₀ + Δq` and is kept, which ties H to the
/// stored positions, but its derivatives are left out; elsewhere a c that is its own
/// rounding is dropped (divided by |Δq|² it would not stay small near rest).
#[inline]
fn gonzalez<S: Mechanical<N, R>, const N: usize, const R: usize>(
    sys: &S,
    (q0, v_q0): (&Vector<N>, f64),
    dq: &Vector<N>,
    h: f64,
    (mid, hess_mid): (&crate::model::mechanical::Forces<N, R>, &Matrix<N, N>),
    quadratic: bool,
) -> (Vector<N>, Matrix<N, N>) {
    let g_mid = mid.gradient;
    let jac_mid = hess_mid * (0.25 * h);
    let dq2 = dq.norm_squared();
    if dq2 == 0.0 {
        return (g_mid, jac_mid);
    }
    let q1 = q0 + dq;
    let u = dq / dq2;
    let (v_q1, g_dq) = (sys.potential(&q1), g_mid.dot(dq));
    let c = v_q1 - v_q0 - g_dq;
    if quadratic {
        return (g_mid + c * u, jac_mid);
    }
    if c.abs() <= 8.0 * f64::EPSILON * (v_q1.abs() + v_q0.abs() + g_dq.abs()) {
        return (g_mid, jac_mid);
    }
    // d(Δq/|Δq|²)/dq̇₁ = (h/2)(I − 2 Δq Δqᵀ/|Δq|²)/|Δq|²; dc/dq̇₁ = (h/2)[∇V(q₁) − ∇V(q̄) − ½∇²V(q̄)Δq].
    let du = (Matrix::<N, N>::identity() - 2.0 * (dq * u.transpose())) * (0.5 * h / dq2);
    let dc = (sys.gradient(&q1) - g_mid - 0.5 * (hess_mid * dq)) * (0.5 * h);
    (g_mid + c * u, jac_mid + du * c + u * dc.transpose())
}
