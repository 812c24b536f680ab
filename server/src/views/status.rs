//! [`Status`]: how a run ended, `ok` or `failed`.

use nhlab_core::RunOutcome;
use serde::Serialize;
use utoipa::ToSchema;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// It reached t_end.
    Ok,
    /// It stopped early; `error` says where and why.
    Failed,
    /// The method has no step for the system (the scorecard's runs only); `error` says why.
    #[serde(rename = "not_applicable")]
    NotApplicable,
}

impl Status {
    /// The status of an outcome.
    pub fn of(outcome: &RunOutcome) -> Self {
        if outcome.error.is_none() { Self::Ok } else { Self::Failed }
    }
}
