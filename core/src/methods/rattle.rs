//! `rattle`: McLachlan & Perlmutter's nonholonomic RATTLE (J. Nonlinear Sci. 16, 2006,
//! eq. (4.18)), written as they write it, in momenta `p = M q̇` (`docs/model.md` §3):
//!
//! ```text
//! q_½ = q₀ + (h/2) M⁻¹p₀
//! p₁  = p₀ − (h/2)(∂_q H(q_½, p₀) + ∂_q H(q_½, p₁)) + h A(q_½)ᵀ λ
//! q₁  = q_½ + (h/2) M⁻¹p₁,      0 = A(q₁) M⁻¹p₁
//! ```
//!
//! the constraint force at the midpoint, the constraint imposed at q₁. Second order and
//! symmetric. With M constant, `∂_q H(q, p) = ∇V(q)` whatever p, and the map is the same as
//! DLA^{0,1}'s (a test checks that they agree to round-off); the two part where M depends on
//! q. Solved by Newton in `(p₁, λ)`; on a class system through its general form.

use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::{GeneralStepper, Integrator, MethodInfo, Stepper};
use crate::model::mechanical::{General, Mechanical};
use crate::model::system::System;
use crate::solver::newton::{Linearization, NewtonConfig, solve};
use crate::{InputError, Matrix, State, StepFailure};

/// Nonholonomic RATTLE.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Rattle {
    /// Newton's settings.
    pub newton: NewtonConfig,
}

static INFO: MethodInfo = MethodInfo {
    id: "rattle",
    name: "Nonholonomic RATTLE (McLachlan–Perlmutter)",
    params: &[],
    order: 2,
    reference: "McLachlan & Perlmutter, J. Nonlinear Sci. 16 (2006), eq. (4.18)",
    implicit: true,
    composed_order_limit: None,
    class_only: None,
    instrument: false,
    symmetric_at: None,
    external: false,
    by_tableau: false,
};

impl Integrator for Rattle {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(_params: &[f64]) -> Result<Self, InputError> {
        Ok(Self::default())
    }
    fn label(&self) -> String {
        "RATTLE".into()
    }
    fn symmetric(&self) -> bool {
        true
    }
}

impl Stepper for Rattle {
    type Memory<const N: usize, const R: usize> = GeneralMemory<N, R>;
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        self.step_general(&General(sys), st, mem, h)
    }
}

impl GeneralStepper for Rattle {
    #[inline]
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let mass = sys.mass();
        let p0 = mass.times(&st.v);
        let q_half = st.q + 0.5 * h * mass.solve(&p0);
        let half = sys.forces(&q_half);
        let g = half.constraint.transpose() * (-h);
        let mut p1 = p0 - h * half.gradient + h * (half.constraint.transpose() * st.lambda);
        let mut lambda = st.lambda;
        solve(&self.newton, &mut p1, &mut lambda, |p1, lambda| {
            let v1 = mass.solve(p1);
            let q1 = q_half + 0.5 * h * v1;
            let (f1, d1) = sys.forces_and_derivatives(&q1);
            let a1 = f1.constraint;
            let dc = a1 + (0.5 * h) * d1.constraint_jacobian(&v1);
            Linearization {
                f1: p1 - p0 + h * half.gradient + g * lambda,
                f2: a1 * v1,
                b: Matrix::<N, N>::identity(),
                g,
                c: mass.solve_columns(&dc.transpose()).transpose(),
                b_maybe_bordered: true,
                affine_but_for_the_driver: false,
            }
        })?;
        let v1 = mass.solve(&p1);
        st.advance_to(0.5 * h * (st.v + v1), v1);
        st.lambda = lambda;
        mem.remember(&st.q, sys.forces(&st.q));
        Ok(())
    }
}
