//! Verdicts on an error series: `exact`, `bounded` or `drift` (`docs/model.md` §6).
//!
//! Criterion (one for all series, documented in the API):
//! - `exact`: the largest error stays at round-off, `max ≤ 1e-10 · max(1, |I(0)|)`;
//! - `drift`: the mean error over the last quarter of the time span (`late`) exceeds the
//!   largest error over the first 1/32 of it (`early`): `late / early > 1`;
//! - `bounded` otherwise.
//!
//! Why this shape: a bounded error reaches its full oscillation amplitude within a period or
//! two and its later *mean* stays below that early *max* (on the paper's scenes the ratio is
//! at most 0.76). A growing error ends above anything it reached early, including one that
//! grows early and then saturates (DLA^0.4 drains the CVT's passenger energy to zero by
//! t ≈ 400 of 3000: ratio 1.4), which a first-quarter/last-quarter mean ratio calls bounded.

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
    /// Largest error over the first 1/32 of the time span.
    pub early: f64,
    /// Mean error over the last quarter.
    pub late: f64,
    /// `late / early`.
    pub ratio: f64,
}

/// Round-off threshold, relative to `max(1, |I(0)|)`.
pub const EXACT_TOL: f64 = 1e-10;
/// `late / early` above which a series drifts.
pub const DRIFT_RATIO: f64 = 1.0;
/// Fraction of the span whose largest error is the early level.
pub const EARLY_FRACTION: f64 = 1.0 / 32.0;

/// Classifies a series of buckets; `scale` is `|I(0)|` (0 for the constraint).
pub fn classify(buckets: &[Bucket], scale: f64) -> Verdict {
    let max = buckets.iter().map(|b| b.max).fold(0.0, f64::max);
    let span = buckets.last().map_or(0.0, |b| b.t);
    // With few buckets a window may be empty: then the first (last) bucket stands for it.
    let early_buckets = buckets.iter().take_while(|b| b.t <= EARLY_FRACTION * span).count().max(1);
    let early = buckets.iter().take(early_buckets).map(|b| b.max).fold(0.0, f64::max);
    let late_buckets: Vec<f64> =
        buckets.iter().filter(|b| b.t > 0.75 * span).map(|b| b.mean).collect();
    let late = if late_buckets.is_empty() {
        buckets.last().map_or(0.0, |b| b.mean)
    } else {
        late_buckets.iter().sum::<f64>() / late_buckets.len() as f64
    };
    let ratio = if early > 0.0 {
        late / early
    } else if late > 0.0 {
        f64::INFINITY
    } else {
        0.0
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
