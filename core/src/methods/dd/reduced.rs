//! DD's step on the mobile robot solved for one unknown, the driver's `σ = ζ̇₀ + ζ̇₁`: the same
//! equations as [`discrete_derivative_step`](super::step::discrete_derivative_step), which
//! solves for `N + R` unknowns.
//!
//! The midpoint constraint `A(q̄)(q̇₀ + q̇₁) = 0` says that `s = q̇₀ + q̇₁` lies in the kernel of
//! `A(ζ̄) = [A_x(ζ̄) | 0]`, which on a coupled system is spanned by `(k̃(ζ̄), 0)` and the
//! driver's axis (`docs/model.md` §1): `s = (w k̃, σ)`, `ζ̄ = ζ₀ + hσ/4`, `ζ₁ = ζ₀ + hσ/2`.
//! Projecting the momentum equation `s − 2q̇₀ + h∇̄V = h A(q̄)ᵀλ` on those two directions removes
//! λ. Where the passenger feels no potential (U ≡ 0, [`System::free_passenger`]) Gonzalez's
//! gradient is `V_d'(ζ̄) e_ζ + 2c s/(h|s|²)` with `c = V_d(ζ₁) − V_d(ζ₀) − V_d'(ζ̄) hσ/2`, a
//! function of σ alone, and the two projections read
//!
//! ```text
//! w a m = p,   σ m = r,   m = 1 + 2c/|s|²,   |s|² = w²a + σ²,
//! a = |k̃|²,   p = 2 k̃·q̇₀,   r = 2ζ̇₀ − h V_d'(ζ̄).
//! ```
//!
//! So `|s|² = E/m²` with `E = p²/a + r²`, m solves `2c m² − E m + E = 0`, and the root that
//! tends to 1 with c is `m = 2/(1 + √(1 − 8c/E))`: given σ, w follows in closed form, and
//! Newton solves `G(σ) = σ − r(1 + √(1 − 8c/E))/2 = 0`, one scalar equation, where the
//! two-unknown solve this replaced formed a 2×2 Jacobian from vectors on every iteration
//! and was slower. Both take two iterations from the driver's extrapolated speed
//! ([`DriverHistory`](crate::methods::dd::driver_history::DriverHistory)).
//!
//! q̇₁ comes from the last linearization and Newton's last increment (at most 10⁻⁹(1 + |σ|), so
//! that what its linear use leaves is below round-off: [`LINEAR_MAX`]), applied to q̇₁'s
//! components rather than to the rounded σ (whose grid is that of |q̇₀ + q̇₁|; left in the
//! energy balance, that rounding made DD's energy drift on the knife edge, `dd_roundoff`).
//! The w of that linearization is the closed form's, whose rounding Newton in σ never sees:
//! with `a` rounded near 2 (`|k̃|² = 2` on the disk) it biased DD's energy by 3·10⁻¹⁷ of H per
//! step (`tests/it/fast_path.rs`). So w's increment is the one a two-unknown Newton step would
//! take, from the projection `k̃·(s m − 2q̇₀)` of the residual at the linearization as
//! computed: unbiased (4·10⁻¹⁸), off the iteration's chain. `k̃` is not normalized: its
//! components are the cross product of A's two rows, so no square root enters but the one
//! above. Same steps as the general path to 10⁻¹³ (`tests/it/fast_path.rs`). Near rest at an
//! equilibrium c is its own rounding and E → 0, so `8c/E` has no meaning and this solve no
//! root: it fails, and DD takes the general solve, which drops such a c (`dd::is_rounding`,
//! `tests/it/at_rest.rs`).

use super::memory::DdMemory;
use crate::solver::angle_tracker::AngleTracker;
use crate::solver::newton::{NewtonConfig, solve_one};
use crate::solver::passenger_kernel::{self, kernel_and_derivative};
use crate::model::system::System;
use crate::{State, StepFailure, Vector};
use crate::linalg;

/// Whether DD takes this solve on a system: no passenger potential, two constraints whose
/// passenger kernel [`passenger_kernel`] covers, and V_d not quadratic (where V is quadratic
/// DD's step has a closed form, [`closed_form`](super::closed_form)). Of the test systems, the
/// mobile robot. This solve is less than 2× faster than its general one, the least a fast
/// path must gain, and is kept because without it DD on the mobile robot misses its speed
/// target (`docs/performance.md`).
pub(crate) fn applies<S: System<N, R>, const N: usize, const R: usize>(sys: &S) -> bool {
    sys.free_passenger() && !sys.quadratic_driver() && R == 2 && passenger_kernel::covers::<N, R>()
}

/// Largest last Newton increment in σ (relative to `1 + |σ|`) that the step's end takes
/// linearly, leaving an error of order `C δ²` with C ≈ 10⁻³. At h = 0.1 Newton's second
/// increments stay below ~2·10⁻¹¹, but it accepts ~0.1 % of steps after one iteration, whose
/// increments reach 2·10⁻⁷; at h = 0.3 its second increments reach 2·10⁻⁶, and without this
/// bound DD's energy drifted there by 3·10⁻¹⁵ of H per step (`tests/it/fast_path.rs`).
const LINEAR_MAX: f64 = 1e-9;

/// What the last linearization computed, from which the step's q̇₁ follows.
struct Last<const N: usize> {
    /// `q̇₀ + q̇₁` there, with w in closed form.
    s: Vector<N>,
    /// `k̃(ζ̄)` and `dk̃/dζ` there.
    k: Vector<N>,
    dk: Vector<N>,
    /// `w`, and Gonzalez's `c` and `dc/dσ`.
    w: f64,
    c: f64,
    dc: f64,
}

/// One DD step solved for σ (see the module's doc). Only where it [`applies`].
#[inline]
pub(crate) fn step<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    mem: &mut DdMemory<N, R>,
    h: f64,
    newton: &NewtonConfig,
) -> Result<(), StepFailure> {
    let (q0, v0) = (st.q, st.v);
    let z0 = q0[N - 1];
    let v_q0 = mem.end.driver_potential_and_constraint(sys, st).0;
    let g0 = mem.end.gradient_and_constraint(sys, st).0;
    let (mut mid, mut end) = (AngleTracker::new(), AngleTracker::new());
    // σ from the driver's last steps, Euler's otherwise, and Euler's again if Newton fails
    // from the extrapolated one (as the general path does).
    let euler = 2.0 * v0[N - 1] - h * g0[N - 1];
    let (start, fallback) = match mem.history.guess(&q0, &v0, h) {
        Some(zeta_dot) => (v0[N - 1] + zeta_dot, Some(euler)),
        None => (euler, None),
    };
    // d/dσ of ζ̄ and of ζ₁.
    let (quarter, half) = (0.25 * h, 0.5 * h);
    let mut last = None;
    let mut f = |sigma: f64| {
        let at_mid = mid.terms(sys, z0 + quarter * sigma);
        let at_end = end.terms(sys, z0 + half * sigma);
        let (k, dk) = kernel_and_derivative(&at_mid.constraint, &at_mid.constraint_d);
        let (a, p) = (k.norm_squared(), 2.0 * k.dot(&v0));
        let r = 2.0 * v0[N - 1] - h * at_mid.potential_d1;
        let c = at_end.potential - v_q0 - at_mid.potential_d1 * (half * sigma);
        // Their derivatives with respect to σ.
        let (k_dk, dk_v0) = (k.dot(&dk), dk.dot(&v0));
        let da = 2.0 * k_dk * quarter;
        let dp = 2.0 * dk_v0 * quarter;
        let dr = -h * at_mid.potential_d2 * quarter;
        let dc = (at_end.potential_d1
            - at_mid.potential_d1
            - 0.5 * at_mid.potential_d2 * (half * sigma))
            * half;
        // x = 8c/E = 8ca/(p² + ar²).
        let pp = p * p + a * r * r;
        let dpp = 2.0 * p * dp + da * r * r + 2.0 * a * r * dr;
        let (x, dx) = (8.0 * c * a / pp, 8.0 * ((dc * a + c * da) - c * a * dpp / pp) / pp);
        // G' needs x'/√(1 − x): as √(1 − x) · 1/(1 − x), whose division runs beside the root.
        let (root, over) = ((1.0 - x).sqrt(), 1.0 / (1.0 - x));
        let g = sigma - 0.5 * r * (1.0 + root);
        let dg = 1.0 - 0.5 * dr * (1.0 + root) + 0.25 * r * dx * (root * over);
        // w = p/(am), in closed form given σ.
        let w = p * (1.0 + root) / (2.0 * a);
        let mut s = k * w;
        s[N - 1] = sigma;
        last = Some(Last { s, k, dk, w, c, dc });
        (g, dg)
    };
    let (mut sigma, mut fallback) = (start, fallback);
    let d_sigma = loop {
        match (solve_one(newton, &mut sigma, LINEAR_MAX, &mut f), fallback.take()) {
            (Ok(d), _) => break d,
            (Err(_), Some(euler)) => sigma = euler,
            (Err(failure), None) => return Err(failure),
        }
    };
    let Last { s: s_lin, k, dk, w, c, dc } = last.ok_or(StepFailure::Singular)?;
    // As the last linearization computed them (the same operations, so the same numbers).
    let (a, p) = (k.norm_squared(), 2.0 * k.dot(&v0));
    let (k_dk, dk_v0) = (k.dot(&dk), dk.dot(&v0));
    // The two-unknown Newton step's w increment `−(F₁ + ∂F₁/∂σ δσ) / (∂F₁/∂w)` from there,
    // with F₁ = k̃·(s m − 2q̇₀) from s as rounded, m = 1 + g, g = 2c/|s|². Both slopes exact:
    // with ∂F₁/∂w ≈ a m alone (off by g, 10⁻⁵ at h = 0.1 but growing like h³), DD's energy
    // drifted by 2·10⁻¹⁶ of H per step at h = 0.5.
    let sigma_lin = s_lin[N - 1];
    let ks = k.dot(&s_lin);
    let d = w * w * a + sigma_lin * sigma_lin;
    let dd = 2.0 * (quarter * w * w * k_dk + sigma_lin);
    let over_d = 1.0 / d;
    let g = 2.0 * c * over_d;
    let (m, dm) = (1.0 + g, 2.0 * (dc - c * dd * over_d) * over_d);
    let mut ds_sigma = dk * (quarter * w);
    ds_sigma[N - 1] = 1.0;
    let dw_dsigma = quarter * (2.0 * m * w * k_dk - 2.0 * dk_v0) + dm * ks;
    // ∂F₁/∂w = a m + (k̃·s) ∂m/∂w, ∂m/∂w = −2g a w/|s|². Its reciprocal is off the chain that
    // waits on δσ. One reciprocal of |s|² instead of three divisions by it: slightly faster.
    let inv = -1.0 / (a * (m - 2.0 * g * w * ks * over_d));
    let dw = ((ks * m - p) + dw_dsigma * d_sigma) * inv;
    let v1 = (s_lin - v0) + (ds_sigma * d_sigma + k * dw);
    let s = v0 + v1;
    // h A(q̄)ᵀλ is the residual at the solution, with A(ζ̄) there: the last linearization's is
    // off by Newton's last increment in σ, which would show in λ.
    let at_mid = mid.terms(sys, z0 + quarter * sigma);
    let at_end = end.terms(sys, z0 + half * sigma);
    let c = at_end.potential - v_q0 - at_mid.potential_d1 * (half * sigma);
    let mut residual = s * (1.0 + 2.0 * c / s.norm_squared()) - 2.0 * v0;
    residual[N - 1] += h * at_mid.potential_d1;
    let a = at_mid.constraint;
    st.lambda = linalg::solve(&(a * a.transpose()), &(a * residual * (1.0 / h)))
        .ok_or(StepFailure::Singular)?;
    st.advance_to(s * (0.5 * h), v1);
    mem.history.record((&q0, &v0), h, (&st.q, &st.v));
    let at_q1 = end.terms(sys, st.q[N - 1]);
    mem.end.remember(st, at_q1.constraint, at_q1.potential, at_q1.potential_d1);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::step;
    use crate::methods::dd::DdMemory;
    use crate::methods::integrator::Stepper;
    use crate::methods::{Dd, Memory};
    use crate::model::systems::MobileRobot;
    use crate::{NewtonConfig, State, Vector};

    /// From rest away from an equilibrium (`p = 0`: the passenger's share of E vanishes) this
    /// solve takes the steps, and they are the general path's.
    #[test]
    fn steps_from_rest_as_the_general_path_does() {
        let general = Dd { fast_path: false, ..Dd::default() };
        for zeta in [0.3, 2.0] {
            let q = Vector::<4>::new(0.0, 0.0, 0.0, zeta);
            let st = State::with_continuous_multiplier(&MobileRobot, q, Vector::zeros()).unwrap();
            let (mut fast, mut slow) = (st, st);
            let (mut fast_mem, mut slow_mem) = (DdMemory::empty(), DdMemory::empty());
            for _ in 0..10 {
                let newton = NewtonConfig::ENERGY_CONSERVING;
                step(&MobileRobot, &mut fast, &mut fast_mem, 0.1, &newton).unwrap();
                general.step(&MobileRobot, &mut slow, &mut slow_mem, 0.1).unwrap();
            }
            assert!(fast.q.iter().chain(fast.v.iter()).all(|x| x.is_finite()));
            assert!((fast.q - slow.q).amax() < 1e-13 && (fast.v - slow.v).amax() < 1e-13);
            assert!(fast.v[3] != 0.0, "the driver moved");
        }
    }
}
