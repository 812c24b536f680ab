//! `rk4`: the classical Runge–Kutta method on the constrained ODE with the multiplier
//! eliminated (MATH.md §1) — the non-geometric baseline users compare against.
//!
//! Fourth order, explicit, neither reversible nor constraint-preserving: it drifts off the
//! constraint manifold, which the `constraint` series shows.

use crate::method::{Integrator, MethodInfo};
use crate::system::{System, constraint_force};
use crate::{InputError, State, StepFailure};

/// Classical RK4 (no parameters).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Rk4;

static INFO: MethodInfo = MethodInfo {
    id: "rk4",
    name: "Classical Runge–Kutta (RK4) on the reduced ODE",
    params: &[],
    order: 4,
    reference: "Kutta (1901); Hairer, Nørsett & Wanner, Solving ODEs I, §II.1",
    implicit: false,
};

impl Integrator for Rk4 {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(_params: &[f64]) -> Result<Self, InputError> {
        Ok(Self)
    }
    fn label(&self) -> String {
        "RK4".into()
    }
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let f = |q, v| sys.acceleration(&q, &v).map(|(a, _)| a).ok_or(StepFailure::Singular);
        let (q0, v0) = (st.q, st.v);
        // First same as last: the previous step ended with q̈ here.
        let a1 = match st.acceleration() {
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
        // The multiplier at q₁ (the state carries it), and with it q̈ for the next step and
        // A, V_d, V_d' for the integrals there: one evaluation, one sin/cos.
        let (q1, v1, zeta) = (st.q, st.v, st.q[N - 1]);
        let (g, a) = (sys.gradient(&q1), sys.constraint(zeta));
        let lambda = sys.continuous_multiplier_with(&q1, &v1, &g, &a);
        let v_d = sys.driver_potential(zeta);
        st.lambda = lambda.ok_or(StepFailure::Singular)?;
        st.remember_acceleration(constraint_force(&a, &st.lambda) - g);
        st.remember_at_end(a, v_d, g[N - 1]);
        Ok(())
    }
}
