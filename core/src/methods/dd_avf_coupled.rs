//! DD-AVF's coupled fast path: the driver alone, then the passenger as one linear problem.
//!
//! On a coupled system (A depends on ζ only and has no driver column) the average vector
//! field splits `V = U(x) + V_d(ζ)`, and DD-AVF's driver row reads
//!
//! ```text
//! ζ̇₁ − ζ̇₀ + h ḡ(ζ₀, ζ₁) = 0,   ḡ = (V_d(ζ₁) − V_d(ζ₀))/(ζ₁ − ζ₀),   ζ₁ = ζ₀ + h(ζ̇₀ + ζ̇₁)/2:
//! ```
//!
//! one scalar equation that does not see the passenger, solved by scalar Newton (a single
//! step where V_d is quadratic, which makes it affine). With ζ₁, hence ζ̄ and `Ā = A(ζ̄)`,
//! known and U quadratic (the average of its affine gradient is `∇U(x̄)`, with Hessian K),
//! the rest is linear:
//!
//! ```text
//! M s − h Āᵀλ = 2q̇₀ − h∇U(q₀),   Ā s = 0,   s = q̇₀ + q̇₁,   M = I + h²K/4
//! ```
//!
//! (passenger rows). The constraint makes `s = w k̃(ζ̄)` plus its driver component
//! ([`passenger_kernel`](crate::passenger_kernel)), and projecting on `k̃` removes λ:
//! `w = k̃·(2q̇₀ − h∇U(q₀)) / k̃ᵀM k̃`, one division; λ follows from the residual by one R×R
//! solve. The general path factors an `N + R` system on every Newton iteration. This is the
//! fast path issue 4 describes; the same equations give the same steps as the general path to
//! 10⁻¹³ (`tests/fast_path.rs`), and the speed is in `docs/benchmarks.md`. DD (Gonzalez's
//! gradient) has no such split: its correction term couples the driver's row to the
//! passenger's motion.

use super::dd_avf::avf_driver_mean;
use crate::angle_tracker::AngleTracker;
use crate::newton::{NewtonConfig, solve_affine_scalar, solve_scalar};
use crate::passenger_kernel::{self, kernel};
use crate::system::System;
use crate::{State, StepFailure, linalg};

/// Whether the split applies: U quadratic, so that the passenger's problem is linear once the
/// driver is known, and a passenger kernel that `passenger_kernel` covers (every test system).
pub(crate) const fn applies<S: System<N, R>, const N: usize, const R: usize>() -> bool {
    S::QUADRATIC_PASSENGER && passenger_kernel::covers::<N, R>()
}

/// One DD-AVF step by the split of the module's doc (only where it [`applies`]).
#[inline]
pub(crate) fn coupled_step<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    h: f64,
    newton: &NewtonConfig,
) -> Result<(), StepFailure> {
    let (q0, v0) = (st.q, st.v);
    let (z0, zd0) = (q0[N - 1], v0[N - 1]);
    let g0 = st.gradient(sys);
    let vd0 = st.driver_potential_and_constraint(sys).0;
    // The driver alone, in ζ̇₁. Its guess: extrapolated from the last steps where they are
    // known (`DriverHistory`), Euler's otherwise, and Euler's again if Newton fails from the
    // extrapolated one (as the general path does).
    let euler = zd0 - h * g0[N - 1];
    let extrapolated = st.driver_history.guess(&q0, &v0, h);
    let mut end = AngleTracker::new();
    let zd1 = if S::QUADRATIC_DRIVER {
        // ḡ = V_d'(ζ̄) = V_d'(ζ₀) + V_d''·Δζ/2 exactly: affine, one step solves it.
        let d2 = sys.driver_potential_d2(z0);
        let mut zd1 = extrapolated.unwrap_or(euler);
        solve_affine_scalar(&mut zd1, |zd1| {
            let dz = 0.5 * h * (zd0 + zd1);
            (zd1 - zd0 + h * (g0[N - 1] + 0.5 * d2 * dz), 1.0 + 0.25 * h * h * d2)
        })?;
        zd1
    } else {
        let mut driver = |zd1: f64| {
            let (g, dg) = avf_driver_mean(sys, (z0, vd0), 0.5 * h * (zd0 + zd1), &mut end);
            // dΔζ/dζ̇₁ = h/2.
            (zd1 - zd0 + h * g, 1.0 + 0.5 * h * h * dg)
        };
        let mut zd1 = extrapolated.unwrap_or(euler);
        match solve_scalar(newton, &mut zd1, &mut driver) {
            Ok(_) => zd1,
            Err(_) if extrapolated.is_some() => {
                zd1 = euler;
                solve_scalar(newton, &mut zd1, &mut driver)?;
                zd1
            }
            Err(failure) => return Err(failure),
        }
    };
    // The passenger, with Ā = A(ζ̄) (see the module's doc).
    let z_mid = z0 + 0.25 * h * (zd0 + zd1);
    let mut mid = AngleTracker::new();
    let a_mid = mid.terms(sys, z_mid).constraint;
    if S::QUADRATIC_DRIVER {
        // Newton evaluated nothing at ζ₁: its sine and cosine are rotated from ζ̄'s by Δζ/2
        // (a polynomial, not a library call, for |Δζ/2| ≤ ¼; `AngleTracker`). Where V_d is
        // not quadratic, rotating ζ̄'s from ζ₁'s instead measured slower (cvt_pendulum
        // 122 → 131 ns/step): it puts the polynomial on the step's chain after Newton.
        end = mid;
    }
    // `g0` is ∇V(q₀); its driver component goes into `passenger` unused (k̃ and Ā have none).
    let k = kernel(&a_mid);
    let stiffness = sys.passenger_hessian(&q0) * (0.25 * h * h);
    let passenger = 2.0 * v0 - h * g0;
    let mk = k + stiffness * k;
    let inverse_kmk = 1.0 / k.dot(&mk);
    let mut v1 = k * (k.dot(&passenger) * inverse_kmk) - v0;
    v1[N - 1] = zd1;
    // One step of iterative refinement, on the constraint's and the projected equation's
    // residuals at q̇₁ as rounded (q̇₁ = s − q̇₀ is rounded to the grid of s). Without it
    // DD-AVF's energy error after 10⁵ steps was 20–300× the general path's (knife edge
    // 6.8·10⁻¹², particle 3.8·10⁻¹², against 8·10⁻¹⁴ and 1.3·10⁻¹⁴); with it, the same order.
    let aat_inv = linalg::inverse(&(a_mid * a_mid.transpose())).ok_or(StepFailure::Singular)?;
    let s1 = v0 + v1;
    let across = a_mid.transpose() * (aat_inv * (a_mid * s1)) * -1.0;
    let r1 = s1 + stiffness * s1 - passenger;
    v1 += k * (-(k.dot(&r1) + mk.dot(&across)) * inverse_kmk) + across;
    // That correction has no driver component, but written through it ζ̇₁ would make the next
    // step's driver wait for this step's passenger (DD-AVF on `cvt_pendulum` 127 → 156
    // ns/step).
    v1[N - 1] = zd1;
    // h Āᵀλ is the residual of the passenger's rows (Ā has no driver column).
    let s = v0 + v1;
    let lambda = aat_inv * (a_mid * (s + stiffness * s - passenger)) * (1.0 / h);
    st.advance_to((v0 + v1) * (0.5 * h), v1);
    st.lambda = lambda;
    st.driver_history.record((&q0, &v0), h, (&st.q, &st.v));
    // What the next step starts from and the integrals at q₁ need; the tracker rotates from
    // Newton's last ζ₁. (The same ending as `discrete_derivative_step`'s: a function shared
    // by the two changed what the compiler inlined, DD-AVF 59 → 89 ns/step on the knife edge.)
    let at_q1 = end.terms(sys, st.q[N - 1]);
    st.remember_at_end(at_q1.gradient(sys, &st.q), at_q1.constraint, at_q1.potential);
    Ok(())
}
