//! [`Rank`]: a run's watch on the rank of its constraint matrix A(q), which ends the run
//! where the rows stop being independent (`docs/model.md` §4): the multiplier is no longer
//! determined there, and a method that steps on regardless reports numbers that mean nothing.

use crate::linalg;
use crate::{Matrix, StepFailure};

/// Below this fraction of its start, A's smallest singular value has been lost to rank.
const RANK_LOST: f64 = 1e-8;
/// Below this fraction of its start, A's smallest singular value is near a loss of rank, and
/// constraint rows that reverse their orientation within a step have passed through one.
const RANK_NEAR: f64 = 0.1;

/// A's smallest singular value followed along a run. A cheap bound each step (the smallest
/// pivot of the Cholesky factor of `A Aᵀ`), the exact value where the bound has fallen far.
/// Steps seldom land on a loss of rank, they step over it: where A is near one at either end of
/// a step and its rows have reversed their orientation in it (`det(A₁A₀ᵀ) ≤ 0`), the run has
/// passed through one.
pub(super) struct Rank {
    initial: f64,
    pivot0: f64,
}

impl Rank {
    pub(super) fn new<const N: usize, const R: usize>(a: &Matrix<R, N>) -> Self {
        let pivot0 = linalg::smallest_cholesky_pivot(&(a * a.transpose()));
        Self { initial: smallest_singular_value(a), pivot0 }
    }

    /// `Err` where A has lost rank at `a` or in the step from `before` to `a`.
    #[inline]
    pub(super) fn check<const N: usize, const R: usize>(
        &self,
        before: &Matrix<R, N>,
        a: &Matrix<R, N>,
    ) -> Result<(), StepFailure> {
        let pivot = linalg::smallest_cholesky_pivot(&(a * a.transpose()));
        if pivot >= RANK_NEAR * self.pivot0 {
            return Ok(());
        }
        let smallest = smallest_singular_value(a);
        let lost = StepFailure::RankLost { smallest, initial: self.initial };
        if smallest.is_nan() || smallest < RANK_LOST * self.initial {
            return Err(lost);
        }
        let reversed = linalg::determinant(&(a * before.transpose()));
        if smallest < RANK_NEAR * self.initial && (reversed.is_nan() || reversed <= 0.0) {
            return Err(lost);
        }
        Ok(())
    }
}

/// A's smallest singular value (rarely: at the start, and where the cheap bound has fallen).
fn smallest_singular_value<const N: usize, const R: usize>(a: &Matrix<R, N>) -> f64 {
    nalgebra::DMatrix::from_row_slice(R, N, a.transpose().as_slice()).singular_values().min()
}
