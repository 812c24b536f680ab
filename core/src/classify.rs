//! Verdicts on an error series: `exact`, `bounded` or `drift` (MATH.md §6).
//!
//! Criterion (one for all series, documented in the API):
//! - `exact`: the largest error stays at round-off, `max ≤ 1e-10 · max(1, |I(0)|)`;
//! - otherwise compare the mean error over the last quarter of the time span (`late`) with
//!   the mean over the second quarter (`early`); `drift` when `late / early > 2`, else
//!   `bounded`. The first quarter is skipped because an error starts at zero and needs a
//!   few periods to reach its oscillation level; a linear drift gives a ratio of 7/3, a
//!   bounded oscillation a ratio near 1.

use crate::Bucket;

/// What a series does over time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VerdictKind {
    /// Round-off only.
    Exact,
    /// Oscillates without growth.
    Bounded,
    /// Grows with t.
    Drift,
}

impl VerdictKind {
    /// The API name.
    pub fn id(self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::Bounded => "bounded",
            Self::Drift => "drift",
        }
    }
}

/// A verdict with the numbers behind it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Verdict {
    /// The verdict.
    pub kind: VerdictKind,
    /// Largest error.
    pub max: f64,
    /// Mean error over the second quarter of the time span.
    pub early: f64,
    /// Mean error over the last quarter.
    pub late: f64,
    /// `late / early`.
    pub ratio: f64,
}

/// Round-off threshold, relative to `max(1, |I(0)|)`.
pub const EXACT_TOL: f64 = 1e-10;
/// `late / early` above which a series drifts.
pub const DRIFT_RATIO: f64 = 2.0;

/// Classifies a series of buckets; `scale` is `|I(0)|` (0 for the constraint).
pub fn classify(buckets: &[Bucket], scale: f64) -> Verdict {
    let max = buckets.iter().map(|b| b.max).fold(0.0, f64::max);
    let span = buckets.last().map_or(0.0, |b| b.t);
    let mean = |lo: f64, hi: f64| {
        let (sum, n) = buckets
            .iter()
            .filter(|b| b.t > lo * span && b.t <= hi * span)
            .fold((0.0, 0usize), |(s, n), b| (s + b.mean, n + 1));
        if n == 0 { 0.0 } else { sum / n as f64 }
    };
    let (early, late) = (mean(0.25, 0.5), mean(0.75, 1.0));
    let ratio = if early > 0.0 {
        late / early
    } else if late > 0.0 {
        f64::INFINITY
    } else {
        1.0
    };
    let kind = if max <= EXACT_TOL * scale.abs().max(1.0) {
        VerdictKind::Exact
    } else if ratio > DRIFT_RATIO {
        VerdictKind::Drift
    } else {
        VerdictKind::Bounded
    };
    Verdict { kind, max, early, late, ratio }
}
