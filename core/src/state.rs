//! [`State`]: what a one-step method carries from step to step.

use crate::{Vector, system::System};

/// Position, velocity and multiplier; every method carries `λ` (leap-frog needs it, the
/// implicit methods start Newton from it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State<const N: usize, const R: usize> {
    /// Configuration `q = (x, ζ)`.
    pub q: Vector<N>,
    /// Velocity `q̇`.
    pub v: Vector<N>,
    /// Multiplier `λ`.
    pub lambda: Vector<R>,
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
        Some(Self { q, v, lambda })
    }

    /// Whether every component is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        (self.q.sum() + self.v.sum() + self.lambda.sum()).is_finite()
    }
}
