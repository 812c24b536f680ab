//! The payloads of the stream's server-sent events, in order: `scene` (a [`SceneView`],
//! once), then per run any number of `progress`, `points`, `observables` and `section`, one
//! `run`, and `done` last —
//! or `shutdown` last instead when the server shuts down mid-stream (its runs stopped).
//! Concatenating a run's `points` for an integral gives the JSON response's series exactly.
//! [`sse_event`](crate::observers::sse_event) writes them.
//!
//! [`SceneView`]: crate::views::SceneView

use crate::views::{GapView, ObservablesView, RunSummary, SeriesView, VerdictView};
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// `progress`: how far a run is (a few per second per run).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ProgressEvent {
    /// Run index (the method's place in `scene.methods`).
    pub run: usize,
    /// Time reached.
    pub t: f64,
    /// Steps done over steps planned, in [0, 1].
    pub fraction: f64,
    /// Steps done.
    pub steps: u64,
}

/// `points`: the buckets of one series completed since the last `points` of that series.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct PointsEvent {
    /// Run index.
    pub run: usize,
    /// Integral id.
    pub integral: String,
    /// The new buckets, as columns `t`, `mean`, `max`.
    #[serde(flatten)]
    pub series: SeriesView,
}

/// `observables`: a run's observables sampled since its last `observables` event, as
/// columns `t` and one per observable (concatenated, the JSON answer's `observables`).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ObservablesEvent {
    /// Run index.
    pub run: usize,
    /// The new samples.
    #[serde(flatten)]
    #[schema(value_type = Object)]
    pub observables: ObservablesView,
}

/// `section`: a run's crossings of its Poincaré section since its last `section` event, as
/// columns `t` (the crossing times) and one per plotted quantity (concatenated, the JSON
/// answer's `section`).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SectionEvent {
    /// Run index.
    pub run: usize,
    /// The new crossings.
    #[serde(flatten)]
    #[schema(value_type = Object)]
    pub section: ObservablesView,
}

/// `run`: a run ended.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct RunEvent {
    /// Run index.
    pub run: usize,
    /// How the run went.
    #[serde(flatten)]
    pub summary: RunSummary,
    /// The verdict of each series, by integral (they need the whole series, so they come
    /// here rather than with the `points`).
    pub verdicts: BTreeMap<String, VerdictView>,
    /// The gap of each series that has one, by integral: no values from `since` on although
    /// the run went on (its verdict is of the values before).
    pub gaps: BTreeMap<String, GapView>,
}

/// `done`: every run has ended; the stream closes.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct DoneEvent {
    /// Number of runs.
    pub runs: usize,
    /// How many failed.
    pub failed: usize,
    /// Wall-clock time of the whole request, in milliseconds.
    pub elapsed_ms: f64,
}

/// `shutdown`: the server is shutting down; the runs were stopped (their `run` events came
/// before, as failed) and the stream closes. The request may be sent again later.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ShutdownEvent {
    /// What happened.
    pub error: String,
    /// Number of runs.
    pub runs: usize,
    /// Wall-clock time of the whole request, in milliseconds.
    pub elapsed_ms: f64,
}
