//! `leapfrog`: the nonholonomic leap-frog (McLachlan–Perlmutter) in velocity-Verlet form.
//!
//! Explicit up to an R×R linear solve for the new multiplier; `λ₀` is carried from the
//! previous step (`docs/model.md` §3, corrections 2 and 6).

mod general;

use crate::linalg;
use crate::methods::integrator::{Integrator, MethodInfo, Stepper};
use crate::methods::memory::EndOfStep;
use crate::model::system::{System, constraint_force};
use crate::{InputError, State, StepFailure, Vector};

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
    composed_order_limit: Some(4),
    class_only: None,
    instrument: false,
    symmetric_at: None,
    external: false,
    by_tableau: false,
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
    fn symmetric(&self) -> bool {
        true
    }
}

impl Stepper for Leapfrog {
    type Memory<const N: usize, const R: usize> = EndOfStep<N, R>;
    // Always inlined, so that in a run the integrals at q₁ share the step's sin/cos of ζ₁.
    #[inline(always)]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut Self::Memory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let (g0, a0) = mem.gradient_and_constraint(sys, st);
        let dv_half = 0.5 * h * (constraint_force(&a0, &st.lambda) - g0);
        let v_half = st.v + dv_half;
        // q₁ = q₀ + h q̇₀ + h Δq̇_½: q̇₀ enters last, as it is what the previous step just made.
        st.advance_q_parts(h * st.v, h * dv_half);
        let q1 = st.q;
        let at_q1 = sys.driver_terms(q1[N - 1]);
        let (a1, g1) = (at_q1.constraint, at_q1.gradient(sys, &q1));
        let w = v_half - 0.5 * h * g1;
        // v₁ = w + (h/2) A₁ᵀ λ₁ with A₁ v₁ = 0. A singular A₁A₁ᵀ gives NaN here and is told
        // apart below: checking it only once the whole update is known keeps sin ζ₁ (in A₁)
        // and cos ζ₁ (in ∇V) in one block, where the compiler makes them a single sincos.
        let solved = linalg::solve(&(a1 * a1.transpose()), &(a1 * w));
        let lambda1 = solved.unwrap_or(Vector::<R>::repeat(f64::NAN)) * (-2.0 / h);
        // q̇₁ = w + (h/2) A₁ᵀλ₁ = q̇₀ + Δq̇_½ + (h/2)(A₁ᵀλ₁ − ∇V(q₁)), as increments.
        let kick = 0.5 * h * (constraint_force(&a1, &lambda1) - g1);
        if !(kick.sum() + lambda1.sum()).is_finite() {
            return Err(if solved.is_none() {
                StepFailure::Singular
            } else {
                StepFailure::NonFinite
            });
        }
        st.advance_v_parts(kick, dv_half);
        st.lambda = lambda1;
        mem.remember(st, a1, at_q1.potential, g1[N - 1]);
        Ok(())
    }
}
