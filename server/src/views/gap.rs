//! [`GapView`]: why a series has no values from some time on although its run went on (the
//! core's [`nhlab_core::Gap`]: the latitude with the passenger at rest, or with no more
//! section crossings). Its verdict is then of the values before the gap.

use nhlab_core::Gap;
use serde::Serialize;
use utoipa::ToSchema;

/// A series' trailing gap.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct GapView {
    /// Time of the series' last value (0 when it has none); none from there to t_end.
    pub since: f64,
    /// `passenger_at_rest` (u = 0 at the crossings: the latitude is undefined) or
    /// `no_crossing` (the driver stopped returning to the section).
    #[schema(value_type = String, example = "passenger_at_rest")]
    pub reason: &'static str,
    /// The same, as a sentence.
    #[schema(example = "no value since t = 73405: the passenger is at rest (u = 0 at the \
        section crossings), where the latitude a·u/|u| is undefined")]
    pub message: String,
}

impl From<Gap> for GapView {
    fn from(g: Gap) -> Self {
        Self { since: g.since, reason: g.reason.id(), message: g.message() }
    }
}
