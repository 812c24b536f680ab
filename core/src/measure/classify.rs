//! Verdicts on an error series: `exact`, `bounded` or `drift` (`docs/model.md` §6).
//!
//! Criterion (one for all series, documented in the API):
//! - `exact`: the largest error stays at round-off, `max ≤ 1e-10 · max(1, |I(0)|)`;
//! - `drift`: the mean error over the last quarter of the time span (`late`) exceeds the
//!   largest error over the first 1/32 of it (`early`): `late / early > 1`; or the integral
//!   has been consumed: `late ≥ ½ |I(0)|` and `late ≥ 0.9 max` (the error sits, to the end,
//!   at its largest value and at half the integral's own size or more);
//! - `bounded` otherwise.
//!
//! Why this shape: a bounded error reaches its full oscillation amplitude within a period or
//! two and its later *mean* stays below that early *max* (on the paper's scenes the ratio is
//! at most 0.76). A growing error ends above anything it reached early, including one that
//! grows early and then saturates (DLA^0.4 drains the CVT's passenger energy to zero by
//! t ≈ 400 of 3000: ratio 1.4), which a first-quarter/last-quarter mean ratio calls bounded.
//!
//! A drift that consumes the integral within the first 1/32 of the span saturates the early
//! window too (DLA^0.4 on the rotating CVT to t = 10⁶: the passenger's energy is gone by
//! t ≈ 400, so early = late = max = 1 and the ratio is 1): the consumption test catches it.
//! A bounded error does not sit at its largest value: it oscillates, its late mean well below
//! its max (at most 0.76 of it on the paper's scenes); nor does it reach half the integral.

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
/// `late / |I(0)|` at or above which an integral counts as consumed (when flat).
pub const CONSUMED: f64 = 0.5;
/// `late / max` at or above which the error sits at its largest value: flat, not oscillating.
pub const FLAT: f64 = 0.9;

/// Whether the error, late, sits at its largest value and at half the integral's own size or
/// more: the integral is gone (or doubled), however early that happened. Not defined for an
/// integral that starts at 0 (the constraint).
pub fn consumed(late: f64, max: f64, scale: f64) -> bool {
    let scale = scale.abs();
    scale > 0.0 && late >= CONSUMED * scale && late >= FLAT * max
}

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
    } else if ratio > DRIFT_RATIO || consumed(late, max, scale) {
        VerdictKind::Drift
    } else {
        VerdictKind::Bounded
    };
    Verdict { kind, max, early, late, ratio }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Buckets at t = 1..=n with these (mean, max).
    fn series(values: impl Fn(f64) -> (f64, f64), n: usize) -> Vec<Bucket> {
        (1..=n)
            .map(|k| {
                let (mean, max) = values(k as f64 / n as f64);
                Bucket { t: k as f64, mean, max }
            })
            .collect()
    }

    #[test]
    fn an_integral_consumed_early_is_a_drift_not_bounded() {
        // Gone within the first bucket: early = late = max = |I(0)| = 1, ratio 1.
        let drained = series(|_| (1.0, 1.0), 200);
        let v = classify(&drained, 1.0);
        assert_eq!((v.kind, v.ratio), (VerdictKind::Drift, 1.0));
        // The same error on an integral ten times larger is not consumed: bounded.
        assert_eq!(classify(&drained, 10.0).kind, VerdictKind::Bounded);
        // An oscillation as large as the integral is bounded: its late mean is below its max.
        let oscillating = series(|_| (0.6, 1.0), 200);
        assert_eq!(classify(&oscillating, 1.0).kind, VerdictKind::Bounded);
        // The constraint (I(0) = 0) is never "consumed".
        assert_eq!(classify(&series(|_| (0.9e-3, 1e-3), 200), 0.0).kind, VerdictKind::Bounded);
        // A drift the ratio sees stays one.
        let growing = series(|s| (s, s), 200);
        assert_eq!(classify(&growing, 100.0).kind, VerdictKind::Drift);
    }
}
