//! [`AppState`]: what every handler shares: the limits and the count of running
//! simulations (tests and, later, admission control watch it).

use crate::Config;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Shared state of the app; cheap to clone.
#[derive(Debug, Clone, Default)]
pub struct AppState {
    /// The limits.
    pub config: Arc<Config>,
    active: Arc<AtomicUsize>,
}

impl AppState {
    /// State with these limits.
    pub fn new(config: Config) -> Self {
        Self { config: Arc::new(config), active: Arc::default() }
    }

    /// Number of simulation runs computing right now (one per method of a request).
    pub fn active_runs(&self) -> usize {
        self.active.load(Ordering::SeqCst)
    }

    /// Counts a run as active until the guard is dropped (also when the run panics).
    pub(crate) fn run_guard(&self) -> RunGuard {
        self.active.fetch_add(1, Ordering::SeqCst);
        RunGuard(self.active.clone())
    }
}

/// Keeps one run counted in [`AppState::active_runs`].
#[derive(Debug)]
pub(crate) struct RunGuard(Arc<AtomicUsize>);

impl Drop for RunGuard {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}
