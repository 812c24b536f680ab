//! Whole turns of an angle ζ, taken off the state and counted.
//!
//! Where ζ is an angle ([`zeta_is_angle`](crate::System::zeta_is_angle): `A` and `V_d` are
//! 2π-periodic and `U` does not depend on ζ) the driver ([`crate::measure::simulate::run`]) keeps ζ
//! within [−π, π]: ζ is stored to ulp(ζ) and the systems' functions see only the stored value, so
//! on a rotating driver, where ζ grows without bound, their inputs lost digits as the run went on.
//! At ζ = 3·10⁴ (ulp 4·10⁻¹²) that rounding made DD's energy error walk to 2.6·10⁻¹¹ of H in 10⁵
//! steps of the rotating, perturbed CVT; within a turn it stays at 7·10⁻¹⁴ (`docs/stability.md`). A
//! turn is taken off in two parts (Cody and Waite): `k·TAU_HI` exactly, the rest through the
//! compensation that already carries q's rounding, so the configuration the state stands for moves
//! by 2π to 10⁻²³ per turn. The driver counts the turns and puts them back where ζ is wanted as the
//! run started it (the latitude's sections, the final state).

use crate::methods::memory::Recall;
use crate::solver::double_double::two_sum;
use crate::{State, Vector};
use std::f64::consts::{PI, TAU};

impl<const N: usize, const R: usize> State<N, R> {
    /// Takes whole turns off ζ once it has left [−π, π], for a system whose ζ is an angle
    /// ([`zeta_is_angle`](crate::System::zeta_is_angle): `A` and `V_d` are 2π-periodic and `U`
    /// does not depend on ζ, so the steps and the integrals are those of the same state), and
    /// rekeys to the new q what `memory` had keyed by the old one. Returns the turns taken.
    ///
    /// Why: ζ is stored to ulp(ζ), and the systems' functions see only the stored ζ; on a
    /// rotating driver ζ grows without bound (see the module's doc).
    #[inline]
    pub fn take_whole_turns(&mut self, memory: &mut impl Recall<N, R>) -> f64 {
        let zeta = self.q[N - 1];
        // Not taken for |ζ| ≤ π, nor for NaN (whose run ends on it).
        if zeta.abs() > PI { self.take_turns(zeta, memory) } else { 0.0 }
    }

    /// `q` with `turns` whole turns (as [`State::take_whole_turns`] counted them) put back
    /// on ζ: the configuration in the coordinates the run started in, to ulp of its ζ.
    #[inline]
    pub(crate) fn q_with_turns(&self, turns: f64) -> Vector<N> {
        let mut q = self.q;
        if turns != 0.0 {
            q[N - 1] = turns * TAU_HI + (q[N - 1] + (self.q_compensation[N - 1] + turns * TAU_LO));
        }
        q
    }

    /// The rare part of [`State::take_whole_turns`], out of line so that the test inlines.
    #[inline(never)]
    fn take_turns(&mut self, zeta: f64, memory: &mut impl Recall<N, R>) -> f64 {
        let k = (zeta / TAU).round().clamp(-MAX_TURNS, MAX_TURNS);
        // k·TAU_HI is exact; the difference is too but where ζ is huge, and two_sum keeps
        // what it rounds away either way.
        let (s, e) = two_sum(zeta, -(k * TAU_HI));
        let (s, e) = two_sum(s, e + (self.q_compensation[N - 1] - k * TAU_LO));
        let from = self.q;
        (self.q[N - 1], self.q_compensation[N - 1]) = (s, e);
        memory.moved(&from, &self.q);
        k
    }
}

/// 2π in two parts: `TAU_HI` has 26 significant bits, so `k·TAU_HI` is exact for
/// |k| ≤ [`MAX_TURNS`], and `TAU_HI + TAU_LO` is 2π to 2.5·10⁻²⁴.
const TAU_HI: f64 = 6.283_185_243_606_567; // 0x1.921fb5p+2
const TAU_LO: f64 = 6.357_301_909_411_278e-8;
/// Most turns taken at once (only a start far out takes more than one; it takes the rest on
/// the following steps).
const MAX_TURNS: f64 = (1u64 << 26) as f64;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::system::BuiltIn;

    use crate::methods::integrator::Stepper;
    use crate::model::systems::CvtPendulum;

    #[test]
    fn whole_turns_leave_the_configuration() {
        use crate::methods::Dd;
        use crate::methods::Memory;
        use crate::methods::dd::DdMemory;
        let sys = CvtPendulum { epsilon: 0.5 };
        let p = &CvtPendulum::info().presets[3];
        let (q, v) = (Vector::from_column_slice(p.q), Vector::from_column_slice(p.v));
        let mut st = State::with_continuous_multiplier(&sys, q, v).unwrap();
        let mut mem = DdMemory::empty();
        assert_eq!(st.take_whole_turns(&mut mem), 0.0, "ζ within [−π, π] stays");
        let (mut kept, mut kept_mem, mut turns) = (st, mem, 0.0);
        for k in 0..2000 {
            Dd::default().step(&sys, &mut st, &mut mem, 0.1).unwrap();
            Dd::default().step(&sys, &mut kept, &mut kept_mem, 0.1).unwrap();
            let before = kept;
            let taken = kept.take_whole_turns(&mut kept_mem);
            turns += taken;
            if taken != 0.0 {
                // Same configuration, in other coordinates.
                assert!(kept.q[2].abs() <= PI && taken.abs() == 1.0, "step {k}");
                let back = kept.q_with_turns(taken)[2] - before.q[2];
                assert!(back.abs() <= f64::EPSILON * 8.0, "step {k}: {back:e}");
            }
        }
        // 70 turns later the two runs are the same but for the rounding of ζ, which the
        // motion's sensitivity amplifies: 0.3–2.8·10⁻¹¹ here, depending on where Newton's
        // stopping rule falls (which moves with its tolerance), 10⁻⁹ over 20,000 steps. Turns of 2π
        // to single precision (no `TAU_LO`) leave 1.4·10⁻⁵.
        assert!(turns > 70.0, "{turns}");
        let gap = (kept.q_with_turns(turns) - st.q).amax().max((kept.v - st.v).amax());
        assert!(gap < 1e-10, "{gap:e}");
        // A start far out takes its turns at once, to the accuracy ζ had.
        let zeta = 1e6 * TAU + 1.0;
        let mut far =
            State::with_continuous_multiplier(&sys, Vector::<3>::new(1.0, 1.0, zeta), v).unwrap();
        let taken = far.take_whole_turns(&mut DdMemory::empty());
        assert_eq!(taken, 1e6);
        assert!((far.q[2] + far.q_compensation[2] - (zeta - 1e6 * TAU)).abs() < 1e-9);
        assert!((far.q_with_turns(taken)[2] - zeta).abs() <= 1e-9);
        // NaN and infinity neither panic nor pass for a number.
        for bad in [f64::NAN, f64::INFINITY] {
            let mut st = far;
            st.q[2] = bad;
            st.take_whole_turns(&mut DdMemory::empty());
            assert!(!st.is_finite());
        }
    }
}
