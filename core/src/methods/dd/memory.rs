//! [`DdMemory`]: what DD and DD-AVF carry from step to step.

use super::driver_history::DriverHistory;
use crate::methods::memory::{EndOfStep, Memory, Recall};
use crate::{Matrix, Vector};

/// What DD and DD-AVF remember from step to step: the driver's terms where the step ended
/// and the driver's last speed increments (Newton's guess).
#[derive(Debug, Clone, Copy)]
pub struct DdMemory<const N: usize, const R: usize> {
    pub(crate) end: EndOfStep<N, R>,
    pub(crate) history: DriverHistory<N>,
}

impl<const N: usize, const R: usize> Memory<N, R> for DdMemory<N, R> {
    fn empty() -> Self {
        Self { end: EndOfStep::empty(), history: DriverHistory::empty() }
    }
}

impl<const N: usize, const R: usize> Recall<N, R> for DdMemory<N, R> {
    #[inline]
    fn driver_terms_at(&self, zeta: f64) -> Option<(f64, Matrix<R, N>)> {
        self.end.driver_terms_at(zeta)
    }
    #[inline]
    fn moved(&mut self, from: &Vector<N>, to: &Vector<N>) {
        self.end.moved(from, to);
        self.history.moved(from, to);
    }
}
