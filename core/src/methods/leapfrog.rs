//! `leapfrog`: the nonholonomic leap-frog (McLachlan–Perlmutter) in velocity-Verlet form.
//!
//! Explicit up to an R×R linear solve for the new multiplier; `λ₀` is carried from the
//! previous step (MATH.md §3, corrections 2 and 6).

use crate::linalg;
use crate::method::{Integrator, MethodInfo};
use crate::system::System;
use crate::{InputError, State, StepFailure};

/// Nonholonomic leap-frog (no parameters).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Leapfrog;

static INFO: MethodInfo = MethodInfo {
    id: "leapfrog",
    name: "Nonholonomic leap-frog (LF)",
    params: &[],
    order: 2,
    reference: "McLachlan & Perlmutter, J. Nonlinear Sci. 16 (2006); Modin & Verdier §2",
    implicit: false,
};

impl Integrator for Leapfrog {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(_params: &[f64]) -> Result<Self, InputError> {
        Ok(Self)
    }
    fn label(&self) -> String {
        "LF".into()
    }
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let a0 = sys.constraint(st.q[N - 1]);
        let dv_half = 0.5 * h * (a0.transpose() * st.lambda - sys.gradient(&st.q));
        let v_half = st.v + dv_half;
        st.advance_q(h * v_half);
        let q1 = st.q;
        let a1 = sys.constraint(q1[N - 1]);
        let g1 = sys.gradient(&q1);
        let w = v_half - 0.5 * h * g1;
        // v₁ = w + (h/2) A₁ᵀ λ₁ with A₁ v₁ = 0.
        let lambda1 = linalg::solve(&(a1 * a1.transpose()), &(a1 * w))
            .ok_or(StepFailure::Singular)?
            * (-2.0 / h);
        // q̇₁ = w + (h/2) A₁ᵀλ₁, as an increment.
        st.advance_v(dv_half + 0.5 * h * (a1.transpose() * lambda1 - g1));
        st.lambda = lambda1;
        Ok(())
    }
}
