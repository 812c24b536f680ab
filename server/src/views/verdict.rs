//! [`VerdictView`]: what an error series does over time — `exact`, `bounded` or `drift` — with
//! the numbers behind it, by the core's criterion ([`nhlab_core::classify`], quoted in
//! [`CRITERION`]).

use nhlab_core::Verdict;
use serde::Serialize;
use utoipa::ToSchema;

/// The criterion, as the API documents it and the page shows it.
pub const CRITERION: &str = "exact: the largest error stays at round-off, \
    max ≤ 1e-10·max(1, |I(0)|); drift: the mean error over the last quarter of the time span \
    (late) exceeds the largest error over its first 1/32 (early), ratio = late/early > 1, or \
    the integral has been consumed: late ≥ |I(0)|/2 and late ≥ 0.9·max (the error sits, to the \
    end, at its largest value and at half the integral's size or more, however early it got \
    there); bounded otherwise. A bounded error reaches its full oscillation within a period or \
    two and its later mean stays below that early maximum; a growing error ends above \
    anything it reached early. The constraint residual is measured against 0, the latitude over its section \
    crossings. For a failed run, the verdict is of the series up to the failure; for a series \
    with a gap (no values from some time on: the latitude with the passenger at rest or no \
    more section crossings), of its values before the gap.";

/// A series' verdict.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, ToSchema)]
pub struct VerdictView {
    /// `exact`, `bounded` or `drift`.
    #[schema(value_type = String, example = "bounded")]
    pub kind: &'static str,
    /// Largest error (null if not finite).
    pub max: Option<f64>,
    /// Largest error over the first 1/32 of the time span.
    pub early: Option<f64>,
    /// Mean error over the last quarter of the time span.
    pub late: Option<f64>,
    /// `late / early` (null if not finite: no early error).
    pub ratio: Option<f64>,
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl From<Verdict> for VerdictView {
    fn from(v: Verdict) -> Self {
        Self {
            kind: v.kind.id(),
            max: finite(v.max),
            early: finite(v.early),
            late: finite(v.late),
            ratio: finite(v.ratio),
        }
    }
}
