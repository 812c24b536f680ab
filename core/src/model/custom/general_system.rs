//! [`GeneralCustom`]: a system given in the general form and compiled
//! ([`GeneralCompiled`]), as a [`Mechanical`] system of fixed sizes N ≥ n, R ≥ m.
//!
//! Sizes are compiled once, so a system with fewer coordinates than its size runs padded:
//! each coordinate beyond the n given has unit mass, no potential and a constraint row of its
//! own (`q̇_p = 0`), which decouples it exactly: it stays at rest at 0 and adds nothing to the
//! energy or the residual (`docs/model.md` §10).

use super::general::GeneralCompiled;
use super::invariants::Invariants;
use crate::model::mechanical::{Derivatives, Forces, Mass, Mechanical};
use crate::{Matrix, Vector};
use std::mem::MaybeUninit;
use std::sync::Arc;

/// See the module's doc.
#[derive(Debug, Clone)]
pub struct GeneralCustom<const N: usize, const R: usize> {
    compiled: Arc<GeneralCompiled>,
    mass: Mass<N>,
    /// The invariants of its spec, on its `(q, q̇)` ([`with_invariants`](Self::with_invariants)).
    invariants: Option<Arc<Invariants>>,
}

/// Most outputs of a general system's `terms` tape: ∇V, A, ∇²V's upper triangle and ∂A/∂q
/// for N = 12, m = 11.
const MAX_TERMS: usize = 12 + 11 * 12 + 12 * 13 / 2 + 12 * 11 * 12;

impl<const N: usize, const R: usize> GeneralCustom<N, R> {
    /// The system of `compiled`, which must have at most N coordinates and R constraints
    /// with as many of each padded (`N − n = R − m`).
    pub fn new(compiled: Arc<GeneralCompiled>) -> Self {
        let (n, m) = (compiled.n, compiled.m);
        debug_assert!(n <= N && m <= R && N - n == R - m);
        let mut mass = Matrix::<N, N>::identity();
        for i in 0..n {
            for j in 0..n {
                mass[(i, j)] = compiled.mass[i * n + j];
            }
        }
        // Checked symmetric positive definite when compiled.
        let mass = Mass::of(mass).unwrap_or(Mass::Identity);
        Self { compiled, mass, invariants: None }
    }

    /// The same system carrying `invariants`, compiled on its `(q, q̇)` (those of the spec it
    /// was compiled from: `Formulated::invariants`).
    pub fn with_invariants(self, invariants: Option<Arc<Invariants>>) -> Self {
        Self { invariants, ..self }
    }

    fn q<'a>(&self, q: &'a Vector<N>) -> &'a [f64] {
        &q.as_slice()[..self.compiled.n]
    }

    /// `∇V` and `A` from the first outputs of a tape, the padding's rows added.
    #[inline]
    fn forces_from(&self, values: &[f64]) -> Forces<N, R> {
        let (n, m) = (self.compiled.n, self.compiled.m);
        let mut gradient = Vector::<N>::zeros();
        gradient.as_mut_slice()[..n].copy_from_slice(&values[..n]);
        let mut constraint = Matrix::<R, N>::zeros();
        for r in 0..m {
            for j in 0..n {
                constraint[(r, j)] = values[n + r * n + j];
            }
        }
        for p in 0..N - n {
            constraint[(m + p, n + p)] = 1.0;
        }
        Forces { gradient, constraint }
    }
}

impl<const N: usize, const R: usize> Mechanical<N, R> for GeneralCustom<N, R> {
    #[inline]
    fn mass(&self) -> &Mass<N> {
        &self.mass
    }
    fn quadratic_potential(&self) -> bool {
        self.compiled.quadratic
    }
    fn invariants(&self) -> Option<&Invariants> {
        self.invariants.as_deref()
    }
    #[inline]
    fn potential(&self, q: &Vector<N>) -> f64 {
        let mut out = [f64::NAN];
        self.compiled.potential.eval(self.q(q), &mut out);
        out[0]
    }
    #[inline]
    fn forces(&self, q: &Vector<N>) -> Forces<N, R> {
        // Written by the code, not filled first: the buffer is sized for the largest system.
        let mut values = [MaybeUninit::uninit(); 12 + 11 * 12];
        let values = self.compiled.forces.eval_uninit(self.q(q), &mut values);
        self.forces_from(values)
    }
    #[inline]
    fn derivatives(&self, q: &Vector<N>) -> Derivatives<N, R> {
        self.forces_and_derivatives(q).1
    }
    #[inline]
    fn forces_and_derivatives(&self, q: &Vector<N>) -> (Forces<N, R>, Derivatives<N, R>) {
        let (n, m) = (self.compiled.n, self.compiled.m);
        let mut values = [MaybeUninit::uninit(); MAX_TERMS];
        let values = self.compiled.terms.eval_uninit(self.q(q), &mut values);
        let forces = self.forces_from(values);
        let mut at = n + m * n;
        let mut hessian = Matrix::<N, N>::zeros();
        for i in 0..n {
            for j in i..n {
                (hessian[(i, j)], hessian[(j, i)]) = (values[at], values[at]);
                at += 1;
            }
        }
        let mut partials = [Matrix::<R, N>::zeros(); N];
        for partial in partials.iter_mut().take(n) {
            for r in 0..m {
                for j in 0..n {
                    partial[(r, j)] = values[at];
                    at += 1;
                }
            }
        }
        (forces, Derivatives { hessian, partials })
    }
}
