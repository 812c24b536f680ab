//! `reference`: the reference solve taken one step at a time, so that it runs as a method
//! and every instrument of a run measures it (its integrals, observables, a Poincaré
//! section, beside the methods under test). Each step solves the reduced ODE
//! (`docs/model.md` §1) over h with Dop853 at tolerance 10⁻¹⁵ ([`dop853_step`]): adaptive
//! inside the step, exact to that tolerance at its end.
//!
//! It is an instrument, not a method under study: neither reversible nor constraint-
//! preserving (it drifts off the constraint by round-off), of no order in h, left out of
//! [`Method::all`](crate::Method::all) and so of the default runs, the cross-product tests
//! and the scorecard's defaults; asked for by its id. Each step allocates the solver's
//! vectors (ode_solvers' Dop853 works on heap vectors of 2N): a few hundred nanoseconds beside
//! the sixty-odd evaluations it takes.

use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::{GeneralStepper, Integrator, MethodInfo, Stepper};
use crate::methods::memory::EndOfStep;
use crate::model::mechanical::{General, Mechanical};
use crate::model::system::System;
use crate::solver::reduced_ode::{TOL, dop853_step};
use crate::{InputError, State, StepFailure};

/// The reference solve, one step at a time (no parameters).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ReferenceStep;

static INFO: MethodInfo = MethodInfo {
    id: "reference",
    name: "Reference: Dop853 at tolerance 1e-15 inside each step",
    params: &[],
    order: 8,
    reference: "Hairer, Nørsett & Wanner, Solving ODEs I, §II.10 (DOP853)",
    implicit: false,
    composed_order_limit: None,
    class_only: None,
    instrument: true,
    symmetric_at: None,
    external: false,
    by_tableau: false,
};

impl Integrator for ReferenceStep {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(_params: &[f64]) -> Result<Self, InputError> {
        Ok(Self)
    }
    fn label(&self) -> String {
        "reference".into()
    }
}

/// One step of any system: the solve, then the multiplier at the end.
#[inline]
fn step<S: Mechanical<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    h: f64,
) -> Result<(), StepFailure> {
    let (q1, v1) = dop853_step(sys, &st.q, &st.v, h, TOL)?;
    st.advance(q1 - st.q, v1 - st.v);
    st.lambda = sys.acceleration(&st.q, &st.v).ok_or(StepFailure::Singular)?.1;
    Ok(())
}

impl Stepper for ReferenceStep {
    type Memory<const N: usize, const R: usize> = EndOfStep<N, R>;
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        _memory: &mut EndOfStep<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        step(&General(sys), st, h)
    }
}

impl GeneralStepper for ReferenceStep {
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        _memory: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        step(sys, st, h)
    }
}
