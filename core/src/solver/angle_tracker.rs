//! [`AngleTracker`]: the driver's terms along a Newton iteration, with `sin ζ` and `cos ζ`
//! carried from one iterate to the next.
//!
//! An implicit step evaluates `A`, `V_d` and their derivatives at every Newton iterate, and
//! where ζ is an angle each evaluation costs a `sin_cos` on the iteration's critical path.
//! After the first iterate ζ moves by the Newton increment only (10⁻⁴, then 10⁻⁸), so the
//! new sine and cosine follow from the last ones by a rotation through that small angle,
//! whose own sine and cosine are short Taylor polynomials: a few multiplications instead of
//! a library call. The rotated values stay within 2ε of `sin_cos`'s (tested), and a
//! tracker lives for one step, so nothing accumulates from step to step.
//!
//! A larger jump, up to ¼ (from ζ̄ to ζ₁ in a step), is rotated too, with longer polynomials
//! (within 2ε of `sincos` too, 1ε at worst in the tests); the last Newton increment, below 10⁻⁹
//! (from the final iterate to the solution), to first order, which is exact there.
//!
//! Where it does evaluate, it takes the `libm` crate's `sincos` (musl's, within an ulp, in
//! Rust) rather than the system's: inlined into the step, without glibc's call and its
//! rounding-mode save and restore, it overlaps with the rest of the step, which makes DD, DD-AVF
//! and DLA^α faster on the angle-driven systems. The systems' own functions keep the standard
//! library's: a step that calls several of them at one ζ shares one call to that, which the
//! compiler cannot do for an inlined `sincos` (with the crate's there too, leap-frog, RK4 and
//! DLA^{0,1} were markedly slower).

use crate::model::system::{DriverTerms, System};

/// Largest change of ζ taken by rotation. Below it the Taylor polynomials below are exact
/// to double precision: the first neglected terms, `d⁵/120` and `d⁶/720`, are < 10⁻¹⁷, a
/// twentieth of an ulp of 1. They are kept this short because they sit on the iteration's
/// critical path.
const ROTATE_MAX: f64 = 1e-3;
/// Largest change of ζ taken by rotation with longer polynomials (see `sin_cos`); beyond it
/// ζ is evaluated.
const ROTATE_FAR_MAX: f64 = 0.25;
/// Largest change of ζ taken by a first-order rotation: the first neglected terms, `d²/2`
/// times sin or cos, are below 5·10⁻¹⁹, a fortieth of an ulp of 1. Such changes are the last
/// Newton increment, between the final iterate and the solution (the driver's terms at the
/// solution, those at the step's end), and those terms start the next step's chain, which the
/// shorter rotation shortens: DD's step on the mobile robot and DLA^α's on `cvt_pendulum` are
/// faster for it. A tier between this and [`ROTATE_MAX`] (second order, up to 3·10⁻⁶) was slower on
/// the mobile robot: Newton's second increments straddle it, and its branch mispredicts.
const ROTATE_LINEAR_MAX: f64 = 1e-9;

/// The last ζ evaluated, with its sine and cosine.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AngleTracker {
    zeta: f64,
    sin: f64,
    cos: f64,
}

impl AngleTracker {
    /// A tracker that has seen no ζ yet (its first evaluation calls `sin_cos`).
    #[inline]
    pub(crate) fn new() -> Self {
        Self { zeta: f64::NAN, sin: f64::NAN, cos: f64::NAN }
    }

    /// `sin ζ` and `cos ζ`: rotated from the last ζ when it is within [`ROTATE_MAX`] (or,
    /// with longer polynomials, [`ROTATE_FAR_MAX`]), evaluated otherwise.
    #[inline]
    pub(crate) fn sin_cos(&mut self, zeta: f64) -> (f64, f64) {
        // Exact (Sterbenz) whenever the two are within a factor of two, i.e. always here but
        // within 2·10⁻³ of 0, where the error is below ulp(10⁻³) anyway. NaN (no last ζ)
        // fails the test.
        let d = zeta - self.zeta;
        let (s, c) = if d.abs() <= ROTATE_LINEAR_MAX {
            (self.sin + self.cos * d, self.cos - self.sin * d)
        } else if d.abs() <= ROTATE_MAX {
            let d2 = d * d;
            let sin_d = d - d * d2 * (1.0 / 6.0);
            let cos_d_m1 = d2 * (d2 * (1.0 / 24.0) - 0.5);
            self.rotated(sin_d, cos_d_m1)
        } else if d.abs() <= ROTATE_FAR_MAX {
            // The same rotation with the polynomials to d¹¹ and d¹²: the first neglected
            // terms, d¹³/13! and d¹⁴/14!, are below 2.4·10⁻¹⁸ at d = ¼. Off the Newton chain
            // (a jump between ζ̄ and ζ₁), where they replace a library call.
            let d2 = d * d;
            let sin_d = d + d
                * d2
                * (-1.0 / 6.0
                    + d2 * (1.0 / 120.0
                        + d2 * (-1.0 / 5040.0
                            + d2 * (1.0 / 362_880.0 + d2 * (-1.0 / 39_916_800.0)))));
            let cos_d_m1 = d2
                * (-0.5
                    + d2 * (1.0 / 24.0
                        + d2 * (-1.0 / 720.0
                            + d2 * (1.0 / 40_320.0
                                + d2 * (-1.0 / 3_628_800.0 + d2 * (1.0 / 479_001_600.0))))));
            self.rotated(sin_d, cos_d_m1)
        } else {
            libm::sincos(zeta)
        };
        *self = Self { zeta, sin: s, cos: c };
        (s, c)
    }

    /// The tracked sine and cosine rotated by an angle d, given `sin d` and `cos d − 1`.
    #[inline]
    fn rotated(&self, sin_d: f64, cos_d_m1: f64) -> (f64, f64) {
        // The small corrections added last, so that the rounding is that of one sum.
        (
            self.sin + (self.cos * sin_d + self.sin * cos_d_m1),
            self.cos + (self.cos * cos_d_m1 - self.sin * sin_d),
        )
    }

    /// The driver's terms at ζ: from the tracked sine and cosine where ζ is an angle, as the
    /// system evaluates them otherwise. Always inlined: on a system given as formulas the call
    /// to its code made this too large for the compiler's own choice, and out of line it slowed
    /// the implicit steps there.
    #[inline(always)]
    pub(crate) fn terms<S: System<N, R>, const N: usize, const R: usize>(
        &mut self,
        sys: &S,
        zeta: f64,
    ) -> DriverTerms<N, R> {
        if sys.zeta_is_angle() {
            let (s, c) = self.sin_cos(zeta);
            sys.driver_terms_trig(zeta, s, c)
        } else {
            sys.driver_terms(zeta)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_stay_within_two_epsilon_of_sin_cos() {
        use libm::sincos as sin_cos;
        // A Newton-like sequence per start: one jump, then shrinking increments, from ζ near
        // 0 to the ~7000 a rotating driver reaches.
        let mut worst: f64 = 0.0;
        for k in 0..20_000 {
            let z0 = (k as f64 * 0.7317).sin() * 10f64.powi(k % 5 - 1) + (k % 7) as f64 * 1000.0;
            let mut t = AngleTracker::new();
            let mut z = z0;
            for inc in [0.3, 9e-4, -3e-6, 1e-9, 9.9e-10, -4e-13, 0.0] {
                z += inc;
                let (s, c) = t.sin_cos(z);
                let (s0, c0) = sin_cos(z);
                worst = worst.max((s - s0).abs()).max((c - c0).abs());
            }
        }
        // The worst difference seen is 1 ε; the bound leaves a factor of 2.
        assert!(worst <= 2.0 * f64::EPSILON, "worst difference {worst:e}");
    }

    /// One far rotation (as from ζ̄ to ζ₁, up to ¼), from an evaluation or after a Newton-like
    /// chain of near ones, stays as close to `sincos` as the near ones do.
    #[test]
    fn far_rotations_stay_within_two_epsilon_of_sin_cos() {
        use libm::sincos as sin_cos;
        let mut worst: f64 = 0.0;
        for k in 0..20_000 {
            let z0 = (k as f64 * 0.7317).sin() * 10f64.powi(k % 5 - 1) + (k % 7) as f64 * 1000.0;
            let jump = 0.25 * (k as f64 * 0.377).sin();
            for near in [&[][..], &[9e-4, -3e-6, 1e-9][..]] {
                let mut t = AngleTracker::new();
                let mut z = z0;
                t.sin_cos(z);
                for inc in near {
                    z += inc;
                    t.sin_cos(z);
                }
                let (s, c) = t.sin_cos(z + jump);
                let (s0, c0) = sin_cos(z + jump);
                worst = worst.max((s - s0).abs()).max((c - c0).abs());
            }
        }
        // The worst difference seen is 1 ε; the bound leaves a factor of 2.
        assert!(worst <= 2.0 * f64::EPSILON, "worst difference {worst:e}");
    }

    /// The evaluation agrees with the standard library's `sin_cos` to two ulps (each is within
    /// one of the exact value), for ζ from 10⁻⁸ to 10⁶, across the argument reductions.
    #[test]
    fn evaluations_agree_with_the_standard_library() {
        let ulps = |a: f64, b: f64| (a - b).abs() / (f64::EPSILON * a.abs().max(b.abs()));
        let mut worst: f64 = 0.0;
        for k in 0..200_000 {
            let x = (f64::from(k) * 0.618_033_988_749_895).fract() * 10f64.powi(k % 15 - 8);
            for x in [x, -x] {
                let ((s, c), (s0, c0)) = (AngleTracker::new().sin_cos(x), x.sin_cos());
                worst = worst.max(ulps(s, s0)).max(ulps(c, c0));
            }
        }
        assert!(worst <= 2.0, "{worst} ulps");
    }

    #[test]
    fn a_first_or_a_large_change_is_evaluated() {
        use libm::sincos as sin_cos;
        let mut t = AngleTracker::new();
        assert_eq!(t.sin_cos(1.0), sin_cos(1.0));
        assert_eq!(t.sin_cos(1.3), sin_cos(1.3));
        assert!(t.sin_cos(f64::NAN).0.is_nan());
        assert_eq!(t.sin_cos(2.0), sin_cos(2.0));
    }
}
