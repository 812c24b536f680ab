//! [`GeneralMemory`]: what a method's general step (`docs/model.md` §3, the general class)
//! carries from one step to the next: the forces `∇V`, `A` and the potential where the last
//! step ended, and RK4's last acceleration. Keyed by q (and q̇ for the acceleration), as the
//! class's memories are: a state moved from outside finds nothing and evaluates afresh, so a
//! memory never changes a step.

use crate::methods::memory::{Memory, Recall};
use crate::model::mechanical::{Forces, Mechanical};
use crate::{Matrix, Vector};

/// See the module's doc.
#[derive(Debug, Clone, Copy)]
pub struct GeneralMemory<const N: usize, const R: usize> {
    q: Vector<N>,
    forces: Forces<N, R>,
    /// `V(q)`, NaN when not remembered.
    potential: f64,
    v: Vector<N>,
    acceleration: Option<Vector<N>>,
    /// The key of an external method's memory ([`External`](super::External)) and the
    /// configuration its last step ended on; 0 for none.
    external: (u64, Vector<N>),
}

impl<const N: usize, const R: usize> GeneralMemory<N, R> {
    /// Knows nothing (NaN never equals a q).
    #[inline]
    pub fn empty() -> Self {
        Self {
            q: Vector::repeat(f64::NAN),
            forces: Forces { gradient: Vector::zeros(), constraint: Matrix::zeros() },
            potential: f64::NAN,
            v: Vector::repeat(f64::NAN),
            acceleration: None,
            external: (0, Vector::repeat(f64::NAN)),
        }
    }

    /// `∇V(q)` and `A(q)`: remembered or evaluated.
    #[inline]
    pub fn forces<S: Mechanical<N, R>>(&self, sys: &S, q: &Vector<N>) -> Forces<N, R> {
        if self.q == *q { self.forces } else { sys.forces(q) }
    }

    /// `V(q)`: remembered or evaluated.
    #[inline]
    pub fn potential<S: Mechanical<N, R>>(&self, sys: &S, q: &Vector<N>) -> f64 {
        if self.q == *q && !self.potential.is_nan() { self.potential } else { sys.potential(q) }
    }

    /// `A(q)`: remembered or evaluated.
    #[inline]
    pub fn constraint<S: Mechanical<N, R>>(&self, sys: &S, q: &Vector<N>) -> Matrix<R, N> {
        if self.q == *q { self.forces.constraint } else { sys.constraint(q) }
    }

    /// Remembers the forces at `q` (where a step ended), forgetting the rest.
    #[inline]
    pub fn remember(&mut self, q: &Vector<N>, forces: Forces<N, R>) {
        *self = Self { q: *q, forces, ..Self::empty() };
    }

    /// Remembers `V(q)` beside the forces at the same q.
    #[inline]
    pub fn remember_potential(&mut self, q: &Vector<N>, potential: f64) {
        if self.q == *q {
            self.potential = potential;
        }
    }

    /// `q̈` at `(q, q̇)`, if the step that ended there remembered it.
    #[inline]
    pub fn acceleration(&self, q: &Vector<N>, v: &Vector<N>) -> Option<Vector<N>> {
        self.acceleration.filter(|_| self.q == *q && self.v == *v)
    }

    /// Remembers `q̈` at `(q, q̇)` beside the forces at the same q.
    #[inline]
    pub fn remember_acceleration(&mut self, q: &Vector<N>, v: &Vector<N>, acceleration: Vector<N>) {
        if self.q == *q {
            (self.v, self.acceleration) = (*v, Some(acceleration));
        }
    }

    /// The key an external method's last step left its memory under, if that step ended
    /// at `q`.
    #[inline]
    pub fn external_key(&self, q: &Vector<N>) -> Option<u64> {
        let (key, at) = self.external;
        (key != 0 && at == *q).then_some(key)
    }

    /// Remembers an external method's memory key at the configuration its step ended on.
    #[inline]
    pub fn remember_external_key(&mut self, q: &Vector<N>, key: u64) {
        self.external = (key, *q);
    }
}

/// A general step on a class system (RATTLE's) keeps this memory in a class run too; it
/// remembers nothing the class's integrals read.
impl<const N: usize, const R: usize> Memory<N, R> for GeneralMemory<N, R> {
    fn empty() -> Self {
        Self::empty()
    }
}

impl<const N: usize, const R: usize> Recall<N, R> for GeneralMemory<N, R> {
    #[inline]
    fn moved(&mut self, from: &Vector<N>, to: &Vector<N>) {
        if self.q == *from {
            self.q = *to;
        }
        if self.external.1 == *from {
            self.external.1 = *to;
        }
    }
}
