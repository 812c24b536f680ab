//! [`RunView`]: one run in the JSON response: its method, how it ended, its own compute
//! time and its error series (up to the failure, if it failed).

use crate::{MethodView, SeriesView};
use nhlab_core::RunOutcome;
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// It reached t_end.
    Ok,
    /// It stopped early; `error` says where and why.
    Failed,
}

impl Status {
    /// The status of an outcome.
    pub fn of(outcome: &RunOutcome) -> Self {
        if outcome.error.is_none() { Self::Ok } else { Self::Failed }
    }
}

/// One run of the JSON response.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct RunView {
    /// The method.
    pub method: MethodView,
    /// `ok` or `failed`.
    pub status: Status,
    /// Why it failed (step and time), or null.
    pub error: Option<String>,
    /// Steps completed.
    pub steps: u64,
    /// Wall-clock time of the run, from its start to its end, in milliseconds. It includes
    /// the time the run waited for a core: runs beyond the server's cores share them.
    pub elapsed_ms: f64,
    /// CPU time the run's thread used, in milliseconds: what the method cost, whatever the
    /// load (null where the platform does not measure it).
    pub cpu_ms: Option<f64>,
    /// Error series by integral.
    pub series: BTreeMap<String, SeriesView>,
}
