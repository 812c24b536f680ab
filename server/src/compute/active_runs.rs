//! [`ActiveRuns`]: the count of simulation runs computing right now (`GET /health`'s
//! `active_runs`), each counted by a [`RunGuard`] from its start until it ends or panics.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The number of runs computing; cheap to clone (the clones share the count).
#[derive(Debug, Clone, Default)]
pub struct ActiveRuns(Arc<AtomicUsize>);

impl ActiveRuns {
    /// Runs computing right now.
    pub fn count(&self) -> usize {
        self.0.load(Ordering::SeqCst)
    }

    /// Counts a run as active until the guard is dropped (also when the run panics).
    pub fn guard(&self) -> RunGuard {
        self.0.fetch_add(1, Ordering::SeqCst);
        RunGuard(self.0.clone())
    }
}

/// Keeps one run counted in [`ActiveRuns`].
#[derive(Debug)]
pub struct RunGuard(Arc<AtomicUsize>);

impl Drop for RunGuard {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}
