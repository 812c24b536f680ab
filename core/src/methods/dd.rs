//! `dd`: the discrete-derivative method (Gonzalez's discrete gradient, as Betsch uses it).
//!
//! Conserves the total energy H exactly (up to round-off) and is reversible, but does not
//! preserve the fibration: through `|Δq|²` the driver's update sees the passenger.
//! Where V is quadratic, Gonzalez's correction is only the rounding of `q₁` (see
//! [`discrete_gradient`]) and the discrete gradient is otherwise `∇V(q̄)`.
//! Implicit in `(q̇₁, λ)`, solved by Newton with the Jacobian derived below (exact, but for
//! the derivatives of that rounding). By default, where V is quadratic, in closed form and
//! ended in double-double so that H stays at round-off however long the run
//! ([`exact_energy`](super::exact_energy)); on the mobile robot in the driver's speed alone,
//! once the midpoint constraint is built in and λ projected out
//! ([`dd_reduced`](super::dd_reduced)); elsewhere (or with `fast_path: false`) in `(q̇₁, λ)` as
//! written in MATH.md §3, starting from Euler's step with the driver's speed extrapolated from
//! the last steps ([`DriverHistory`](crate::driver_history::DriverHistory)), which saves the
//! third iteration on most steps.

use super::dd_reduced::{self, reduced_step};
use super::exact_energy;
use crate::angle_tracker::AngleTracker;
use crate::method::{Integrator, MethodInfo};
use crate::newton::{Linearization, NewtonConfig, solve};
use crate::system::{DriverTerms, System};
use crate::{InputError, Matrix, State, StepFailure, Vector};

/// The discrete-derivative method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dd {
    /// Newton's settings.
    pub newton: NewtonConfig,
    /// Where V is quadratic, take the step in closed form and end it in double-double
    /// (`exact_energy`); on the mobile robot, solve Newton for the driver's speed alone, the
    /// passenger's following in closed form (`dd_reduced`). Same steps to round-off; `false`
    /// forces the general `(q̇₁, λ)` solve, which they are tested against (in doubles: its
    /// energy error grows with the run where the exact end's stays flat).
    pub fast_path: bool,
}

impl Default for Dd {
    fn default() -> Self {
        Self { newton: NewtonConfig::ENERGY_CONSERVING, fast_path: true }
    }
}

static INFO: MethodInfo = MethodInfo {
    id: "dd",
    name: "Discrete derivative (DD)",
    params: &[],
    order: 2,
    reference: "Gonzalez, J. Nonlinear Sci. 6 (1996); Betsch, CMAME 195 (2006); Modin & Verdier §2",
    implicit: true,
};

/// Gonzalez's discrete gradient `∇̄V(q₀, q₁)` and its derivative with respect to `q̇₁`
/// (where `q₁ = q₀ + (h/2)(q̇₀ + q̇₁)`, so `dΔq = (h/2) dq̇₁`, `dq̄ = (h/4) dq̇₁`), given the
/// driver's terms at `ζ̄`; those at `ζ₁` come from `end`, which follows ζ₁ along Newton's
/// iterates.
///
/// Where a part of V is quadratic, `V(q₁) − V(q₀) = ∇V(q̄)·Δq` holds exactly for that part,
/// so its share of the correction `c` is only the rounding of `q₁ = q₀ + Δq`. That share is
/// kept in `c`: it feeds the rounding of the positions back into q̇₁, which keeps H
/// consistent with the rounded positions (without it, DD's energy error over 10⁸ knife-edge
/// steps at h = 0.31 grows linearly, to 20× more). But its derivatives are round-off and are
/// left out of the Jacobian, which only Newton's speed depends on: for a quadratic V
/// (knife edge, disk, `cvt`, `particle`) the Jacobian is then that of `∇V(q̄)`, and for
/// quadratic U (every test system) only the driver's share of `dc/dq̇₁` is kept.
#[inline]
fn discrete_gradient<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    (q0, v_q0): (&Vector<N>, f64),
    dq: &Vector<N>,
    h: f64,
    mid: &DriverTerms<N, R>,
    end: &mut AngleTracker,
) -> (Vector<N>, Matrix<N, N>) {
    let value = gonzalez_value(sys, (q0, v_q0), dq, mid, end);
    let hess_mid = mid.hessian(sys, &value.q_mid);
    let Some(Correction { c, u, dq2, q1, at_q1 }) = value.correction else {
        return (value.gradient, hess_mid * (0.25 * h));
    };
    // d(Δq/|Δq|²)/dq̇₁ = (h/2) (I − 2 Δq Δqᵀ/|Δq|²) / |Δq|²
    let du = (Matrix::<N, N>::identity() - 2.0 * (dq * u.transpose())) * (0.5 * h / dq2);
    let mut jac = hess_mid * (0.25 * h) + du * c;
    // dc/dq̇₁ = (h/2) [∇V(q₁) − ∇V(q̄) − ½ ∇²V(q̄) Δq]
    if S::QUADRATIC_PASSENGER {
        let dz = dq[N - 1];
        let dc = (at_q1.potential_d1 - mid.potential_d1 - 0.5 * mid.potential_d2 * dz) * (0.5 * h);
        for i in 0..N {
            jac[(i, N - 1)] += u[i] * dc;
        }
    } else {
        let dc = (at_q1.gradient(sys, &q1) - value.g_mid - 0.5 * (hess_mid * dq)) * (0.5 * h);
        jac += u * dc.transpose();
    }
    (value.gradient, jac)
}

/// The value of Gonzalez's discrete gradient at Δq, and what its derivatives are built from.
struct GonzalezValue<const N: usize, const R: usize> {
    /// `∇̄V(q₀, q₀ + Δq) = ∇V(q̄) + c u`.
    gradient: Vector<N>,
    /// `q̄ = q₀ + Δq/2`.
    q_mid: Vector<N>,
    /// `∇V(q̄)`.
    g_mid: Vector<N>,
    /// The correction's parts where its derivatives count: Δq ≠ 0 and V not quadratic.
    correction: Option<Correction<N, R>>,
}

/// Gonzalez's correction `c u` and what its derivatives need.
struct Correction<const N: usize, const R: usize> {
    /// `c = V(q₁) − V(q₀) − ∇V(q̄)·Δq`.
    c: f64,
    /// `u = Δq/|Δq|²`.
    u: Vector<N>,
    /// `|Δq|²`.
    dq2: f64,
    /// `q₁ = q₀ + Δq`.
    q1: Vector<N>,
    /// The driver's terms at ζ₁.
    at_q1: DriverTerms<N, R>,
}

/// Gonzalez's `∇̄V(q₀, q₀ + Δq)` (see [`discrete_gradient`] for the rounding term it keeps),
/// given `V(q₀)` and the driver's terms at ζ̄; those at ζ₁ through `end`.
#[inline]
fn gonzalez_value<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    (q0, v_q0): (&Vector<N>, f64),
    dq: &Vector<N>,
    mid: &DriverTerms<N, R>,
    end: &mut AngleTracker,
) -> GonzalezValue<N, R> {
    let q_mid = q0 + 0.5 * dq;
    let g_mid = mid.gradient(sys, &q_mid);
    let dq2 = dq.norm_squared();
    if dq2 == 0.0 {
        return GonzalezValue { gradient: g_mid, q_mid, g_mid, correction: None };
    }
    let q1 = q0 + dq;
    let u = dq / dq2;
    if S::QUADRATIC_PASSENGER && S::QUADRATIC_DRIVER {
        let c = sys.potential(&q1) - v_q0 - g_mid.dot(dq);
        return GonzalezValue { gradient: g_mid + c * u, q_mid, g_mid, correction: None };
    }
    let at_q1 = end.terms(sys, q1[N - 1]);
    let (v_q1, g_dq) = (sys.passenger_potential(&q1) + at_q1.potential, g_mid.dot(dq));
    let c = v_q1 - v_q0 - g_dq;
    if is_rounding(c, v_q1.abs() + v_q0.abs() + g_dq.abs()) {
        return GonzalezValue { gradient: g_mid, q_mid, g_mid, correction: None };
    }
    let correction = Some(Correction { c, u, dq2, q1, at_q1 });
    GonzalezValue { gradient: g_mid + c * u, q_mid, g_mid, correction }
}

/// Whether Gonzalez's `c = V(q₁) − V(q₀) − ∇V(q̄)·Δq`, whose terms add up to `size` in
/// absolute value, is its own rounding (c is O(|Δq|³), the rounding of its difference
/// O(ε|V|)). Such a c carries no value, and divided by |Δq|² it does not stay small: at rest at
/// an equilibrium DD's Jacobian came out singular, where every other method stays at rest
/// (`tests/at_rest.rs`). There the gradient is `∇V(q̄)`, which c changes by less than the
/// rounding of V.
#[inline]
fn is_rounding(c: f64, size: f64) -> bool {
    c.abs() <= 8.0 * f64::EPSILON * size
}

impl Integrator for Dd {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(_params: &[f64]) -> Result<Self, InputError> {
        Ok(Self::default())
    }
    fn label(&self) -> String {
        "DD".into()
    }
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        if self.fast_path && exact_energy::applies::<S, N, R>() {
            return exact_energy::step(sys, st, h);
        }
        if self.fast_path && dd_reduced::applies::<S, N, R>() {
            // Where the solve for σ fails (at rest at an equilibrium its closed form is 0/0),
            // the general one decides, out of line: inlined here it slowed every step by 4 %.
            return reduced_step(sys, st, h, &self.newton)
                .or_else(|_| self.general_step_out_of_line(sys, st, h));
        }
        self.general_step(sys, st, h)
    }
}

impl Dd {
    /// DD's step by the general `(q̇₁, λ)` solve.
    #[inline]
    fn general_step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let v_q0 = sys.passenger_potential(&st.q) + st.driver_potential_and_constraint(sys).0;
        let q0 = st.q;
        // Gonzalez's correction makes the Jacobian dense unless V is quadratic.
        let diagonal = S::QUADRATIC_PASSENGER && S::QUADRATIC_DRIVER;
        let gradient = |dq: &Vector<N>, mid: &DriverTerms<N, R>, end: &mut AngleTracker| {
            discrete_gradient(sys, (&q0, v_q0), dq, h, mid, end)
        };
        discrete_derivative_step(sys, st, h, &self.newton, diagonal, gradient)
    }

    /// [`Dd::general_step`] where it is the exception.
    #[cold]
    #[inline(never)]
    fn general_step_out_of_line<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        self.general_step(sys, st, h)
    }
}

/// A discrete gradient as the discrete-derivative steps take it: `(Δq, the driver's terms at
/// ζ̄, a tracker of ζ₁) ↦ (∇̄V(q₀, q₀ + Δq), its derivative with respect to q̇₁)`.
pub(crate) trait DiscreteGradient<const N: usize, const R: usize>:
    FnMut(&Vector<N>, &DriverTerms<N, R>, &mut AngleTracker) -> (Vector<N>, Matrix<N, N>)
{
}

impl<F, const N: usize, const R: usize> DiscreteGradient<N, R> for F where
    F: FnMut(&Vector<N>, &DriverTerms<N, R>, &mut AngleTracker) -> (Vector<N>, Matrix<N, N>)
{
}

/// One step of the discrete-derivative family (MATH.md §3) for a given discrete gradient:
/// `gradient(Δq, terms at ζ̄, tracker of ζ₁)` returns `∇̄V(q₀, q₀ + Δq)` and its derivative
/// with respect to `q̇₁`; if it evaluates the driver at ζ₁ through the tracker, the terms at
/// the step's end follow from its last iterate by a tiny rotation. `diagonal_gradient_jacobian`
/// says whether that derivative can be diagonal (then Newton's matrix is checked for the
/// shape that [`linalg::inverse_maybe_bordered`](crate::linalg) inverts cheaply). The general
/// `(q̇₁, λ)` solve, shared by `dd` (Gonzalez) and `dd_avf` (average vector field); DD's
/// faster solves are `exact_energy` (DD-AVF's too) and `dd_reduced`.
#[inline]
pub(crate) fn discrete_derivative_step<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    h: f64,
    newton: &NewtonConfig,
    diagonal_gradient_jacobian: bool,
    mut gradient: impl DiscreteGradient<N, R>,
) -> Result<(), StepFailure> {
    let (q0, v0) = (st.q, st.v);
    let (g0, a0) = st.gradient_and_constraint(sys);
    let euler = (v0 + h * (a0.transpose() * st.lambda - g0), st.lambda);
    let (mut mid, mut end) = (AngleTracker::new(), AngleTracker::new());
    let mut linearize = |v1: &Vector<N>, lambda: &Vector<R>| {
        let s = v0 + v1;
        let dq = s * (0.5 * h);
        let z_mid = q0[N - 1] + 0.5 * dq[N - 1];
        let at_mid = mid.terms(sys, z_mid);
        let (a_mid, da_mid) = (at_mid.constraint, at_mid.constraint_d);
        let (grad, jac) = gradient(&dq, &at_mid, &mut end);
        let mut b = Matrix::<N, N>::identity() + jac * h;
        // −h A(q̄)ᵀλ depends on q̇₁ through ζ̄ (dζ̄ = (h/4) dζ̇₁).
        let dforce = da_mid.transpose() * lambda * (-h * 0.25 * h);
        let mut c = a_mid * 0.5;
        let dcol = da_mid * s * (0.125 * h);
        for i in 0..N {
            b[(i, N - 1)] += dforce[i];
        }
        for r in 0..R {
            c[(r, N - 1)] += dcol[r];
        }
        Linearization {
            f1: v1 - v0 + h * grad - h * (a_mid.transpose() * lambda),
            f2: a_mid * s * 0.5,
            b,
            g: a_mid.transpose() * (-h),
            c,
            b_maybe_bordered: diagonal_gradient_jacobian,
            affine_but_for_the_driver: false,
        }
    };
    // Euler's guess with the driver's speed extrapolated from its last steps where they are
    // known (see `DriverHistory`); Euler's own if Newton fails from it.
    let extrapolated = st.driver_history.guess(&q0, &v0, h).map(|zeta_dot| {
        let mut v1 = euler.0;
        v1[N - 1] = zeta_dot;
        (v1, euler.1)
    });
    let (mut v1, mut lambda) = extrapolated.unwrap_or(euler);
    let mut fallback = extrapolated.is_some();
    // One call site, so that `solve` and the linearization stay inlined.
    loop {
        match solve(newton, &mut v1, &mut lambda, &mut linearize) {
            Ok(_) => break,
            Err(_) if fallback => (v1, lambda, fallback) = (euler.0, euler.1, false),
            Err(failure) => return Err(failure),
        }
    }
    st.advance_to((v0 + v1) * (0.5 * h), v1);
    st.lambda = lambda;
    st.driver_history.record((&q0, &v0), h, (&st.q, &st.v));
    // What the next step starts from and the integrals at q₁ need.
    let at_q1 = end.terms(sys, st.q[N - 1]);
    st.remember_at_end(at_q1.constraint, at_q1.potential, at_q1.potential_d1);
    Ok(())
}
