//! [`RunView`]: one run in the JSON response: its [`RunSummary`] and its error series (up to
//! the failure, if it failed).

use crate::views::{RunSummary, SeriesView};
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
}
