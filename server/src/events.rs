//! The payloads of the stream's server-sent events, in order: `scene` (a [`SceneView`],
//! once), then per run any number of `progress` and `points`, one `run`, and `done` last —
//! or `shutdown` last instead when the server shuts down mid-stream (its runs stopped).
//! Concatenating a run's `points` for an integral gives the JSON response's series exactly.
//!
//! [`SceneView`]: crate::SceneView

use crate::{MethodView, SeriesView, Status, VerdictView};
use axum::response::sse::Event;
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

/// `run`: a run ended.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct RunEvent {
    /// Run index.
    pub run: usize,
    /// The method.
    pub method: MethodView,
    /// `ok` or `failed`.
    pub status: Status,
    /// Why it failed, or null.
    pub error: Option<String>,
    /// Steps completed.
    pub steps: u64,
    /// Wall-clock time of the run, from its start to its end, in milliseconds. It includes
    /// the time the run waited for a core: runs beyond the server's cores share them.
    pub elapsed_ms: f64,
    /// CPU time the run's thread used, in milliseconds: what the method cost, whatever the
    /// load (null where the platform does not measure it).
    pub cpu_ms: Option<f64>,
    /// The verdict of each series, by integral (they need the whole series, so they come
    /// here rather than with the `points`).
    pub verdicts: BTreeMap<String, VerdictView>,
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

/// An event named `name` carrying `data` as JSON.
///
/// Serialized into one buffer first: axum's `Event::json_data` hands serde_json's every token
/// (each number, comma, bracket) to its line-splitting writer, a memchr and a copy per token,
/// which cost a stream of `points` about 5 % of the server's CPU.
pub fn event<T: Serialize>(name: &str, data: &T) -> Event {
    match serde_json::to_string(data) {
        Ok(json) => Event::default().event(name).data(json),
        Err(e) => {
            let message = format!("could not serialize the {name} event: {e}");
            let error = serde_json::json!({ "error": message }).to_string();
            Event::default().event("error").data(error)
        }
    }
}
