//! [`State`]: what a one-step method carries from step to step.

use crate::driver_history::DriverHistory;
use crate::{Matrix, Vector, system::System};

/// Position, velocity and multiplier; every method carries `λ` (leap-frog needs it, the
/// implicit methods start Newton from it).
///
/// Methods move the state by increments through [`State::advance`], which sums them with
/// compensation (Kahan; Hairer, Lubich & Wanner, *Geometric Numerical Integration*, VIII.5):
/// the rounding error of each addition is kept and added back on the next step, so that over
/// 10⁸ steps round-off does not accumulate like a random walk in q and q̇.
///
/// Two states are equal when their numbers are (q, q̇, λ and the compensations); what a step
/// remembered at its end is a cache and does not count.
#[derive(Debug, Clone, Copy)]
pub struct State<const N: usize, const R: usize> {
    /// Configuration `q = (x, ζ)`.
    pub q: Vector<N>,
    /// Velocity `q̇`.
    pub v: Vector<N>,
    /// Multiplier `λ`.
    pub lambda: Vector<R>,
    /// What the last additions to `q` lost to rounding (compensated summation).
    pub q_compensation: Vector<N>,
    /// What the last additions to `q̇` lost to rounding.
    pub v_compensation: Vector<N>,
    /// The driver's terms where the last step ended, if it computed them (first same as
    /// last).
    pub(crate) at_end: AtEnd<N, R>,
    /// The acceleration `q̈(q, q̇)` where the last step ended, if it computed it (RK4).
    pub(crate) acceleration_at_end: AccelerationAtEnd<N>,
    /// The driver's last speed increments, if they ended here (DD's Newton guess).
    pub(crate) driver_history: DriverHistory<N>,
}

/// `q̈(q, q̇)` of the reduced ODE at the state a step ended on: RK4's last evaluation is the
/// first stage of its next step. Keyed by `q` and `q̇` (the acceleration depends on both).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AccelerationAtEnd<const N: usize> {
    q: Vector<N>,
    v: Vector<N>,
    acceleration: Vector<N>,
}

/// `A(ζ)`, `V_d(ζ)` and `V_d'(ζ)` at the ζ a step ended on, so that the next step, which
/// starts there, does not evaluate them again (leap-frog's force, DLA^α's `∇V(q₀)`), nor do
/// the integrals at that state (`h`, `|A q̇|`): one sin/cos per step instead of two or three on
/// the trigonometric systems. Keyed by ζ itself, what they depend on, so a state moved from
/// outside (a test, a restart) never reuses a stale value. ∇U, which depends on the passenger,
/// is evaluated where needed (it is affine on every test system).
///
/// The key is one number, not q: a step writes q as its compensated sum left it, in pieces
/// the compiler chooses, and copying the whole vector back for a key read it in other pieces,
/// which the processor cannot forward from the pending stores (a stall of ~20 % of DLA^α's
/// fast step on `particle`; `docs/benchmarks-history.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AtEnd<const N: usize, const R: usize> {
    zeta: f64,
    constraint: Matrix<R, N>,
    driver_potential: f64,
    driver_potential_d1: f64,
}

impl<const N: usize, const R: usize> AtEnd<N, R> {
    /// Knows nothing (NaN never equals a ζ).
    fn empty() -> Self {
        Self {
            zeta: f64::NAN,
            constraint: Matrix::zeros(),
            driver_potential: 0.0,
            driver_potential_d1: 0.0,
        }
    }
}

impl<const N: usize> AccelerationAtEnd<N> {
    /// Knows nothing.
    fn empty() -> Self {
        Self {
            q: Vector::repeat(f64::NAN),
            v: Vector::repeat(f64::NAN),
            acceleration: Vector::zeros(),
        }
    }
}

impl<const N: usize, const R: usize> PartialEq for State<N, R> {
    fn eq(&self, other: &Self) -> bool {
        self.q == other.q
            && self.v == other.v
            && self.lambda == other.lambda
            && self.q_compensation == other.q_compensation
            && self.v_compensation == other.v_compensation
    }
}

impl<const N: usize, const R: usize> State<N, R> {
    /// A state whose multiplier is the continuous one of MATH.md §1, which starts every run;
    /// `None` when `A Aᵀ` is singular.
    pub fn with_continuous_multiplier<S: System<N, R>>(
        sys: &S,
        q: Vector<N>,
        v: Vector<N>,
    ) -> Option<Self> {
        let lambda = sys.continuous_multiplier(&q, &v)?;
        Some(Self {
            q,
            v,
            lambda,
            q_compensation: Vector::zeros(),
            v_compensation: Vector::zeros(),
            at_end: AtEnd::empty(),
            acceleration_at_end: AccelerationAtEnd::empty(),
            driver_history: DriverHistory::empty(),
        })
    }

    /// Whether the driver's terms at the current ζ are remembered.
    #[inline]
    fn remembered(&self) -> bool {
        self.at_end.zeta == self.q[N - 1]
    }

    /// `∇V(q)` and `A(q)` at the current `q`: the driver's terms remembered from the step that
    /// ended here, or evaluated.
    #[inline]
    pub(crate) fn gradient_and_constraint<S: System<N, R>>(
        &self,
        sys: &S,
    ) -> (Vector<N>, Matrix<R, N>) {
        if self.remembered() {
            (self.gradient(sys), self.at_end.constraint)
        } else {
            (sys.gradient(&self.q), sys.constraint(self.q[N - 1]))
        }
    }

    /// `∇V(q)` at the current `q`, with `V_d'` remembered or evaluated.
    #[inline]
    pub(crate) fn gradient<S: System<N, R>>(&self, sys: &S) -> Vector<N> {
        if self.remembered() {
            let mut g = sys.passenger_gradient(&self.q);
            g[N - 1] = self.at_end.driver_potential_d1;
            g
        } else {
            sys.gradient(&self.q)
        }
    }

    /// `V_d(ζ)` and `A(ζ)` at the current `q`, remembered or evaluated (together, so that
    /// they share one sin/cos).
    #[inline]
    pub(crate) fn driver_potential_and_constraint<S: System<N, R>>(
        &self,
        sys: &S,
    ) -> (f64, Matrix<R, N>) {
        if self.remembered() {
            (self.at_end.driver_potential, self.at_end.constraint)
        } else {
            let zeta = self.q[N - 1];
            (sys.driver_potential(zeta), sys.constraint(zeta))
        }
    }

    /// Remembers `A`, `V_d` and `V_d'` at the current ζ (call after the step has moved `q`;
    /// they must be their values there, to round-off).
    #[inline]
    pub(crate) fn remember_at_end(
        &mut self,
        constraint: Matrix<R, N>,
        driver_potential: f64,
        driver_potential_d1: f64,
    ) {
        let zeta = self.q[N - 1];
        self.at_end = AtEnd { zeta, constraint, driver_potential, driver_potential_d1 };
    }

    /// `q̈(q, q̇)` at the current state, if the step that ended here remembered it.
    #[inline]
    pub(crate) fn acceleration(&self) -> Option<Vector<N>> {
        let a = &self.acceleration_at_end;
        (a.q == self.q && a.v == self.v).then_some(a.acceleration)
    }

    /// Remembers `q̈` at the current state (call after the step has moved it).
    #[inline]
    pub(crate) fn remember_acceleration(&mut self, acceleration: Vector<N>) {
        self.acceleration_at_end = AccelerationAtEnd { q: self.q, v: self.v, acceleration };
    }

    /// `q += dq` with compensated summation.
    #[inline]
    pub fn advance_q(&mut self, dq: Vector<N>) {
        compensated_add(&mut self.q, &mut self.q_compensation, dq, nothing());
    }

    /// `q̇ += dv` with compensated summation.
    #[inline]
    pub fn advance_v(&mut self, dv: Vector<N>) {
        compensated_add(&mut self.v, &mut self.v_compensation, dv, nothing());
    }

    /// Component `i` of `q` after [`State::advance_q`] with an increment whose component `i`
    /// is `d` (the same compensated sum), without moving.
    #[inline]
    pub(crate) fn q_after(&self, i: usize, d: f64) -> f64 {
        self.q[i] + (d + self.q_compensation[i])
    }

    /// `q += late + early` with compensated summation, where `early` is known before the
    /// step's chain of dependencies reaches `late`: it is folded into the compensation off
    /// that chain, so that compensating costs the chain one addition, not three.
    #[inline]
    pub fn advance_q_parts(&mut self, late: Vector<N>, early: Vector<N>) {
        compensated_add(&mut self.q, &mut self.q_compensation, late, early);
    }

    /// `q̇ += late + early`, as [`State::advance_q_parts`].
    #[inline]
    pub fn advance_v_parts(&mut self, late: Vector<N>, early: Vector<N>) {
        compensated_add(&mut self.v, &mut self.v_compensation, late, early);
    }

    /// Both, for a step that computed its increments first (explicit methods: the increment
    /// is a sum of small force terms, accurate to its own size).
    #[inline]
    pub fn advance(&mut self, dq: Vector<N>, dv: Vector<N>) {
        self.advance_q(dq);
        self.advance_v(dv);
    }

    /// `q += dq` compensated, and `q̇ = v1` for a method that solves for q̇₁ itself (the
    /// implicit ones): q̇₁ − q̇₀ is then no more accurate than q̇₁, so there is no rounding
    /// loss to carry, and carrying one would inject the previous step's error into q̇₁.
    #[inline]
    pub fn advance_to(&mut self, dq: Vector<N>, v1: Vector<N>) {
        self.advance_q(dq);
        self.v = v1;
        self.v_compensation = Vector::zeros();
    }

    /// Whether every component is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        (self.q.sum() + self.v.sum() + self.lambda.sum()).is_finite()
    }

    /// Moves `q` to `to`, which stands for the same configuration (whole turns of an angle
    /// taken off, [`State::take_whole_turns`]), and the compensation to `compensation`; the
    /// caches that were keyed by the old `q` follow it.
    #[inline]
    pub(crate) fn move_to_same_configuration(&mut self, to: Vector<N>, compensation: Vector<N>) {
        let from = self.q;
        (self.q, self.q_compensation) = (to, compensation);
        if self.at_end.zeta == from[N - 1] {
            self.at_end.zeta = to[N - 1];
        }
        if self.acceleration_at_end.q == from {
            self.acceleration_at_end.q = to;
        }
        self.driver_history.moved(&from, &to);
    }
}

/// An `early` part of nothing: `−0.0 + e` is `e` exactly (for `e = ±0.0` too), so the
/// compiler drops the addition.
#[inline]
fn nothing<const N: usize>() -> Vector<N> {
    Vector::repeat(-0.0)
}

/// Kahan's step: `x += late + early` keeping in `e` what the addition rounded away.
#[inline]
fn compensated_add<const N: usize>(
    x: &mut Vector<N>,
    e: &mut Vector<N>,
    late: Vector<N>,
    early: Vector<N>,
) {
    for i in 0..N {
        let d = late[i] + (early[i] + e[i]);
        let sum = x[i] + d;
        e[i] = (x[i] - sum) + d;
        x[i] = sum;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::Integrator;
    use crate::methods::{Dla, Dla01, Leapfrog, Rk4};
    use crate::systems::{Cvt, CvtPendulum, MobileRobot, Particle};

    /// Steps with the remembered driver terms against steps that evaluate them afresh.
    fn remembered_vs_fresh<S: System<N, R>, M: Integrator, const N: usize, const R: usize>(
        sys: &S,
        m: &M,
        h: f64,
    ) -> f64 {
        let p = &S::info().presets[0];
        let (q, v) = (Vector::from_column_slice(p.q), Vector::from_column_slice(p.v));
        let mut kept = State::with_continuous_multiplier(sys, q, v).unwrap();
        let mut fresh = kept;
        let mut used = 0;
        let mut gap: f64 = 0.0;
        for _ in 0..2000 {
            used += usize::from(kept.remembered());
            m.step(sys, &mut kept, h).unwrap();
            fresh.at_end = AtEnd::empty();
            fresh.acceleration_at_end = AccelerationAtEnd::empty();
            fresh.driver_history = DriverHistory::empty();
            m.step(sys, &mut fresh, h).unwrap();
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
    fn the_caches_follow_a_state_moved_to_the_same_configuration() {
        use crate::methods::Dd;
        let sys = CvtPendulum { epsilon: 0.5 };
        let p = &CvtPendulum::info().presets[3];
        let (q, v) = (Vector::from_column_slice(p.q), Vector::from_column_slice(p.v));
        let mut st = State::with_continuous_multiplier(&sys, q, v).unwrap();
        let mut turns = 0.0;
        for k in 0..40 {
            Dd::default().step(&sys, &mut st, 0.1).unwrap();
            // Within a turn again (the driver turns once in about 22 steps here).
            turns += st.take_whole_turns();
            assert!(st.q[2].abs() <= std::f64::consts::PI);
            assert!(st.remembered(), "the driver's terms at the end are still known");
            assert_eq!(st.driver_history.guess(&st.q, &st.v, 0.1).is_some(), k >= 2);
        }
        assert!(turns >= 1.0, "the caches were checked across a turn taken off");
        Rk4.step(&sys, &mut st, 0.1).unwrap();
        let mut moved = st;
        moved.q[2] += 6.0;
        moved.move_to_same_configuration(st.q, st.q_compensation);
        assert_eq!(moved.acceleration_at_end.q, st.q, "the key follows");
        let mut elsewhere = st;
        elsewhere.q[2] += 6.0;
        let (to, c) = (elsewhere.q, elsewhere.q_compensation);
        elsewhere.q[2] += 1.0;
        elsewhere.move_to_same_configuration(to, c);
        assert_eq!(elsewhere.acceleration(), None, "a cache of another q is not adopted");
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
        Leapfrog.step(&sys, &mut st, 0.1).unwrap();
        let mut without = st;
        without.at_end = AtEnd::empty();
        assert_eq!(without, st, "what a step remembered does not make states differ");
        assert_eq!(st.gradient(&sys), sys.gradient(&st.q));
        // The passenger moved, ζ not: the driver's terms still hold, ∇U is the new one.
        st.q[0] += 0.5;
        assert!(st.remembered());
        assert_eq!(st.gradient(&sys), sys.gradient(&st.q));
        assert_eq!(st.gradient_and_constraint(&sys).0, sys.gradient(&st.q));
        st.q[2] += 0.25;
        assert!(!st.remembered());
        assert_eq!(st.gradient(&sys), sys.gradient(&st.q));
        assert_eq!(st.gradient_and_constraint(&sys).1, sys.constraint(st.q[2]));
        // q̈ depends on q̇ too: a velocity changed from outside forgets it.
        Rk4.step(&sys, &mut st, 0.1).unwrap();
        assert!(st.acceleration().is_some());
        st.v[0] += 0.5;
        assert_eq!(st.acceleration(), None);
    }
}
