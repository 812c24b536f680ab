//! RK4 on the general class (`docs/model.md` §3): the classical stages on the constrained ODE
//! with the multiplier eliminated, `M q̈ = −∇V + Aᵀλ(q, q̇)`
//! ([`Mechanical::acceleration`]).

use super::Rk4;
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::GeneralStepper;
use crate::model::mechanical::Mechanical;
use crate::{State, StepFailure};

impl GeneralStepper for Rk4 {
    #[inline]
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let f = |q, v| sys.acceleration(&q, &v).map(|(a, _)| a).ok_or(StepFailure::Singular);
        // First same as last.
        let first = mem.acceleration(&st.q, &st.v);
        let (dq, dv) = super::stages(f, (st.q, st.v), first, h)?;
        st.advance(dq, dv);
        let (acceleration, lambda) = sys.acceleration(&st.q, &st.v).ok_or(StepFailure::Singular)?;
        st.lambda = lambda;
        mem.remember(&st.q, sys.forces(&st.q));
        mem.remember_acceleration(&st.q, &st.v, acceleration);
        Ok(())
    }
}
