//! [`DriverHistory`]: the driver's last speed increments, from which DD guesses the driver's
//! speed at the end of its next step for Newton. Used where V_d is not quadratic
//! (`cvt_pendulum`, the mobile robot; where V is quadratic DD starts from the exact solution
//! instead): by the `(q̇₁, λ)` solve of DD and DD-AVF and by DD's solve for the
//! driver's speed ([`reduced`](super::reduced)).
//!
//! DD starts Newton from an explicit Euler step, accurate to O(h²). Most of that error is
//! harmless: the passenger's velocity and λ enter DD's equations (nearly) linearly, so Newton
//! removes their error in one iteration whatever its size. What costs iterations is the
//! error in the driver's speed ζ̇₁, which moves ζ̄ and with it A(ζ̄) and V_d: on the CVT, the
//! particle and the mobile robot it leaves three iterations for most steps at the paper's
//! h = 0.1. The driver evolves smoothly (only DD's passenger and λ zigzag from step to step),
//! so its next speed increment follows from the last three by cubic extrapolation,
//! `Δζ̇ₖ ≈ 3Δζ̇ₖ₋₁ − 3Δζ̇ₖ₋₂ + Δζ̇ₖ₋₃`, to O(h⁴). With it two iterations suffice on nearly all of
//! those steps. Extrapolating the passenger's increments and λ as well was tried and dropped: no
//! fewer iterations (the zigzag makes those guesses worse than Euler's), and a different rounding
//! that made DD's energy error on the knife edge grow linearly at h = 0.31 (10× more after 10⁸
//! steps). Where the driver does not accelerate (the knife edge) the guess is Euler's exactly.
//!
//! Keyed by the driver's `(ζ, ζ̇)` and the h of the step that ended there: a driver moved from
//! outside, a reversed velocity or a new step size starts over. A passenger moved from outside
//! keeps the guess, which is one for the driver's speed and still as good (Newton converges
//! from it to the same step, or falls back to Euler's). The key is two numbers, not `(q, q̇)`:
//! copying the vectors the step had just stored, in the pieces its compensated sums left,
//! stalled the next step on a store-to-load forwarding, which made DD on `cvt_pendulum` and the
//! mobile robot slower (the same stall is why [`EndOfStep`](crate::methods::memory::EndOfStep) is
//! keyed by ζ alone).

use crate::Vector;

/// The driver's last three speed increments (newest first), if they ended at `(ζ, ζ̇)`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DriverHistory<const N: usize> {
    zeta: f64,
    zeta_dot: f64,
    h: f64,
    increments: [f64; 3],
    len: usize,
}

impl<const N: usize> DriverHistory<N> {
    /// Knows nothing (NaN never equals a configuration).
    pub(crate) fn empty() -> Self {
        Self { zeta: f64::NAN, zeta_dot: f64::NAN, h: f64::NAN, increments: [0.0; 3], len: 0 }
    }

    /// Whether the recorded steps, of size `h`, ended at the driver's `(ζ, ζ̇)` of `(q, q̇)`.
    #[inline]
    fn ends_at(&self, q: &Vector<N>, v: &Vector<N>, h: f64) -> bool {
        self.h == h && self.zeta == q[N - 1] && self.zeta_dot == v[N - 1]
    }

    /// The extrapolated driver speed `ζ̇₁` after a step of size `h` from `(q, q̇)`, when the
    /// last three steps were of that size and ended there.
    #[inline]
    pub(crate) fn guess(&self, q: &Vector<N>, v: &Vector<N>, h: f64) -> Option<f64> {
        (self.len >= 3 && self.ends_at(q, v, h)).then(|| {
            let [d1, d2, d3] = self.increments;
            v[N - 1] + (3.0 * (d1 - d2) + d3)
        })
    }

    /// Follows a state moved from `from` to `to` that stands for the same configuration
    /// (whole turns of an angle taken off, `State::take_whole_turns`).
    #[inline]
    pub(crate) fn moved(&mut self, from: &Vector<N>, to: &Vector<N>) {
        if self.zeta == from[N - 1] {
            self.zeta = to[N - 1];
        }
    }

    /// Records a step of size `h` from `(q₀, q̇₀)` to `(q₁, q̇₁)`.
    #[inline]
    pub(crate) fn record(
        &mut self,
        (q0, v0): (&Vector<N>, &Vector<N>),
        h: f64,
        (q1, v1): (&Vector<N>, &Vector<N>),
    ) {
        let len = if self.ends_at(q0, v0, h) { self.len.min(2) + 1 } else { 1 };
        let [d1, d2, _] = self.increments;
        let (zeta, zeta_dot) = (q1[N - 1], v1[N - 1]);
        *self = Self { zeta, zeta_dot, h, increments: [zeta_dot - v0[N - 1], d1, d2], len };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::system::BuiltIn;
    use crate::methods::integrator::Stepper;
    use crate::methods::dd::DdMemory;
    use crate::methods::{Dd, DdAvf, Memory};
    use crate::model::systems::{CvtPendulum, MobileRobot, Particle};
    use crate::{NewtonConfig, State};

    #[test]
    fn extrapolates_a_cubic_exactly_and_forgets_a_moved_driver() {
        // ζ̇(t) = t³ sampled at t = k: increments of a cubic, so the guess is exact.
        let v = |k: f64| Vector::<2>::new(0.5, k * k * k);
        let q = |k: f64| Vector::<2>::new(0.0, k);
        let mut history = DriverHistory::<2>::empty();
        for k in 0..3 {
            let k = f64::from(k);
            assert!(history.guess(&q(k), &v(k), 1.0).is_none(), "fewer than three steps");
            history.record((&q(k), &v(k)), 1.0, (&q(k + 1.0), &v(k + 1.0)));
        }
        assert_eq!(history.guess(&q(3.0), &v(3.0), 1.0), Some(64.0));
        assert!(history.guess(&q(3.0), &(-v(3.0)), 1.0).is_none(), "a reversed velocity");
        assert!(history.guess(&q(3.0), &v(3.0), 0.5).is_none(), "another step size");
        // The guess is the driver's: a passenger moved from outside keeps it.
        let (q_moved, v_moved) = (Vector::<2>::new(7.0, 3.0), Vector::<2>::new(-2.0, 27.0));
        assert_eq!(history.guess(&q_moved, &v_moved, 1.0), Some(64.0));
        // A step from elsewhere starts the count again.
        history.record((&q(9.0), &v(9.0)), 1.0, (&q(10.0), &v(10.0)));
        assert!(history.guess(&q(10.0), &v(10.0), 1.0).is_none());
    }

    fn falls_back_to_euler<S, M, const N: usize, const R: usize>(sys: &S, preset: usize, m: &M)
    where
        S: BuiltIn<N, R>,
        M: Stepper<Memory<N, R> = DdMemory<N, R>>,
    {
        let p = &S::info().presets[preset];
        let (q, v) = (Vector::from_column_slice(p.q), Vector::from_column_slice(p.v));
        let mut st = State::with_continuous_multiplier(sys, q, v).unwrap();
        let mut mem = DdMemory::empty();
        for _ in 0..5 {
            m.step(sys, &mut st, &mut mem, 0.1).unwrap();
        }
        let (mut poisoned, mut poisoned_mem) = (st, mem);
        poisoned_mem.history.increments[0] = f64::NAN;
        let guess = poisoned_mem.history.guess(&st.q, &st.v, 0.1);
        assert!(guess.is_some_and(f64::is_nan), "a guess Newton cannot start from");
        m.step(sys, &mut poisoned, &mut poisoned_mem, 0.1).unwrap();
        mem.history = DriverHistory::empty();
        m.step(sys, &mut st, &mut mem, 0.1).unwrap();
        assert!((poisoned.q - st.q).amax() < 1e-13 && (poisoned.v - st.v).amax() < 1e-13);
    }

    #[test]
    fn a_guess_newton_fails_from_falls_back_to_euler() {
        let pendulum = CvtPendulum { epsilon: 0.5 };
        falls_back_to_euler(&pendulum, 3, &Dd::default());
        // DD-AVF's `(q̇₁, λ)` solve, which starts from the guess too.
        falls_back_to_euler(&pendulum, 3, &DdAvf::default());
        // DD's solve for the driver's speed (`dd::reduced`).
        falls_back_to_euler(&MobileRobot, 0, &Dd::default());
    }

    /// The largest (relative) difference between a step from the extrapolated guess and the
    /// same step from Euler's, along `steps` steps of `m`, and in how many steps the guess
    /// was used.
    fn guess_vs_euler<S, M, const N: usize, const R: usize>(
        sys: &S,
        m: &M,
        h: f64,
        steps: usize,
    ) -> (f64, usize)
    where
        S: BuiltIn<N, R>,
        M: Stepper<Memory<N, R> = DdMemory<N, R>>,
    {
        let p = &S::info().presets[0];
        let (q, v) = (Vector::from_column_slice(p.q), Vector::from_column_slice(p.v));
        let mut st = State::with_continuous_multiplier(sys, q, v).unwrap();
        let mut mem = DdMemory::empty();
        let (mut gap, mut used): (f64, usize) = (0.0, 0);
        for _ in 0..steps {
            used += usize::from(mem.history.guess(&st.q, &st.v, h).is_some());
            let (mut euler, mut euler_mem) = (st, mem);
            euler_mem.history = DriverHistory::empty();
            m.step(sys, &mut st, &mut mem, h).unwrap();
            m.step(sys, &mut euler, &mut euler_mem, h).unwrap();
            // Relative to the size of the numbers (ζ of a rotating driver grows to hundreds).
            let scale = 1.0 + st.q.amax().max(st.v.amax());
            gap = gap.max((st.q - euler.q).amax() / scale).max((st.v - euler.v).amax() / scale);
        }
        (gap, used)
    }

    #[test]
    fn the_guess_changes_no_step_beyond_round_off() {
        for (gap, used) in [
            guess_vs_euler(&CvtPendulum { epsilon: 0.5 }, &Dd::default(), 0.1, 2000),
            guess_vs_euler(&MobileRobot, &Dd::default(), 0.05, 2000),
            // The general path (where V is quadratic DD-AVF's default is DD's closed form).
            guess_vs_euler(&Particle, &DdAvf { fast_path: false, ..DdAvf::default() }, 0.1, 2000),
        ] {
            assert_eq!(used, 1997, "every step after the first three");
            // Both are within Newton's tolerance (10⁻¹⁴ relative) of the same solution.
            assert!(gap <= 3.0 * NewtonConfig::default().tol, "{gap:e}");
        }
    }
}
