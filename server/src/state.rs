//! [`AppState`]: what every handler shares: the limits, the simulation slots (admission),
//! the permits for checking requests, the budget of answers in flight, the count of running
//! simulations, the shutdown flag and the [`Caches`] of latitude axes and references.

use crate::compute::{
    ActiveRuns, AnswerBudget, BudgetGuard, Caches, Cancel, RunGuard, Runner, Slot, off_runtime,
};
use crate::config::Config;
use crate::error::AppError;
use std::sync::Arc;
use std::time::{Duration, Instant};
use tokio::sync::{Semaphore, watch};

/// How long a request may wait for a permit to be checked before it gets 503.
pub const CHECK_WAIT: Duration = Duration::from_secs(1);

/// How long checking one request may take: a check that goes on longer (a sweep of very many
/// cells of a large system, say) stops with a 422, so that no request holds a check permit
/// for long.
pub const CHECK_BUDGET: Duration = Duration::from_secs(5);

/// What a check looks at between its pieces of work: whether its client left, and its time.
#[derive(Debug)]
pub struct Checking {
    cancel: Cancel,
    deadline: Instant,
}

impl Checking {
    /// The error the check stops with, if it must stop now.
    pub fn stop(&self) -> Option<AppError> {
        if self.cancel.is_cancelled() {
            return Some(AppError::unavailable("the client went away"));
        }
        (Instant::now() > self.deadline).then(|| AppError {
            status: axum::http::StatusCode::UNPROCESSABLE_ENTITY,
            path: None,
            message: format!(
                "checking this request takes longer than {} s (each request's check \
                     budget); ask for fewer cells, or split the sweep into shards (nhlab \
                     sweep --shard)",
                CHECK_BUDGET.as_secs()
            ),
        })
    }
}

/// Shared state of the app; cheap to clone.
#[derive(Debug, Clone)]
pub struct AppState {
    /// The limits.
    pub config: Arc<Config>,
    /// Latitude axes and references kept across requests.
    pub caches: Arc<Caches>,
    active: ActiveRuns,
    slots: Arc<Semaphore>,
    checks: Arc<Semaphore>,
    budget: AnswerBudget,
    shutdown: Arc<watch::Sender<bool>>,
}

impl Default for AppState {
    fn default() -> Self {
        Self::new(Config::default())
    }
}

impl AppState {
    /// State with these limits.
    pub fn new(config: Config) -> Self {
        let slots = Arc::new(Semaphore::new(config.max_simulations));
        // As many checks at once as simulations: a check may solve a latitude axis.
        let checks = Arc::new(Semaphore::new(config.max_simulations));
        let budget = AnswerBudget::new(config.max_inflight_bytes);
        Self {
            config: Arc::new(config),
            caches: Arc::default(),
            active: ActiveRuns::default(),
            slots,
            checks,
            budget,
            shutdown: Arc::new(watch::Sender::new(false)),
        }
    }

    /// Number of simulation runs computing right now (one per method of a request).
    pub fn active_runs(&self) -> usize {
        self.active.count()
    }

    /// Number of simulations (admitted requests) holding a slot right now.
    pub fn busy_slots(&self) -> usize {
        self.config.max_simulations - self.slots.available_permits()
    }

    /// Bytes the answers in flight hold now (their estimates), and the limit.
    pub fn answers_in_flight(&self) -> (u64, u64) {
        (self.budget.used(), self.budget.limit())
    }

    /// The most bytes the answers in flight have held at once since the server started.
    pub fn answers_peak(&self) -> u64 {
        self.budget.peak()
    }

    /// Checks a request with `check` (which may compute: a latitude axis, a system's
    /// compilation) on the blocking pool, at most `max_simulations` at once: a flood of
    /// requests cannot take more threads or cores for checking than simulations have. Waits
    /// up to [`CHECK_WAIT`] for a turn, then 503. `check` is handed a [`Checking`] that says
    /// when to stop: its client left, or [`CHECK_BUDGET`] is spent.
    pub async fn check<T: Send + 'static>(
        &self,
        check: impl FnOnce(&Checking) -> Result<T, AppError> + Send + 'static,
    ) -> Result<T, AppError> {
        let permit = tokio::time::timeout(CHECK_WAIT, self.checks.clone().acquire_owned())
            .await
            .ok()
            .and_then(Result::ok)
            .ok_or_else(|| {
                AppError::unavailable(
                    "the server is busy checking other requests; retry in a moment",
                )
            })?;
        // The permit goes with the check: if the client leaves, the check runs on the blocking
        // pool until it next looks at `checking`, and counts until then.
        let cancel = Cancel::default();
        let _on_drop = cancel.on_drop();
        let checking = Checking { cancel, deadline: Instant::now() + CHECK_BUDGET };
        off_runtime(move || {
            let _permit = permit;
            check(&checking)
        })
        .await
    }

    /// Admission: a slot for one simulation and `answer_bytes` of the budget of answers in
    /// flight, or a 503 (with `Retry-After`) when all `max_simulations` are taken, the
    /// budget is spent or the server is shutting down. Never waits: a busy server says so at
    /// once rather than queueing without bound. Every handler that computes calls this after
    /// checking its input (a bad request gets its 4xx even when the server is busy). The
    /// guard goes with the answer until it is written.
    pub fn admit(&self, answer_bytes: u64) -> Result<(Slot, BudgetGuard), AppError> {
        if self.is_shutting_down() {
            return Err(AppError::unavailable("the server is shutting down; retry shortly"));
        }
        let permit = self.slots.clone().try_acquire_owned().map_err(|_| {
            AppError::unavailable(format!(
                "the server is busy: all {} simulation slots are taken (limit \
                 max_simulations); retry in a moment",
                self.config.max_simulations
            ))
        })?;
        let budget = self.budget.reserve(answer_bytes)?;
        Ok((Slot::new(permit), budget))
    }

    /// Asks every open stream to end (with a `shutdown` event) and admission to refuse.
    pub fn shut_down(&self) {
        self.shutdown.send_replace(true);
    }

    /// Whether [`shut_down`](Self::shut_down) was called.
    pub fn is_shutting_down(&self) -> bool {
        *self.shutdown.borrow()
    }

    /// Resolves once [`shut_down`](Self::shut_down) is called.
    pub async fn shutdown_requested(&self) {
        let mut rx = self.shutdown.subscribe();
        // The sender lives in self, so the channel cannot close under us.
        let _ = rx.wait_for(|&stop| stop).await;
    }

    /// Counts a run as active until the guard is dropped (also when the run panics).
    pub(crate) fn run_guard(&self) -> RunGuard {
        self.active.guard()
    }

    /// A runner whose runs count in [`active_runs`](Self::active_runs).
    pub(crate) fn runner(&self) -> Runner {
        Runner::new(&self.active, &self.config)
    }
}
