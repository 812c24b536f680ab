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
        let (q0, v0) = (st.q, st.v);
        // First same as last.
        let a1 = match mem.acceleration(&q0, &v0) {
            Some(a) => a,
            None => f(q0, v0)?,
        };
        let (q2, v2) = (q0 + 0.5 * h * v0, v0 + 0.5 * h * a1);
        let a2 = f(q2, v2)?;
        let (q3, v3) = (q0 + 0.5 * h * v2, v0 + 0.5 * h * a2);
        let a3 = f(q3, v3)?;
        let (q4, v4) = (q0 + h * v3, v0 + h * a3);
        let a4 = f(q4, v4)?;
        st.advance(
            h / 6.0 * (v0 + 2.0 * v2 + 2.0 * v3 + v4),
            h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4),
        );
        let (acceleration, lambda) = sys.acceleration(&st.q, &st.v).ok_or(StepFailure::Singular)?;
        st.lambda = lambda;
        mem.remember(&st.q, sys.forces(&st.q));
        mem.remember_acceleration(&st.q, &st.v, acceleration);
        Ok(())
    }
}
