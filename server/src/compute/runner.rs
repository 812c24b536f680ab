//! [`Runner`]: runs one method of a [`Plan`] on the blocking thread pool, never on the
//! async runtime, counting it in [`ActiveRuns`], holding the request's [`Slot`] until it
//! ends, and timing it: wall clock and its thread's CPU time ([`ThreadClock`]). A panic in a
//! run is caught and becomes that run's error (500 for a JSON request, a failed `run` event
//! in a stream).
//!
//! Checking a request runs there too ([`off_runtime`]), before admission.
//!
//! Cancellation: a [`Cancel`](crate::compute::Cancel) flag, set when the client goes away
//! (the handler's future or the stream is dropped, see
//! [`CancelOnDrop`](crate::compute::CancelOnDrop)) or the server shuts down, and checked by
//! the observers at every progress call. A run is paced ([`run_config`](crate::compute::run_config)): the core calls its
//! observer every [`PROGRESS_EVERY`](crate::compute::PROGRESS_EVERY) steps, or about every
//! [`AIM`](nhlab_core::measure::pace::AIM) where those steps would take longer (a built-in's
//! step costs 50 ns, a heavy formula system's milliseconds), so a run notices within a few
//! milliseconds whatever its system; and it ends as failed past `max_run_seconds`.

use crate::compute::{ActiveRuns, Plan, Slot, ThreadClock, millis};
use crate::config::Config;
use crate::error::AppError;
use crate::views::{MethodView, RunSummary};
use nhlab_core::{Observer, RunOutcome};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};
use tokio::task::JoinHandle;

/// `max_run_seconds` as a duration (a limit too large for one is as good as none).
pub fn time_limit(config: &Config) -> Duration {
    Duration::try_from_secs_f64(config.max_run_seconds).unwrap_or(Duration::MAX)
}

/// How one run ended.
#[derive(Debug)]
pub struct Finished<O> {
    /// The run index (its place in the plan's methods).
    pub index: usize,
    /// The core's outcome, or the panic message if the simulation panicked.
    pub outcome: Result<RunOutcome, String>,
    /// Wall-clock time from the run's start to its end, in milliseconds.
    pub elapsed_ms: f64,
    /// CPU time of the run's thread, in milliseconds (`None` where not measured).
    pub cpu_ms: Option<f64>,
    /// The observer, with whatever it collected.
    pub observer: O,
}

impl<O> Finished<O> {
    /// How the run of `method` went, or the panic's message if it panicked.
    pub fn summary(&self, method: MethodView) -> Result<RunSummary, &str> {
        match &self.outcome {
            Ok(outcome) => Ok(RunSummary::new(method, outcome, self.elapsed_ms, self.cpu_ms)),
            Err(panic) => Err(panic),
        }
    }
}

/// Starts runs of a plan.
#[derive(Debug, Clone)]
pub struct Runner {
    runs: ActiveRuns,
    slot: Option<Slot>,
    /// `Config::max_run_seconds`.
    time_limit: Duration,
    /// `Config::panic_on_points` (debug builds only).
    #[cfg(debug_assertions)]
    panic_on_points: Option<usize>,
}

impl Runner {
    /// A runner counting its runs in `runs`, with the app's `config`.
    pub fn new(runs: &ActiveRuns, config: &Config) -> Self {
        Self {
            runs: runs.clone(),
            slot: None,
            time_limit: time_limit(config),
            #[cfg(debug_assertions)]
            panic_on_points: config.panic_on_points,
        }
    }

    /// The same, its runs holding `slot` (from
    /// [`AppState::admit`](crate::state::AppState::admit)) until they end.
    pub fn with_slot(mut self, slot: Slot) -> Self {
        self.slot = Some(slot);
        self
    }

    /// Runs method `index` of `plan` on the blocking pool, reporting to `observer`.
    pub fn spawn<O: Observer + Send + 'static>(
        &self,
        plan: &Plan,
        index: usize,
        observer: O,
    ) -> JoinHandle<Finished<O>> {
        self.spawn_then(plan, index, observer, |finished| finished)
    }

    /// [`Runner::spawn`], then `then` on the same blocking thread once the run has ended
    /// (outside its `elapsed_ms`). What an answer needs from a run (its JSON, its last
    /// events) is made there, in parallel with the other runs, rather than after all of
    /// them.
    pub fn spawn_then<O: Observer + Send + 'static, T: Send + 'static>(
        &self,
        plan: &Plan,
        index: usize,
        mut observer: O,
        then: impl FnOnce(Finished<O>) -> T + Send + 'static,
    ) -> JoinHandle<T> {
        let guard = self.runs.guard();
        let slot = self.slot.clone();
        #[cfg(debug_assertions)]
        let inject_panic = self.panic_on_points == Some(plan.points);
        let prepared = plan.prepared.clone();
        let method = plan.methods[index];
        let cfg = plan.run_config(Some(self.time_limit));
        tokio::task::spawn_blocking(move || {
            let (_guard, _slot) = (guard, slot);
            lower_priority();
            let (start, clock) = (Instant::now(), ThreadClock::start());
            let outcome = catch_unwind(AssertUnwindSafe(|| {
                #[cfg(debug_assertions)]
                if inject_panic {
                    panic!("injected fault (Config::panic_on_points, debug builds only)");
                }
                prepared.run(&method, &cfg, &mut observer)
            }))
            .map_err(|panic| {
                let message = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".into());
                tracing::error!(run = index, %message, "simulation panicked");
                message
            });
            // Read in the reverse order of the starts, so that the CPU clock's span lies
            // within the wall clock's.
            let cpu_ms = clock.elapsed_ms();
            let elapsed_ms = millis(start.elapsed());
            then(Finished { index, outcome, elapsed_ms, cpu_ms, observer })
        })
    }
}

/// Runs `check` (resolving a request, which may compute latitude axes: Dop853 solves that
/// can take a while for an odd scene) on the blocking pool at low priority, so that checking
/// input never holds up the async runtime either. A panic in it is a 500.
pub async fn off_runtime<T: Send + 'static>(
    check: impl FnOnce() -> Result<T, AppError> + Send + 'static,
) -> Result<T, AppError> {
    tokio::task::spawn_blocking(move || {
        lower_priority();
        check()
    })
    .await
    .map_err(|e| AppError::internal(format!("internal error: checking the request: {e}")))?
}

/// Makes the current blocking-pool thread yield to the async runtime's threads (nice 19 on
/// Linux), once per thread: however many runs compute, the kernel lets a runtime thread that
/// wakes up (a request to answer, an event to send) run at once, so `/health`, admission and
/// the streams stay responsive. Other systems keep the default priority.
pub fn lower_priority() {
    #[cfg(target_os = "linux")]
    {
        use std::cell::Cell;
        thread_local!(static LOWERED: Cell<bool> = const { Cell::new(false) });
        LOWERED.with(|lowered| {
            if !lowered.get() {
                lowered.set(true);
                // SAFETY: plain system calls on the calling thread's own id; no memory is
                // shared. A failure (not permitted) leaves the priority as it was.
                #[allow(unsafe_code, reason = "setpriority has no safe wrapper in libc")]
                let result = unsafe {
                    libc::setpriority(libc::PRIO_PROCESS, libc::gettid() as libc::id_t, 19)
                };
                if result != 0 {
                    tracing::debug!("could not lower the priority of a simulation thread");
                }
            }
        });
    }
}
