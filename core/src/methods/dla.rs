//! `dla`: the discrete Lagrange–d'Alembert method DLA^α of Cortés & Martínez, `0 < α ≤ 1`.
//!
//! Second order and reversible only for α = ½; the paper's DLA^0.4 is its non-reversible
//! counterexample. Implicit in `(q̇₁, λ)`, solved by Newton with the exact Jacobian.
//!
//! The coupled fast path (default, where [`coupled_fast_path`] says it pays: `cvt`,
//! `particle`): the driver's update `ζ̇₁ = ζ̇₀ − αh V_d'(ζ₀) − (1−α)h V_d'(ζ₁)` does not see the
//! passenger and, V_d being quadratic, is affine in ζ̇₁: one division. With ζ₁ known and `∇U`
//! affine, the passenger's update is one linear saddle solve. Same equations, same result to
//! round-off, without the N×N Newton iterations.

mod general;

use crate::solver::angle_tracker::AngleTracker;
use crate::methods::integrator::{Integrator, MethodInfo, Stepper, SymmetricAt};
use crate::methods::memory::EndOfStep;
use crate::methods::coupled::coupled_fast_path;
use crate::solver::newton::{Linearization, NewtonConfig, solve};
use crate::model::system::{ParamSpec, System};
use crate::{InputError, Matrix, State, StepFailure, Vector};
use crate::linalg;

/// DLA^α.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dla {
    /// Where the potential force is sampled: α at q₀, 1 − α at q₁.
    pub alpha: f64,
    /// Newton's settings.
    pub newton: NewtonConfig,
    /// Take the coupled fast path where it pays ([`coupled_fast_path`]; same steps to round-off);
    /// `false` forces the general Newton solve, which the fast path is tested against.
    pub fast_path: bool,
}

impl Default for Dla {
    fn default() -> Self {
        Self { alpha: 0.5, newton: NewtonConfig::default(), fast_path: true }
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
    composed_order_limit: None,
    class_only: None,
    instrument: false,
    symmetric_at: Some(SymmetricAt { param: "alpha", value: 0.5, order_elsewhere: 1 }),
    external: false,
    by_tableau: false,
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
    fn general_path(&self) -> Option<Self> {
        Some(Self { fast_path: false, ..*self })
    }
    fn order(&self) -> u32 {
        if self.alpha == 0.5 { 2 } else { 1 }
    }
    fn label(&self) -> String {
        format!("DLA^{}", self.alpha)
    }
    fn symmetric(&self) -> bool {
        self.alpha == 0.5
    }
}

impl Stepper for Dla {
    type Memory<const N: usize, const R: usize> = EndOfStep<N, R>;
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut Self::Memory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let a = self.alpha;
        let q_a = st.q + (1.0 - a) * h * st.v;
        let a_qa = sys.constraint(q_a[N - 1]);
        let g0 = mem.gradient(sys, st);
        let v0 = st.v;
        if self.fast_path && coupled_fast_path(sys) {
            return self.step_coupled(sys, st, mem, h, q_a, &a_qa, &g0);
        }
        let g = a_qa.transpose() * (-h);
        // Explicit Euler guess; Newton then needs a few iterations.
        let mut v1 = v0 + h * (a_qa.transpose() * st.lambda - g0);
        let mut lambda = st.lambda;
        let mut tracker = AngleTracker::new();
        solve(&self.newton, &mut v1, &mut lambda, |v1, lambda| {
            let q1 = q_a + a * h * v1;
            let at_q1 = tracker.terms(sys, q1[N - 1]);
            let a1 = at_q1.constraint;
            let mut c = a1;
            let dcol = at_q1.constraint_d * v1 * (a * h);
            for r in 0..R {
                c[(r, N - 1)] += dcol[r];
            }
            Linearization {
                f1: v1 - v0 + a * h * g0 + (1.0 - a) * h * at_q1.gradient(sys, &q1) + g * lambda,
                f2: a1 * v1,
                b: Matrix::<N, N>::identity() + (1.0 - a) * a * h * h * at_q1.hessian(sys, &q1),
                g,
                c,
                b_maybe_bordered: true,
                affine_but_for_the_driver: sys.quadratic_passenger(),
            }
        })?;
        st.advance_to((1.0 - a) * h * st.v + a * h * v1, v1);
        st.lambda = lambda;
        // What the next step and the integrals need at q₁, one Newton increment from the
        // tracker's last iterate: a rotation, where evaluating would call `sin_cos`.
        let at_q1 = tracker.terms(sys, st.q[N - 1]);
        mem.remember(st, at_q1.constraint, at_q1.potential, at_q1.potential_d1);
        Ok(())
    }
}

impl Dla {
    /// The coupled fast path (see the module's doc), where [`coupled_fast_path`] holds:
    /// `q_a`, `A(q_a)` and `∇V(q₀)` as the general path computes them.
    #[inline]
    #[allow(clippy::too_many_arguments, reason = "what the general path computed, passed on")]
    fn step_coupled<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut EndOfStep<N, R>,
        h: f64,
        q_a: Vector<N>,
        a_qa: &Matrix<R, N>,
        g0: &Vector<N>,
    ) -> Result<(), StepFailure> {
        let a = self.alpha;
        let (z_a, b) = (q_a[N - 1], 1.0 - a);
        // Driver alone: w − ζ̇₀ + αh V_d'(ζ₀) + (1−α)h V_d'(ζ_a + αh w) = 0. V_d being quadratic,
        // V_d'(ζ_a + αh w) = V_d'(ζ_a) + αh w V_d'', so w is one product: the reciprocal of the
        // slope does not depend on the state, so its division runs beside the chain from one
        // step's driver to the next instead of on it (what Newton's step from a guess did).
        let slope = 1.0 + a * b * h * h * sys.driver_potential_d2(z_a);
        let w = (st.v[N - 1] - a * h * g0[N - 1] - b * h * sys.driver_potential_d1(z_a))
            * (1.0 / slope);
        if !w.is_finite() {
            return Err(if slope == 0.0 { StepFailure::Singular } else { StepFailure::NonFinite });
        }
        let a1 = sys.constraint(z_a + a * h * w);
        // Passenger, with ∇U(q₁) = ∇U(q_a) + αh K q̇₁ exact for quadratic U:
        // (I + α(1−α)h²K) q̇₁ − h A_aᵀλ = q̇₀ − αh∇V(q₀) − (1−α)h∇U(q_a), A(ζ₁) q̇₁ = 0.
        // The driver row of K and the driver column of A vanish, so that row reads q̇₁_ζ = w.
        let m = Matrix::<N, N>::identity() + (a * b * h * h) * sys.passenger_hessian(&q_a);
        let mut rhs_v = st.v - a * h * g0 - b * h * sys.passenger_gradient(&q_a);
        rhs_v[N - 1] = w;
        // M does not wait on the passenger's chain; below 4×4 its closed form is then the
        // cheaper (fewer instructions than the shape test, callgrind).
        let m_inv = if N >= 4 { linalg::inverse_maybe_bordered(&m) } else { linalg::inverse(&m) }
            .ok_or(StepFailure::Singular)?;
        let (m_rhs, m_at) = (m_inv * rhs_v, m_inv * a_qa.transpose());
        let lambda =
            linalg::solve(&(a1 * m_at), &(a1 * m_rhs)).ok_or(StepFailure::Singular)? * (-1.0 / h);
        let mut v1 = m_rhs + h * (m_at * lambda);
        // The driver speed is w (that row of the system reads q̇₁_ζ = w), and is written so:
        // computed through M⁻¹ and λ it would be w to round-off, but would make the next
        // step's driver wait for this step's passenger solve.
        v1[N - 1] = w;
        st.advance_to((1.0 - a) * h * st.v + a * h * v1, v1);
        st.lambda = lambda;
        // What the next step starts from and the integrals need, at ζ₁ as the state holds it.
        let zeta = st.q[N - 1];
        mem.remember(
            st,
            sys.constraint(zeta),
            sys.driver_potential(zeta),
            sys.driver_potential_d1(zeta),
        );
        Ok(())
    }
}
