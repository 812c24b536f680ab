//! `dla`: the discrete Lagrange–d'Alembert method DLA^α of Cortés & Martínez, `0 < α ≤ 1`.
//!
//! Second order and reversible only for α = ½; the paper's DLA^0.4 is its non-reversible
//! counterexample. Implicit in `(q̇₁, λ)`, solved by Newton with the exact Jacobian.

use crate::method::{Integrator, MethodInfo};
use crate::newton::{Linearization, NewtonConfig, solve};
use crate::system::{ParamSpec, System};
use crate::{InputError, Matrix, State, StepFailure};

/// DLA^α.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dla {
    /// Where the potential force is sampled: α at q₀, 1 − α at q₁.
    pub alpha: f64,
    /// Newton's settings.
    pub newton: NewtonConfig,
}

impl Default for Dla {
    fn default() -> Self {
        Self { alpha: 0.5, newton: NewtonConfig::default() }
    }
}

static INFO: MethodInfo = MethodInfo {
    id: "dla",
    name: "Discrete Lagrange–d'Alembert DLA^α",
    params: &[ParamSpec {
        name: "alpha",
        default: 0.5,
        min: 0.0,
        max: 1.0,
        min_open: true,
        max_open: false,
        description: "weight α of the force at q₀; second order and reversible only for α = 0.5",
    }],
    order: 2,
    reference: "Cortés & Martínez, Nonlinearity 14 (2001); Modin & Verdier §2",
    implicit: true,
};

impl Integrator for Dla {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(params: &[f64]) -> Result<Self, InputError> {
        Ok(Self { alpha: params[0], ..Self::default() })
    }
    fn params(&self) -> Vec<f64> {
        vec![self.alpha]
    }
    fn order(&self) -> u32 {
        if self.alpha == 0.5 { 2 } else { 1 }
    }
    fn label(&self) -> String {
        format!("DLA^{}", self.alpha)
    }
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let a = self.alpha;
        let q_a = st.q + (1.0 - a) * h * st.v;
        let a_qa = sys.constraint(q_a[N - 1]);
        let g0 = sys.gradient(&st.q);
        let v0 = st.v;
        let g = a_qa.transpose() * (-h);
        // Explicit Euler guess; Newton then needs a few iterations.
        let mut v1 = v0 + h * (a_qa.transpose() * st.lambda - g0);
        let mut lambda = st.lambda;
        solve(&self.newton, &mut v1, &mut lambda, |v1, lambda| {
            let q1 = q_a + a * h * v1;
            let z1 = q1[N - 1];
            let a1 = sys.constraint(z1);
            let mut c = a1;
            let dcol = sys.constraint_d(z1) * v1 * (a * h);
            for r in 0..R {
                c[(r, N - 1)] += dcol[r];
            }
            Linearization {
                f1: v1 - v0 + a * h * g0 + (1.0 - a) * h * sys.gradient(&q1) + g * lambda,
                f2: a1 * v1,
                b: Matrix::<N, N>::identity() + (1.0 - a) * a * h * h * sys.hessian(&q1),
                g,
                c,
            }
        })?;
        st.q = q_a + a * h * v1;
        st.v = v1;
        st.lambda = lambda;
        Ok(())
    }
}
