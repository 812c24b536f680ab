//! `rk4`: the classical Runge–Kutta method on the constrained ODE with the multiplier
//! eliminated (`docs/model.md` §1) — the non-geometric baseline users compare against.
//!
//! Fourth order, explicit, neither reversible nor constraint-preserving: it drifts off the
//! constraint manifold, which the `constraint` series shows.

mod general;

use crate::methods::integrator::{Integrator, MethodInfo, Stepper};
use crate::methods::memory::{AccelerationAtEnd, EndOfStep, Memory, Recall};
use crate::{Matrix, Vector};
use crate::model::system::{System, constraint_force};
use crate::{InputError, State, StepFailure};

/// Classical RK4 (no parameters).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Rk4;

/// RK4's memory: the acceleration its last stage ended with (first same as last) and the
/// driver's terms there, for the integrals.
#[derive(Debug, Clone, Copy)]
pub struct Rk4Memory<const N: usize, const R: usize> {
    pub(crate) acceleration: AccelerationAtEnd<N>,
    pub(crate) end: EndOfStep<N, R>,
}

impl<const N: usize, const R: usize> Memory<N, R> for Rk4Memory<N, R> {
    fn empty() -> Self {
        Self { acceleration: AccelerationAtEnd::empty(), end: EndOfStep::empty() }
    }
}

impl<const N: usize, const R: usize> Recall<N, R> for Rk4Memory<N, R> {
    #[inline]
    fn driver_terms_at(&self, zeta: f64) -> Option<(f64, Matrix<R, N>)> {
        self.end.driver_terms_at(zeta)
    }
    #[inline]
    fn moved(&mut self, from: &Vector<N>, to: &Vector<N>) {
        self.acceleration.moved(from, to);
        self.end.moved(from, to);
    }
}

static INFO: MethodInfo = MethodInfo {
    id: "rk4",
    name: "Classical Runge–Kutta (RK4) on the reduced ODE",
    params: &[],
    order: 4,
    reference: "Kutta (1901); Hairer, Nørsett & Wanner, Solving ODEs I, §II.1",
    implicit: false,
    composed_order_limit: None,
    class_only: None,
    instrument: false,
    symmetric_at: None,
    external: false,
    by_tableau: false,
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
}

impl Stepper for Rk4 {
    type Memory<const N: usize, const R: usize> = Rk4Memory<N, R>;
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut Self::Memory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let f = |q, v| sys.acceleration(&q, &v).map(|(a, _)| a).ok_or(StepFailure::Singular);
        // First same as last: the previous step ended with q̈ here.
        let (dq, dv) = stages(f, (st.q, st.v), mem.acceleration.at(st), h)?;
        st.advance(dq, dv);
        // The multiplier at q₁ (the state carries it), and with it q̈ for the next step and
        // A, V_d, V_d' for the integrals there: one evaluation, one sin/cos.
        let (q1, v1, zeta) = (st.q, st.v, st.q[N - 1]);
        let at_q1 = sys.driver_terms(zeta);
        let g = at_q1.gradient(sys, &q1);
        st.lambda = at_q1.continuous_multiplier(&g, &v1).ok_or(StepFailure::Singular)?;
        mem.acceleration.remember(st, constraint_force(&at_q1.constraint, &st.lambda) - g);
        mem.end.remember(st, at_q1.constraint, at_q1.potential, g[N - 1]);
        Ok(())
    }
}

/// The classical stages from `(q₀, q̇₀)` for the acceleration `f` (its value at the start
/// given where the last step ended there): the increments of q and q̇, as
/// `docs/model.md` §3 writes them. The class's step and the general one share them.
#[inline(always)]
pub(crate) fn stages<const N: usize>(
    f: impl Fn(Vector<N>, Vector<N>) -> Result<Vector<N>, StepFailure>,
    (q0, v0): (Vector<N>, Vector<N>),
    first: Option<Vector<N>>,
    h: f64,
) -> Result<(Vector<N>, Vector<N>), StepFailure> {
    let a1 = match first {
        Some(a) => a,
        None => f(q0, v0)?,
    };
    let (q2, v2) = (q0 + 0.5 * h * v0, v0 + 0.5 * h * a1);
    let a2 = f(q2, v2)?;
    let (q3, v3) = (q0 + 0.5 * h * v2, v0 + 0.5 * h * a2);
    let a3 = f(q3, v3)?;
    let (q4, v4) = (q0 + h * v3, v0 + h * a3);
    let a4 = f(q4, v4)?;
    Ok((h / 6.0 * (v0 + 2.0 * v2 + 2.0 * v3 + v4), h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4)))
}
