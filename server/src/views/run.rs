//! [`RunView`]: one run in the JSON response: its [`RunSummary`] and its error series (up to
//! the failure, if it failed).

use crate::views::{ObservablesView, RunSummary, SeriesView};
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// One run of the JSON response.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct RunView {
    /// How the run went.
    #[serde(flatten)]
    pub summary: RunSummary,
    /// Error series by integral.
    pub series: BTreeMap<String, SeriesView>,
    /// The observables asked for, sampled at `points` times spread evenly over the run (the
    /// state at the step ending nearest each time; up to the failure, if it failed); absent
    /// when none were asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>, example = json!({"t": [0.0, 0.5], "theta": [0.1, 0.2]}))]
    pub observables: Option<ObservablesView>,
    /// The Poincaré section asked for: `t`, the times of the crossings, and one column per
    /// plotted quantity, named by its text; absent when none was asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>, example = json!({"t": [6.1, 12.4], "x": [0.1, 0.2]}))]
    pub section: Option<ObservablesView>,
}
