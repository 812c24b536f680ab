//! DD where V is quadratic: its step in closed form, and the step's end in double-double, so
//! that the energy balance holds to ~10⁻³² and H stays at round-off however long the run.
//!
//! DD conserves H exactly in exact arithmetic. In doubles each step rounds q̇₁ and the
//! increment of q, and the energy balance is off by ~10⁻¹⁸ of H per step. Compensated
//! summation of q alone does not remove that: the rounding is made inside the step. Where
//! the rounded numbers repeat, it adds up linearly instead of like √N. The paper's knife edge
//! at h = π/10 is such a case: the discrete orbit has a period of 20 steps, and DD's energy
//! error grew to 2.5·10⁻¹¹ in 10⁸ steps.
//!
//! Where V is quadratic (the knife edge, `cvt`, `particle`, the rolling disk) Gonzalez's
//! correction vanishes but for rounding, and DD's discrete gradient is `∇V(q̄)`. On a coupled
//! system the step then has a closed form ([`step`]): the driver's equation is affine in ζ̇₁
//! alone, and once ζ̄ is known the passenger's is affine in one unknown along the kernel of
//! A(ζ̄). With `s = q̇₀ + q̇₁`, `Δq = (h/2) s` and `r = s − 2q̇₀ + h∇V(q̄)` the step's energy
//! change is exactly
//!
//! ```text
//! ΔH = ½ (q̇₁ − q̇₀)·s + ∇V(q̄)·Δq = ½ s·r.
//! ```
//!
//! The midpoint constraint makes `s = w k̃ + σ e_ζ` (`passenger_kernel`), so
//! `s·r = w F₁ + σ F₂` with `F₁ = k̃·r` and `F₂ = r_ζ`, the two projections of DD's
//! momentum equation ([`reduced`](super::reduced)). Both are affine in (w, σ) for quadratic V, and
//! do not couple them (U does not depend on ζ). So [`finish`] takes the step's (w, σ) as solved in
//! doubles, evaluates F₁ and F₂ there in double-double, with the state's q and q̇ as double-doubles
//! (their compensations are the low parts), corrects (w, σ) by one Newton step, which is then
//! exact, and moves the state to `q₀ + (h/2)s`, `s − q̇₀` in double-double. The energy balance
//! then holds to the double-double rounding, whatever k̃ and A(ζ̄) were rounded to (F₁ = 0
//! along the k̃ used is all `s·r = 0` needs). λ stays the double the step solved (it does not
//! enter the balance). The energy conserved is that of V's exact quadratic,
//! `∇V(q) = ∇V(0) + ∇²V q` with the system's own coefficients; the integrals evaluate it in
//! doubles, to an ulp of its terms.
//!
//! DD-AVF is the same method where V is quadratic (its average of an affine gradient is
//! `∇V(q̄)`), and takes this step there too.

use super::memory::DdMemory;
use crate::solver::angle_tracker::AngleTracker;
use crate::solver::double_double::{Dekker, DoubleDouble, Fused, Products, Sum2};
use crate::solver::passenger_kernel::{self, kernel};
use crate::model::system::System;
use crate::{State, StepFailure, Vector};
use crate::linalg;

/// Whether the closed form and the exact end apply: V quadratic (then the discrete gradient
/// is `∇V(q̄)` and both residuals are affine) on a system whose passenger kernel
/// `passenger_kernel` covers.
pub(crate) fn applies<S: System<N, R>, const N: usize, const R: usize>(sys: &S) -> bool {
    sys.quadratic_passenger() && sys.quadratic_driver() && passenger_kernel::covers::<N, R>()
}

/// One DD step in closed form, where it [`applies`]. In doubles:
/// `σ = ζ̇₀ + ζ̇₁` from the driver's affine equation `σ − 2ζ̇₀ + h V_d'(ζ₀ + hσ/4) = 0`; then
/// `Ā = A(ζ̄)` (one sine and cosine) and `w = k̃·P / k̃ᵀMk̃` with `P = 2q̇₀ − h∇V(q₀)`,
/// `M = I + h²∇²U/4` (the passenger rows projected on k̃, which removes λ); λ from the
/// residual those rows leave, `h Āᵀλ`. Then [`finish`] makes it exact.
#[inline]
pub(crate) fn step<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    mem: &mut DdMemory<N, R>,
    h: f64,
) -> Result<(), StepFailure> {
    let z = N - 1;
    // From the state's value rounded, compensations included: then the doubles this step
    // ends on are within an ulp or two of its exact end, and stay so over any number of
    // steps. (From `q`, `q̇` alone they would follow the doubles' own orbit, whose energy
    // drifts, and the compensations would grow to make up the difference.)
    let (q0, v0) = (st.q + st.q_compensation, st.v + st.v_compensation);
    let g0 = sys.gradient(&q0);
    let sigma = (2.0 * v0[z] - h * g0[z]) / (1.0 + 0.25 * h * h * sys.driver_potential_d2(q0[z]));
    let mut mid = AngleTracker::new();
    let a = mid.terms(sys, q0[z] + 0.25 * h * sigma).constraint;
    let k = kernel(&a);
    let stiffness = sys.passenger_hessian(&q0) * (0.25 * h * h);
    // The driver components of P and of the residual go unused: k̃ and Ā have none.
    let passenger = 2.0 * v0 - h * g0;
    let w = k.dot(&passenger) / k.dot(&(k + stiffness * k));
    let mut s = k * w;
    s[z] = sigma;
    let residual = s + stiffness * s - passenger;
    let lambda = linalg::solve(&(a * a.transpose()), &(a * residual))
        .ok_or(StepFailure::Singular)?
        * (1.0 / h);
    finish(sys, st, &Solved { k, w, sigma, v1: s - v0 }, h);
    st.lambda = lambda;
    // ζ₁'s sine and cosine rotated from ζ̄'s by Δζ/2 (`AngleTracker`), for what the next step
    // starts from and the integrals at q₁ need.
    let at_q1 = mid.terms(sys, st.q[z]);
    mem.end.remember(st, at_q1.constraint, at_q1.potential, at_q1.potential_d1);
    Ok(())
}

/// The step as [`step`] solved it in doubles: `s = q̇₀ + q̇₁ = w k̃ + σ e_ζ`, with k̃ at the
/// step's ζ̄, and q̇₁.
struct Solved<const N: usize> {
    /// k̃(ζ̄).
    k: Vector<N>,
    /// s's coordinate along k̃.
    w: f64,
    /// s's driver component, `ζ̇₀ + ζ̇₁`.
    sigma: f64,
    /// q̇₁.
    v1: Vector<N>,
}

/// Moves `st` (still at the step's start) to the end of the step `solved`, in double-double
/// (see the module's doc).
///
/// The state's doubles (`q`, `q̇`) are the closed form's own end, as `State::advance_to`
/// would leave them; the compensations get the exact remainders (they are small: the closed
/// form solved the same equations from the same state, to an ulp). The next step starts from
/// their sum, so it waits for this work: on `cvt` most of DD's time is spent here, and the closed
/// form is slower than DD's general solve; it is kept for accuracy, not speed
/// (`docs/performance.md`).
#[inline]
fn finish<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    solved: &Solved<N>,
    h: f64,
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") && std::arch::is_x86_feature_detected!("fma") {
        // SAFETY: `finish_fused` needs AVX and FMA, which this CPU has (checked just above).
        return unsafe { finish_fused(sys, st, solved, h) };
    }
    if cfg!(target_arch = "aarch64") {
        // Fused multiply–add is part of AArch64's base instruction set.
        finish_with::<S, N, R, Fused>(sys, st, solved, h);
    } else {
        finish_with::<S, N, R, Dekker>(sys, st, solved, h);
    }
}

/// [`finish_with`] compiled for AVX and FMA: its products are then one fused multiply–add
/// instead of Dekker's 17 operations, and its copies disappear with AVX's three-operand
/// instructions (DD on the knife edge is markedly faster for it). The build targets plain x86-64,
/// so this is chosen at run time.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
fn finish_fused<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &mut State<N, R>,
    solved: &Solved<N>,
    h: f64,
) {
    finish_with::<S, N, R, Fused>(sys, st, solved, h);
}

/// [`finish`], with the exact products of `P`.
#[inline]
fn finish_with<S: System<N, R>, const N: usize, const R: usize, P: Products>(
    sys: &S,
    st: &mut State<N, R>,
    &Solved { k, w, sigma, v1 }: &Solved<N>,
    h: f64,
) {
    let z = N - 1;
    let d = DoubleDouble::<P>::from;
    let (q, q_lo, v, v_lo) = (st.q, st.q_compensation, st.v, st.v_compensation);
    let q0 = |i: usize| DoubleDouble::<P>::new(q[i], q_lo[i]);
    let v0 = |i: usize| DoubleDouble::<P>::new(v[i], v_lo[i]);
    // The doubles: the closed form's end, q moved by Kahan's step as `advance_to` does.
    st.advance_to((v + v1) * (0.5 * h), v1);

    // V's coefficients: ∇V(q) = ∇V(0) + ∇²V q, driver and passenger apart. Terms with a zero
    // coefficient are skipped (they are exact zeros; the compiler drops the tests where the
    // system's coefficients are constants).
    let origin = Vector::<N>::zeros();
    let (b, stiffness) = (sys.passenger_gradient(&origin), sys.passenger_hessian(&origin));
    let (b_z, kappa) = (sys.driver_potential_d1(0.0), sys.driver_potential_d2(0.0));
    let quarter_h = 0.25 * h;

    // Driver: F₂(σ) = σ − 2ζ̇₀ + h(V_d'(0) + V_d'' ζ̄), ζ̄ = ζ₀ + (h/4)σ; F₂' = 1 + V_d''h²/4.
    let mut f2 = Sum2::<P>::new(sigma);
    f2.add_dd(v0(z).scaled(-2.0));
    if b_z != 0.0 {
        f2.add_product(d(h), d(b_z));
    }
    if kappa != 0.0 {
        let z_mid = q0(z) + DoubleDouble::product(sigma, quarter_h);
        f2.add_product(DoubleDouble::product(h, kappa), z_mid);
    }
    let driver_slope = 1.0 + quarter_h * h * kappa;

    // Passenger: F₁(w) = k̃·r, r = w k̃ − 2ẋ₀ + h∇U(x̄), x̄ = x₀ + (h/4) w k̃;
    // F₁' = k̃ᵀ(I + h²K/4)k̃.
    let mut f1 = Sum2::<P>::new(0.0);
    let mut slope = 0.0;
    for i in 0..z {
        let mut r = Sum2::<P>::new(0.0);
        r.add_product(d(w), d(k[i]));
        r.add_dd(v0(i).scaled(-2.0));
        if b[i] != 0.0 {
            r.add_product(d(h), d(b[i]));
        }
        let mut kk = 0.0;
        for j in 0..z {
            let kij = stiffness[(i, j)];
            if kij != 0.0 {
                let x_mid = q0(j) + DoubleDouble::product(w, k[j]) * quarter_h;
                r.add_product(DoubleDouble::product(h, kij), x_mid);
                kk += kij * k[j];
            }
        }
        f1.add_product(r.to_dd(), d(k[i]));
        slope += k[i] * (k[i] + quarter_h * h * kk);
    }

    // One Newton step on each (they are affine, and do not couple w and σ).
    let sigma = d(sigma) + -f2.to_f64() / driver_slope;
    let w = d(w) + -f1.to_f64() / slope;

    // The exact end, s = w k̃ + σ e_ζ, q̇₁ = s − q̇₀, q₁ = q₀ + (h/2) s: what the doubles
    // above leave out of it.
    for i in 0..N {
        let si = if i == z { sigma } else { DoubleDouble::product(w.hi, k[i]) + w.lo * k[i] };
        let mut v1 = Sum2::<P>::new(-st.v[i]);
        v1.add_dd(si);
        v1.add_dd(-v0(i));
        st.v_compensation[i] = v1.to_f64();
        let mut q1 = Sum2::<P>::new(-st.q[i]);
        q1.add_dd(q0(i));
        q1.add_product(si, d(0.5 * h));
        st.q_compensation[i] = q1.to_f64();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::system::BuiltIn;
    use crate::methods::integrator::Stepper;
    use crate::methods::{Dd, Memory};
    use crate::model::systems::{Cvt, KnifeEdge, RollingDisk};

    /// Both products are exact, so the two ends are the same to the bit: the one this machine
    /// does not take at run time is checked against the one it does.
    fn same_end_with_either_product<S: BuiltIn<N, R>, const N: usize, const R: usize>(sys: &S) {
        let p = &S::info().presets[0];
        let (q, v) = (Vector::from_column_slice(p.q), Vector::from_column_slice(p.v));
        let mut st = State::with_continuous_multiplier(sys, q, v).unwrap();
        let mut mem = DdMemory::empty();
        for _ in 0..1000 {
            // The doubles of a step (the general path's), ended both ways from the same state.
            let (mut general, mut general_mem) = (st, mem);
            Dd { fast_path: false, ..Dd::default() }
                .step(sys, &mut general, &mut general_mem, p.step)
                .unwrap();
            let s = st.v + general.v;
            let a = sys.constraint(st.q[N - 1] + 0.25 * p.step * s[N - 1]);
            let k = kernel(&a);
            let (w, sigma) = (k.dot(&s) / k.norm_squared(), s[N - 1]);
            let solved = Solved { k, w, sigma, v1: general.v };
            let (mut fused, mut dekker) = (st, st);
            finish_with::<S, N, R, Fused>(sys, &mut fused, &solved, p.step);
            finish_with::<S, N, R, Dekker>(sys, &mut dekker, &solved, p.step);
            assert_eq!(fused, dekker);
            assert!(fused.v_compensation.amax() > 0.0 || fused.q_compensation.amax() > 0.0);
            Dd::default().step(sys, &mut st, &mut mem, p.step).unwrap();
        }
    }

    #[test]
    fn fused_and_dekker_products_end_the_step_alike() {
        same_end_with_either_product(&KnifeEdge { epsilon: 0.1 });
        same_end_with_either_product(&Cvt);
        same_end_with_either_product(&RollingDisk);
    }
}
