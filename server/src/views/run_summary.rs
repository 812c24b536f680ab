//! [`RunSummary`]: how one run went, as every report of a run gives it: its method, how it
//! ended, how far it got and what it cost. A run of the JSON response
//! ([`RunView`](crate::views::RunView)), the stream's `run` event
//! ([`RunEvent`](crate::views::RunEvent)) and a run of the scorecard
//! ([`ScorecardRun`](crate::views::ScorecardRun)) each hold one, flattened into their own
//! fields.

use crate::views::{MethodView, Status};
use nhlab_core::RunOutcome;
use serde::Serialize;
use utoipa::ToSchema;

/// How one run went.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct RunSummary {
    /// The method.
    pub method: MethodView,
    /// `ok` or `failed`.
    pub status: Status,
    /// Why it failed (step and time: diverged, Newton, or `time limit:` past
    /// `max_run_seconds`), or null.
    pub error: Option<String>,
    /// Steps completed.
    pub steps: u64,
    /// Wall-clock time of the run, from its start to its end, in milliseconds. It includes
    /// the time the run waited for a core: runs beyond the server's cores share them.
    pub elapsed_ms: f64,
    /// CPU time the run's thread used, in milliseconds: what the method cost, whatever the
    /// load (null where the platform does not measure it).
    pub cpu_ms: Option<f64>,
}

impl RunSummary {
    /// A run of `method` that ended with `outcome`, timed `elapsed_ms` (wall) and `cpu_ms`.
    pub fn new(
        method: MethodView,
        outcome: &RunOutcome,
        elapsed_ms: f64,
        cpu_ms: Option<f64>,
    ) -> Self {
        Self {
            method,
            status: Status::of(outcome),
            error: outcome.error.as_ref().map(|e| e.to_string()),
            steps: outcome.steps,
            elapsed_ms,
            cpu_ms,
        }
    }

    /// A run of `method` not taken: the method has no step for the system (`why`).
    pub fn not_applicable(method: MethodView, why: String) -> Self {
        Self {
            method,
            status: Status::NotApplicable,
            error: Some(why),
            steps: 0,
            elapsed_ms: 0.0,
            cpu_ms: None,
        }
    }

    /// A run of `method` that failed without an outcome (it panicked, or its task was lost):
    /// no step counted.
    pub fn failed(method: MethodView, error: String, elapsed_ms: f64, cpu_ms: Option<f64>) -> Self {
        Self { method, status: Status::Failed, error: Some(error), steps: 0, elapsed_ms, cpu_ms }
    }
}
