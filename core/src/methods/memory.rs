//! What a method carries from one step to the next besides the state: its [`Memory`].
//!
//! A method's memory holds values it computed at the end of a step that the next step (and
//! the integrals at that state) would otherwise compute again: the driver's terms at ζ₁
//! ([`EndOfStep`]), RK4's last acceleration ([`AccelerationAtEnd`]), DD's driver history. It
//! never changes a step's result beyond round-off: every entry is keyed by what it depends
//! on, so a state moved from outside (a test, a restart) finds nothing and evaluates afresh.
//! The state itself ([`State`]) holds the physics only.

use crate::model::system::System;
use crate::{Matrix, State, Vector};

/// A method's cache from step to step (see the module's doc).
pub trait Memory<const N: usize, const R: usize>:
    Recall<N, R> + Copy + Send + Sync + std::fmt::Debug
{
    /// Remembers nothing.
    fn empty() -> Self;
}

/// What a run reads of a memory between steps, and how the memory follows the state.
pub trait Recall<const N: usize, const R: usize> {
    /// `V_d(ζ)` and `A(ζ)` where the last step ended, if it remembered them at this ζ: the
    /// integrals at that state read them instead of evaluating (one sin/cos fewer).
    #[inline]
    fn driver_terms_at(&self, zeta: f64) -> Option<(f64, Matrix<R, N>)> {
        let _ = zeta;
        None
    }
    /// Follows a state moved from `from` to `to`, which stands for the same configuration
    /// (whole turns of an angle taken off): what was keyed by `from` is now keyed by `to`.
    #[inline]
    fn moved(&mut self, from: &Vector<N>, to: &Vector<N>) {
        let _ = (from, to);
    }
}

/// `A(ζ)`, `V_d(ζ)` and `V_d'(ζ)` at the ζ a step ended on, so that the next step, which
/// starts there, does not evaluate them again (leap-frog's force, DLA^α's `∇V(q₀)`), nor do
/// the integrals at that state (`h`, `|A q̇|`): one sin/cos per step instead of two or three on
/// the trigonometric systems. Keyed by ζ itself, what they depend on. ∇U, which depends on
/// the passenger, is evaluated where needed.
///
/// The key is one number, not q: a step writes q as its compensated sum left it, in pieces
/// the compiler chooses, and copying the whole vector back for a key would read it in other
/// pieces, which the processor cannot forward from the pending stores (a stall).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndOfStep<const N: usize, const R: usize> {
    zeta: f64,
    constraint: Matrix<R, N>,
    driver_potential: f64,
    driver_potential_d1: f64,
}

impl<const N: usize, const R: usize> Memory<N, R> for EndOfStep<N, R> {
    /// Knows nothing (NaN never equals a ζ).
    #[inline]
    fn empty() -> Self {
        Self {
            zeta: f64::NAN,
            constraint: Matrix::zeros(),
            driver_potential: 0.0,
            driver_potential_d1: 0.0,
        }
    }
}

impl<const N: usize, const R: usize> Recall<N, R> for EndOfStep<N, R> {
    #[inline]
    fn driver_terms_at(&self, zeta: f64) -> Option<(f64, Matrix<R, N>)> {
        (self.zeta == zeta).then_some((self.driver_potential, self.constraint))
    }
    #[inline]
    fn moved(&mut self, from: &Vector<N>, to: &Vector<N>) {
        if self.zeta == from[N - 1] {
            self.zeta = to[N - 1];
        }
    }
}

impl<const N: usize, const R: usize> EndOfStep<N, R> {
    /// Whether the driver's terms at the current ζ of `st` are remembered.
    #[inline]
    pub(crate) fn holds(&self, st: &State<N, R>) -> bool {
        self.zeta == st.q[N - 1]
    }

    /// `∇V(q)` and `A(q)` at the state's `q`: remembered or evaluated.
    #[inline]
    pub(crate) fn gradient_and_constraint<S: System<N, R>>(
        &self,
        sys: &S,
        st: &State<N, R>,
    ) -> (Vector<N>, Matrix<R, N>) {
        if self.holds(st) {
            (self.gradient(sys, st), self.constraint)
        } else {
            (sys.gradient(&st.q), sys.constraint(st.q[N - 1]))
        }
    }

    /// `∇V(q)` at the state's `q`, with `V_d'` remembered or evaluated.
    #[inline]
    pub(crate) fn gradient<S: System<N, R>>(&self, sys: &S, st: &State<N, R>) -> Vector<N> {
        if self.holds(st) {
            let mut g = sys.passenger_gradient(&st.q);
            g[N - 1] = self.driver_potential_d1;
            g
        } else {
            sys.gradient(&st.q)
        }
    }

    /// `V_d(ζ)` and `A(ζ)` at the state's `q`, remembered or evaluated (together, so that
    /// they share one sin/cos).
    #[inline]
    pub(crate) fn driver_potential_and_constraint<S: System<N, R>>(
        &self,
        sys: &S,
        st: &State<N, R>,
    ) -> (f64, Matrix<R, N>) {
        driver_potential_and_constraint(self, sys, st)
    }

    /// Remembers `A`, `V_d` and `V_d'` at the state's ζ (call after the step has moved `q`;
    /// they must be their values there, to round-off).
    #[inline]
    pub(crate) fn remember(
        &mut self,
        st: &State<N, R>,
        constraint: Matrix<R, N>,
        driver_potential: f64,
        driver_potential_d1: f64,
    ) {
        let zeta = st.q[N - 1];
        *self = Self { zeta, constraint, driver_potential, driver_potential_d1 };
    }
}

/// `V_d(ζ)` and `A(ζ)` at the state's `q`, as `memory` remembered them or evaluated
/// together (one sin/cos): what the integrals at a state need.
#[inline]
pub fn driver_potential_and_constraint<S, M, const N: usize, const R: usize>(
    memory: &M,
    sys: &S,
    st: &State<N, R>,
) -> (f64, Matrix<R, N>)
where
    S: System<N, R>,
    M: Recall<N, R>,
{
    let zeta = st.q[N - 1];
    memory
        .driver_terms_at(zeta)
        .unwrap_or_else(|| (sys.driver_potential(zeta), sys.constraint(zeta)))
}

/// `q̈(q, q̇)` of the reduced ODE at the state a step ended on: RK4's last evaluation is the
/// first stage of its next step. Keyed by `q` and `q̇` (the acceleration depends on both).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccelerationAtEnd<const N: usize> {
    q: Vector<N>,
    v: Vector<N>,
    acceleration: Vector<N>,
}

impl<const N: usize> AccelerationAtEnd<N> {
    /// Knows nothing.
    #[inline]
    pub(crate) fn empty() -> Self {
        Self {
            q: Vector::repeat(f64::NAN),
            v: Vector::repeat(f64::NAN),
            acceleration: Vector::zeros(),
        }
    }

    /// `q̈` at the state's `(q, q̇)`, if the step that ended there remembered it.
    #[inline]
    pub(crate) fn at<const R: usize>(&self, st: &State<N, R>) -> Option<Vector<N>> {
        (self.q == st.q && self.v == st.v).then_some(self.acceleration)
    }

    /// Remembers `q̈` at the state (call after the step has moved it).
    #[inline]
    pub(crate) fn remember<const R: usize>(&mut self, st: &State<N, R>, acceleration: Vector<N>) {
        *self = Self { q: st.q, v: st.v, acceleration };
    }

    /// Follows a state moved to the same configuration.
    #[inline]
    pub(crate) fn moved(&mut self, from: &Vector<N>, to: &Vector<N>) {
        if self.q == *from {
            self.q = *to;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::dd::DdMemory;
    use crate::methods::rk4::Rk4Memory;
    use crate::methods::{Dd, Dla, Dla01, Integrator, Leapfrog, Rk4, Stepper};
    use crate::model::system::BuiltIn;
    use crate::model::systems::{Cvt, CvtPendulum, MobileRobot, Particle};

    /// Steps with the method's memory against steps that start each from an empty one.
    fn remembered_vs_fresh<S: BuiltIn<N, R>, M: Integrator, const N: usize, const R: usize>(
        sys: &S,
        m: &M,
        h: f64,
    ) -> f64 {
        let p = &S::info().presets[0];
        let (q, v) = (Vector::from_column_slice(p.q), Vector::from_column_slice(p.v));
        let mut kept = State::with_continuous_multiplier(sys, q, v).unwrap();
        let mut fresh = kept;
        let mut memory = M::Memory::<N, R>::empty();
        let mut used = 0;
        let mut gap: f64 = 0.0;
        for _ in 0..2000 {
            used += usize::from(memory.driver_terms_at(kept.q[N - 1]).is_some());
            m.step(sys, &mut kept, &mut memory, h).unwrap();
            m.step(sys, &mut fresh, &mut M::Memory::<N, R>::empty(), h).unwrap();
            gap = gap.max((kept.q - fresh.q).amax()).max((kept.v - fresh.v).amax());
        }
        assert!(used >= 1999, "the remembered values were used in {used} of 2000 steps");
        gap
    }

    #[test]
    fn remembered_force_gives_the_same_steps() {
        let pendulum = CvtPendulum { epsilon: 0.5 };
        // Leap-frog remembers exactly what it would evaluate: bitwise the same steps.
        assert_eq!(remembered_vs_fresh(&pendulum, &Leapfrog, 0.1), 0.0);
        assert_eq!(remembered_vs_fresh(&MobileRobot, &Leapfrog, 0.05), 0.0);
        // DLA^{0,1}'s fast path only remembers (for the integrals), at the ζ₁ it predicted the
        // state holds; DLA^α's evaluates at ζ₁ as the state holds it.
        assert_eq!(remembered_vs_fresh(&Cvt, &Dla01::default(), 0.1), 0.0);
        let dla = Dla { alpha: 0.4, ..Dla::default() };
        assert_eq!(remembered_vs_fresh(&Particle, &dla, 0.1), 0.0);
        // Their general paths (every angle-driven system) rotate the driver's terms from the
        // last Newton iterate's.
        assert!(remembered_vs_fresh(&pendulum, &Dla01::default(), 0.1) < 1e-12);
        assert!(remembered_vs_fresh(&MobileRobot, &Dla01::default(), 0.05) < 1e-12);
        assert!(remembered_vs_fresh(&pendulum, &dla, 0.1) < 1e-12);
        assert!(remembered_vs_fresh(&MobileRobot, &Dla::default(), 0.05) < 1e-12);
        // RK4's first stage is the q̈ its last step ended with, computed the same way.
        assert_eq!(remembered_vs_fresh(&pendulum, &Rk4, 0.1), 0.0);
        assert_eq!(remembered_vs_fresh(&MobileRobot, &Rk4, 0.05), 0.0);
    }

    #[test]
    fn the_memory_follows_a_state_moved_to_the_same_configuration() {
        let sys = CvtPendulum { epsilon: 0.5 };
        let p = &CvtPendulum::info().presets[3];
        let (q, v) = (Vector::from_column_slice(p.q), Vector::from_column_slice(p.v));
        let mut st = State::with_continuous_multiplier(&sys, q, v).unwrap();
        let mut memory = DdMemory::empty();
        let mut turns = 0.0;
        for k in 0..40 {
            Dd::default().step(&sys, &mut st, &mut memory, 0.1).unwrap();
            // Within a turn again (the driver turns once in about 22 steps here).
            turns += st.take_whole_turns(&mut memory);
            assert!(st.q[2].abs() <= std::f64::consts::PI);
            assert!(memory.end.holds(&st), "the driver's terms at the end are still known");
            assert_eq!(memory.history.guess(&st.q, &st.v, 0.1).is_some(), k >= 2);
        }
        assert!(turns >= 1.0, "the memory was checked across a turn taken off");
        let mut rk4 = Rk4Memory::empty();
        Rk4.step(&sys, &mut st, &mut rk4, 0.1).unwrap();
        let mut elsewhere = st.q;
        elsewhere[2] += 6.0;
        let mut moved = rk4;
        moved.moved(&elsewhere, &st.q);
        assert!(moved.acceleration.at(&st).is_some(), "a key of another q does not follow");
        moved.moved(&st.q, &elsewhere);
        assert_eq!(moved.acceleration.at(&st), None, "the key follows");
    }

    #[test]
    fn a_state_moved_from_outside_forgets() {
        let sys = CvtPendulum { epsilon: 0.5 };
        let mut st = State::with_continuous_multiplier(
            &sys,
            Vector::<3>::new(1.0, 1.0, 0.0),
            Vector::<3>::new(0.0, 0.0, 1.0),
        )
        .unwrap();
        let mut memory = EndOfStep::empty();
        Leapfrog.step(&sys, &mut st, &mut memory, 0.1).unwrap();
        assert_eq!(memory.gradient(&sys, &st), sys.gradient(&st.q));
        // The passenger moved, ζ not: the driver's terms still hold, ∇U is the new one.
        st.q[0] += 0.5;
        assert!(memory.holds(&st));
        assert_eq!(memory.gradient(&sys, &st), sys.gradient(&st.q));
        assert_eq!(memory.gradient_and_constraint(&sys, &st).0, sys.gradient(&st.q));
        st.q[2] += 0.25;
        assert!(!memory.holds(&st));
        assert_eq!(memory.gradient(&sys, &st), sys.gradient(&st.q));
        assert_eq!(memory.gradient_and_constraint(&sys, &st).1, sys.constraint(st.q[2]));
        // q̈ depends on q̇ too: a velocity changed from outside forgets it.
        let mut rk4 = Rk4Memory::empty();
        Rk4.step(&sys, &mut st, &mut rk4, 0.1).unwrap();
        assert!(rk4.acceleration.at(&st).is_some());
        st.v[0] += 0.5;
        assert_eq!(rk4.acceleration.at(&st), None);
    }
}
