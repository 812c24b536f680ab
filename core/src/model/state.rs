//! [`State`]: what a one-step method carries from step to step.

use crate::model::mechanical::Mechanical;
use crate::{Vector, model::system::System};

/// Position, velocity and multiplier; every method carries `λ` (leap-frog needs it, the
/// implicit methods start Newton from it).
///
/// Methods move the state by increments through [`State::advance`], which sums them with
/// compensation (Kahan; Hairer, Lubich & Wanner, *Geometric Numerical Integration*, VIII.5):
/// the rounding error of each addition is kept and added back on the next step, so that over
/// 10⁸ steps round-off does not accumulate like a random walk in q and q̇.
#[derive(Debug, Clone, Copy, PartialEq)]
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
}

impl<const N: usize, const R: usize> State<N, R> {
    /// A state whose multiplier is the continuous one of `docs/model.md` §1, which starts every
    /// run; `None` when `A Aᵀ` is singular.
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
        })
    }

    /// A state of a general system ([`Mechanical`]) whose multiplier is the continuous one;
    /// `None` when `A M⁻¹ Aᵀ` is singular.
    pub fn general_start<S: Mechanical<N, R>>(sys: &S, q: Vector<N>, v: Vector<N>) -> Option<Self> {
        let lambda = sys.continuous_multiplier(&q, &v)?;
        Some(Self {
            q,
            v,
            lambda,
            q_compensation: Vector::zeros(),
            v_compensation: Vector::zeros(),
        })
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
    pub(crate) fn advance_q_parts(&mut self, late: Vector<N>, early: Vector<N>) {
        compensated_add(&mut self.q, &mut self.q_compensation, late, early);
    }

    /// `q̇ += late + early`, as [`State::advance_q_parts`].
    #[inline]
    pub(crate) fn advance_v_parts(&mut self, late: Vector<N>, early: Vector<N>) {
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
