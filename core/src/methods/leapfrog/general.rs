//! LF on the general class (`docs/model.md` §3): the kicks divided by M, the multiplier from
//! the r×r system `A M⁻¹ Aᵀ`,
//!
//! ```text
//! q̇_½ = q̇₀ + (h/2) M⁻¹(−∇V(q₀) + A(q₀)ᵀ λ₀),     q₁ = q₀ + h q̇_½
//! w = q̇_½ − (h/2) M⁻¹∇V(q₁),    (A₁ M⁻¹ A₁ᵀ) λ₁ = −(2/h) A₁ w,    q̇₁ = w + (h/2) M⁻¹A₁ᵀ λ₁
//! ```

use super::Leapfrog;
use crate::linalg;
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::GeneralStepper;
use crate::model::mechanical::Mechanical;
use crate::{State, StepFailure};

impl GeneralStepper for Leapfrog {
    #[inline]
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let mass = sys.mass();
        let f0 = mem.forces(sys, &st.q);
        let dv_half = 0.5 * h * mass.solve(&(f0.constraint.transpose() * st.lambda - f0.gradient));
        st.advance_q_parts(h * st.v, h * dv_half);
        let f1 = sys.forces(&st.q);
        let a1 = f1.constraint;
        let m_at = mass.solve_columns(&a1.transpose());
        let kick_g = -0.5 * h * mass.solve(&f1.gradient);
        let w = st.v + dv_half + kick_g;
        let lambda1 =
            linalg::solve(&(a1 * m_at), &(a1 * w)).ok_or(StepFailure::Singular)? * (-2.0 / h);
        let kick = kick_g + 0.5 * h * (m_at * lambda1);
        if !(kick.sum() + lambda1.sum()).is_finite() {
            return Err(StepFailure::NonFinite);
        }
        st.advance_v_parts(kick, dv_half);
        st.lambda = lambda1;
        mem.remember(&st.q, f1);
        Ok(())
    }
}
