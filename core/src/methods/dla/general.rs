//! DLA^α on the general class (`docs/model.md` §3): with M and A(q),
//!
//! ```text
//! q_a = q₀ + (1−α) h q̇₀
//! M (q̇₁ − q̇₀) = −α h ∇V(q₀) − (1−α) h ∇V(q₁) + h A(q_a)ᵀ λ
//! q₁ = q_a + α h q̇₁,      0 = A(q₁) q̇₁
//! ```
//!
//! solved by Newton in `(q̇₁, λ)` with the exact Jacobian. On a class system (M = I,
//! A = A(ζ)) these are the class step's equations.

use super::Dla;
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::GeneralStepper;
use crate::model::mechanical::Mechanical;
use crate::solver::newton::{Linearization, solve};
use crate::{State, StepFailure};

impl GeneralStepper for Dla {
    #[inline]
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let (a, b) = (self.alpha, 1.0 - self.alpha);
        let mass = sys.mass();
        let (q0, v0) = (st.q, st.v);
        let g0 = mem.forces(sys, &q0).gradient;
        let q_a = q0 + b * h * v0;
        let a_qa = sys.constraint(&q_a);
        let momentum0 = mass.times(&v0);
        let g = a_qa.transpose() * (-h);
        // Explicit Euler's guess.
        let mut v1 = v0 + h * mass.solve(&(a_qa.transpose() * st.lambda - g0));
        let mut lambda = st.lambda;
        solve(&self.newton, &mut v1, &mut lambda, |v1, lambda| {
            let q1 = q_a + a * h * v1;
            let (f, d) = sys.forces_and_derivatives(&q1);
            Linearization {
                f1: mass.times(v1) - momentum0 + a * h * g0 + b * h * f.gradient + g * lambda,
                f2: f.constraint * v1,
                b: mass.matrix() + (a * b * h * h) * d.hessian,
                g,
                c: f.constraint + (a * h) * d.constraint_jacobian(v1),
                b_maybe_bordered: false,
                affine_but_for_the_driver: false,
            }
        })?;
        st.advance_to(b * h * v0 + a * h * v1, v1);
        st.lambda = lambda;
        mem.remember(&st.q, sys.forces(&st.q));
        Ok(())
    }
}
