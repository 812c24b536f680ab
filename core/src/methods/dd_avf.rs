//! `dd_avf`: the discrete-derivative method of `dd` with the *average vector field*
//! discrete gradient `∇̄V(q₀, q₁) = ∫₀¹ ∇V(q₀ + s Δq) ds` (Modin & Verdier, open problem 3).
//!
//! With `V = U(x) + V_d(ζ)` the integral splits. The driver part is one-dimensional:
//! `(V_d(ζ₁) − V_d(ζ₀))/Δζ` in closed form, or 4-point Gauss–Legendre when `|Δζ| < 10⁻²`
//! (where the closed form would cancel; the quadrature error there is below 10⁻²⁰). The
//! passenger part uses 3-point Gauss–Legendre, exact for U up to degree 6; where U (every
//! test system) or V_d is quadratic, the average of its affine gradient is taken at the
//! midpoint instead. Unlike Gonzalez's gradient, the driver's update then sees the driver
//! alone, so the method can preserve the fibration while conserving H.
//!
//! Where V is quadratic (the knife edge, `cvt`, `particle`, the rolling disk) the AVF gradient
//! is `∇V(q̄)`, Gonzalez's without its correction, so DD-AVF is DD there and takes DD's step in
//! closed form, ended in double-double ([`closed_form`](super::dd::closed_form)): H stays at
//! round-off however long the run. Elsewhere it solves `(q̇₁, λ)` by Newton (`dd`'s
//! `discrete_derivative_step`). A coupled split (the driver's row alone, then the passenger by one
//! division) was removed: it was less than 2× faster than the general solve, the least a fast path
//! must gain (`docs/performance.md`).

use super::dd::step::discrete_derivative_step;
use super::dd::{DdMemory, closed_form};
use crate::solver::angle_tracker::AngleTracker;
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::{GeneralStepper, Integrator, MethodInfo, Stepper};
use crate::model::mechanical::Mechanical;
use crate::solver::newton::NewtonConfig;
use crate::model::system::{DriverTerms, System};
use crate::{InputError, Matrix, State, StepFailure, Vector};

/// The discrete-derivative method with the AVF discrete gradient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DdAvf {
    /// Newton's settings.
    pub newton: NewtonConfig,
    /// Where V is quadratic, take DD's step in closed form ended in double-double
    /// (`dd::closed_form`: the same equations there, H at round-off); `false` forces the general
    /// Newton solve in `(q̇₁, λ)`, which it is tested against.
    pub fast_path: bool,
}

impl Default for DdAvf {
    fn default() -> Self {
        Self { newton: NewtonConfig::ENERGY_CONSERVING, fast_path: true }
    }
}

static INFO: MethodInfo = MethodInfo {
    id: "dd_avf",
    name: "Discrete derivative, average vector field (DD-AVF)",
    params: &[],
    order: 2,
    reference: "Quispel & McLaren, J. Phys. A 41 (2008); Modin & Verdier, open problem 3",
    implicit: true,
    composed_order_limit: Some(4),
    class_only: Some(
        "its average-vector-field gradient is split into the driver's exact difference \
         quotient and the passenger's quadrature, which needs V = U(x) + V_d(ζ) \
         (docs/model.md §3)",
    ),
    instrument: false,
    symmetric_at: None,
    external: false,
    by_tableau: false,
};

/// Gauss–Legendre nodes and weights on [0, 1].
const GL3: [(f64, f64); 3] = [
    (0.112_701_665_379_258_3, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];
const GL4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_9, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];
/// Below this |Δζ| the driver's closed form loses digits to cancellation.
const CLOSED_FORM_MIN: f64 = 1e-2;

/// The AVF gradient and its derivative with respect to `q₁` (not yet times `dq₁/dq̇₁`),
/// given the driver's terms at `ζ̄`. Where a part of V is quadratic its gradient is affine,
/// and its average is its value at the midpoint (and `∫ s ∇²V ds = ½ ∇²V`): the quadrature
/// is skipped for U on every test system, and for `V_d` where it is quadratic.
#[inline]
fn avf_gradient<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    (q0, vd0): (&Vector<N>, f64),
    dq: &Vector<N>,
    mid: &DriverTerms<N, R>,
    end: &mut AngleTracker,
) -> (Vector<N>, Matrix<N, N>) {
    let (mut grad, mut jac) = if sys.quadratic_passenger() {
        let q_mid = q0 + 0.5 * dq;
        (sys.passenger_gradient(&q_mid), sys.passenger_hessian(&q_mid) * 0.5)
    } else {
        GL3.iter().fold((Vector::<N>::zeros(), Matrix::<N, N>::zeros()), |(g, j), &(s, w)| {
            let q = q0 + s * dq;
            (g + w * sys.passenger_gradient(&q), j + (w * s) * sys.passenger_hessian(&q))
        })
    };
    let (g, dg) = if sys.quadratic_driver() {
        (mid.potential_d1, 0.5 * mid.potential_d2)
    } else {
        avf_driver_mean(sys, (q0[N - 1], vd0), dq[N - 1], end)
    };
    grad[N - 1] = g;
    jac[(N - 1, N - 1)] = dg;
    (grad, jac)
}

/// The driver's part of the AVF gradient, `ḡ = ∫₀¹ V_d'(ζ₀ + sΔζ) ds`, and its derivative
/// with respect to ζ₁, given `V_d(ζ₀)`; V_d at ζ₁ through the tracker.
#[inline]
fn avf_driver_mean<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    (z0, vd0): (f64, f64),
    dz: f64,
    end: &mut AngleTracker,
) -> (f64, f64) {
    if dz.abs() >= CLOSED_FORM_MIN {
        // One reciprocal, computed beside the terms at ζ₁, instead of two dependent divisions.
        let inv = 1.0 / dz;
        let at_z1 = end.terms(sys, z0 + dz);
        let g = (at_z1.potential - vd0) * inv;
        (g, (at_z1.potential_d1 - g) * inv)
    } else {
        GL4.iter().fold((0.0, 0.0), |(g, dg), &(s, w)| {
            let z = z0 + s * dz;
            (g + w * sys.driver_potential_d1(z), dg + w * s * sys.driver_potential_d2(z))
        })
    }
}

impl Integrator for DdAvf {
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
        "DD-AVF".into()
    }
    fn symmetric(&self) -> bool {
        true
    }
}

impl Stepper for DdAvf {
    type Memory<const N: usize, const R: usize> = DdMemory<N, R>;
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut DdMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        if self.fast_path && closed_form::applies(sys) {
            return closed_form::step(sys, st, mem, h);
        }
        let q0 = st.q;
        let vd0 = mem.end.driver_potential_and_constraint(sys, st).0;
        let gradient = |dq: &Vector<N>, mid: &DriverTerms<N, R>, end: &mut AngleTracker| {
            // dq₁/dq̇₁ = (h/2) I.
            let (grad, jac) = avf_gradient(sys, (&q0, vd0), dq, mid, end);
            (grad, jac * (0.5 * h))
        };
        discrete_derivative_step(sys, st, mem, h, &self.newton, true, gradient)
    }
}

/// DD-AVF has no step on the general class (`MethodInfo::class_only` says why; runs are
/// refused before they start).
impl GeneralStepper for DdAvf {
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        _sys: &S,
        _state: &mut State<N, R>,
        _memory: &mut GeneralMemory<N, R>,
        _h: f64,
    ) -> Result<(), StepFailure> {
        Err(StepFailure::NotApplicable)
    }
}
