//! `dla01`: DLA^{0,1} of McLachlan & Perlmutter: the force and the constraint force are
//! taken at the midpoint `q₀ + (h/2) q̇₀`, the constraint is imposed at `q₁`.
//!
//! Second order and reversible. Implicit in `(q̇₁, λ)`, solved by Newton with the exact
//! Jacobian (the nonlinearity is only through `A(ζ₁)`). The coupled fast path (default,
//! where [`coupled_fast_path`] says it pays: `cvt`, `particle`) uses that `A` has no driver
//! column: the driver's update `ζ̇₁ = ζ̇₀ − h V_d'(ζ_½)` is then explicit, so is `ζ₁`, and λ
//! follows from one R×R solve — the step becomes explicit, with the same result as Newton's
//! to round-off.

mod general;

use crate::solver::angle_tracker::AngleTracker;
use crate::methods::integrator::{Integrator, MethodInfo, Stepper};
use crate::methods::memory::EndOfStep;
use crate::methods::coupled::coupled_fast_path;
use crate::solver::newton::{Linearization, NewtonConfig, solve};
use crate::model::system::{System, constraint_force};
use crate::{InputError, Matrix, State, StepFailure};
use crate::linalg;

/// DLA^{0,1}.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dla01 {
    /// Newton's settings (general path).
    pub newton: NewtonConfig,
    /// Take the explicit coupled fast path where it pays ([`coupled_fast_path`]; same steps
    /// to round-off); `false` forces the general Newton solve, which the fast path is tested
    /// against.
    pub fast_path: bool,
}

impl Default for Dla01 {
    fn default() -> Self {
        Self { newton: NewtonConfig::default(), fast_path: true }
    }
}

static INFO: MethodInfo = MethodInfo {
    id: "dla01",
    name: "DLA^{0,1} (McLachlan–Perlmutter)",
    params: &[],
    order: 2,
    reference: "McLachlan & Perlmutter, J. Nonlinear Sci. 16 (2006); Modin & Verdier §2",
    implicit: true,
    composed_order_limit: None,
    class_only: None,
    instrument: false,
    symmetric_at: None,
    external: false,
    by_tableau: false,
};

impl Integrator for Dla01 {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(_params: &[f64]) -> Result<Self, InputError> {
        Ok(Self::default())
    }
    fn general_path(&self) -> Option<Self> {
        Some(Self { fast_path: false, ..*self })
    }
    fn label(&self) -> String {
        "DLA^{0,1}".into()
    }
    fn symmetric(&self) -> bool {
        true
    }
}

impl Stepper for Dla01 {
    type Memory<const N: usize, const R: usize> = EndOfStep<N, R>;
    // Always inlined: one call site per run loop, where the integrals then share its work.
    #[inline(always)]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut Self::Memory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let q_half = st.q + 0.5 * h * st.v;
        let a_half = sys.constraint(q_half[N - 1]);
        let g_half = sys.gradient(&q_half);
        let w = st.v - h * g_half;
        if self.fast_path && coupled_fast_path(sys) {
            // v₁ = w + h A_½ᵀ λ has the driver speed of w (A has no driver column), so ζ₁ is
            // known, and A(ζ₁) v₁ = 0 gives (h A₁ A_½ᵀ) λ = −A₁ w.
            // ζ₁ exactly as the state will hold it (λ does not move ζ), so that the constraint
            // is imposed there and V_d, A at ζ₁ (one sin/cos) serve the integrals too.
            let dz = h * st.v[N - 1] + (0.5 * h) * (h * -g_half[N - 1]);
            let z1 = st.q_after(N - 1, dz);
            let (a1, v_d1, d1) =
                (sys.constraint(z1), sys.driver_potential(z1), sys.driver_potential_d1(z1));
            let lambda = linalg::solve(&(a1 * a_half.transpose()), &(a1 * w))
                .ok_or(StepFailure::Singular)?
                * (-1.0 / h);
            let dv = h * (constraint_force(&a_half, &lambda) - g_half);
            st.advance(h * st.v + (0.5 * h) * dv, dv);
            st.lambda = lambda;
            if st.q[N - 1] == z1 {
                mem.remember(st, a1, v_d1, d1);
            }
            return Ok(());
        }
        let g = a_half.transpose() * (-h);
        let mut v1 = w + h * (a_half.transpose() * st.lambda);
        let mut lambda = st.lambda;
        let mut tracker = AngleTracker::new();
        solve(&self.newton, &mut v1, &mut lambda, |v1, lambda| {
            let at_z1 = tracker.terms(sys, q_half[N - 1] + 0.5 * h * v1[N - 1]);
            let a1 = at_z1.constraint;
            let mut c = a1;
            let dcol = at_z1.constraint_d * v1 * (0.5 * h);
            for r in 0..R {
                c[(r, N - 1)] += dcol[r];
            }
            Linearization {
                f1: v1 - w + g * lambda,
                f2: a1 * v1,
                b: Matrix::<N, N>::identity(),
                g,
                c,
                b_maybe_bordered: true,
                affine_but_for_the_driver: true,
            }
        })?;
        st.advance_to(0.5 * h * (st.v + v1), v1);
        st.lambda = lambda;
        // What the integrals need at q₁, one Newton increment from the tracker's last iterate:
        // a rotation, where evaluating would call `sin_cos`.
        let at_q1 = tracker.terms(sys, st.q[N - 1]);
        mem.remember(st, at_q1.constraint, at_q1.potential, at_q1.potential_d1);
        Ok(())
    }
}
