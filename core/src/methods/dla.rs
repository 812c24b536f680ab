//! `dla`: the discrete Lagrange–d'Alembert method DLA^α of Cortés & Martínez, `0 < α ≤ 1`.
//!
//! Second order and reversible only for α = ½; the paper's DLA^0.4 is its non-reversible
//! counterexample. Implicit in `(q̇₁, λ)`, solved by Newton with the exact Jacobian.
//!
//! The coupled fast path (default, when U is quadratic): the driver's update
//! `ζ̇₁ = ζ̇₀ − αh V_d'(ζ₀) − (1−α)h V_d'(ζ₁)` does not see the passenger, so it is one scalar
//! Newton solve (a single step where V_d is quadratic, `System::QUADRATIC_DRIVER`); with ζ₁
//! known and `∇U` affine, the passenger update is one linear saddle solve. Same equations,
//! same result to round-off, without the N×N Newton iterations.

use crate::angle_tracker::AngleTracker;
use crate::method::{Integrator, MethodInfo};
use crate::newton::{Linearization, NewtonConfig, solve, solve_affine_scalar, solve_scalar};
use crate::system::{DriverTerms, ParamSpec, System};
use crate::{InputError, Matrix, State, StepFailure, Vector, linalg};

/// DLA^α.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dla {
    /// Where the potential force is sampled: α at q₀, 1 − α at q₁.
    pub alpha: f64,
    /// Newton's settings.
    pub newton: NewtonConfig,
    /// Take the coupled fast path when the system allows it (same steps to round-off);
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
        let g0 = st.gradient(sys);
        let v0 = st.v;
        if self.fast_path && S::QUADRATIC_PASSENGER {
            return self.step_coupled(sys, st, h, q_a, &a_qa, &g0);
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
            }
        })?;
        st.advance_to((1.0 - a) * h * st.v + a * h * v1, v1);
        st.lambda = lambda;
        Ok(())
    }
}

impl Dla {
    /// The coupled fast path (see the module's doc): `q_a`, `A(q_a)` and `∇V(q₀)` as the
    /// general path computes them.
    #[inline]
    fn step_coupled<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        h: f64,
        q_a: Vector<N>,
        a_qa: &Matrix<R, N>,
        g0: &Vector<N>,
    ) -> Result<(), StepFailure> {
        let a = self.alpha;
        let (z_a, b) = (q_a[N - 1], 1.0 - a);
        // Driver alone: F(w) = w − ζ̇₀ + αh V_d'(ζ₀) + (1−α)h V_d'(ζ_a + αh w) = 0.
        let rhs = st.v[N - 1] - a * h * g0[N - 1];
        let mut w = rhs - b * h * g0[N - 1];
        // A, A', V_d, V_d', V_d'' at an iterate share one sin/cos (after the first iterate,
        // rotated from the previous one's: `AngleTracker`); A(ζ₁) at the solution
        // is then one Taylor step away when the last increment is tiny, and so are the
        // values at the stored ζ₁ that the next step and the integrals use.
        let (mut last, mut tracker) = (None, AngleTracker::new());
        let driver = |w: f64| {
            let at = Taylor::at(sys, &mut tracker, z_a + a * h * w);
            let value_slope =
                (w - rhs + b * h * at.at.potential_d1, 1.0 + a * b * h * h * at.at.potential_d2);
            last = Some(at);
            value_slope
        };
        if S::QUADRATIC_DRIVER {
            solve_affine_scalar(&mut w, driver)?;
        } else {
            solve_scalar(&self.newton, &mut w, driver)?;
        }
        let z1 = z_a + a * h * w;
        // Newton evaluated at least once if it succeeded; the fallback is never taken.
        let last = last.unwrap_or_else(|| Taylor::at(sys, &mut tracker, z1));
        let a1 = last.constraint(sys, z1);
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
        let zeta = st.q[N - 1];
        let mut g1 = sys.passenger_gradient(&st.q);
        g1[N - 1] = last.d1(sys, zeta);
        st.remember_at_end(g1, last.constraint(sys, zeta), last.potential(sys, zeta));
        Ok(())
    }
}

/// The driver's functions at a point ζ*, and their Taylor expansions to a ζ within 10⁻⁸ of
/// it (A and V_d' to first order, V_d to second), where the neglected terms (`|A''| dz²/2`,
/// `|V_d'''| dz²/2`, `|V_d'''| dz³/6`) are below 10⁻¹⁵; farther away they are evaluated.
struct Taylor<const N: usize, const R: usize> {
    zeta: f64,
    at: DriverTerms<N, R>,
}

impl<const N: usize, const R: usize> Taylor<N, R> {
    #[inline]
    fn at<S: System<N, R>>(sys: &S, tracker: &mut AngleTracker, zeta: f64) -> Self {
        Self { zeta, at: tracker.terms(sys, zeta) }
    }
    #[inline]
    fn near(&self, zeta: f64) -> Option<f64> {
        let dz = zeta - self.zeta;
        (dz.abs() <= 1e-8).then_some(dz)
    }
    #[inline]
    fn constraint<S: System<N, R>>(&self, sys: &S, zeta: f64) -> Matrix<R, N> {
        let t = &self.at;
        self.near(zeta)
            .map_or_else(|| sys.constraint(zeta), |dz| t.constraint + t.constraint_d * dz)
    }
    #[inline]
    fn d1<S: System<N, R>>(&self, sys: &S, zeta: f64) -> f64 {
        let t = &self.at;
        self.near(zeta).map_or_else(
            || sys.driver_potential_d1(zeta),
            |dz| t.potential_d1 + t.potential_d2 * dz,
        )
    }
    #[inline]
    fn potential<S: System<N, R>>(&self, sys: &S, zeta: f64) -> f64 {
        self.near(zeta).map_or_else(
            || sys.driver_potential(zeta),
            |dz| self.at.potential + dz * (self.at.potential_d1 + 0.5 * self.at.potential_d2 * dz),
        )
    }
}
