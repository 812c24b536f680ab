//! DLA^{0,1} on the general class (`docs/model.md` §3): force and constraint force at the
//! midpoint `q_½ = q₀ + (h/2) q̇₀`, the constraint at q₁,
//!
//! ```text
//! M (q̇₁ − q̇₀) = −h ∇V(q_½) + h A(q_½)ᵀ λ,    q₁ = q_½ + (h/2) q̇₁,    0 = A(q₁) q̇₁
//! ```
//!
//! solved by Newton in `(q̇₁, λ)`: it is linear but for A(q₁).

use super::Dla01;
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::GeneralStepper;
use crate::model::mechanical::Mechanical;
use crate::solver::newton::{Linearization, solve};
use crate::{State, StepFailure};

impl GeneralStepper for Dla01 {
    #[inline]
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let mass = sys.mass();
        let q_half = st.q + 0.5 * h * st.v;
        let half = sys.forces(&q_half);
        let w = mass.times(&st.v) - h * half.gradient;
        let g = half.constraint.transpose() * (-h);
        let mut v1 = mass.solve(&(w + h * (half.constraint.transpose() * st.lambda)));
        let mut lambda = st.lambda;
        let m = mass.matrix();
        solve(&self.newton, &mut v1, &mut lambda, |v1, lambda| {
            let q1 = q_half + 0.5 * h * v1;
            let (f1, d1) = sys.forces_and_derivatives(&q1);
            let a1 = f1.constraint;
            Linearization {
                f1: mass.times(v1) - w + g * lambda,
                f2: a1 * v1,
                b: m,
                g,
                c: a1 + (0.5 * h) * d1.constraint_jacobian(v1),
                b_maybe_bordered: false,
                affine_but_for_the_driver: false,
            }
        })?;
        st.advance_to(0.5 * h * (st.v + v1), v1);
        st.lambda = lambda;
        mem.remember(&st.q, sys.forces(&st.q));
        Ok(())
    }
}
