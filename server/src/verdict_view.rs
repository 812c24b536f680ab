//! [`VerdictView`]: what an error series does over time — `exact`, `bounded` or `drift` — with
//! the numbers behind it, by the core's criterion ([`nhlab_core::classify`], quoted in
//! [`CRITERION`]). [`Verdicts`] keeps a run's buckets and initial values to classify each
//! series once the run has ended (a verdict needs the whole series).

use nhlab_core::{Bucket, Integral, Verdict, classify};
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// The criterion, as the API documents it and the page shows it.
pub const CRITERION: &str = "exact: the largest error stays at round-off, \
    max ≤ 1e-10·max(1, |I(0)|); drift: the mean error over the last quarter of the time span \
    (late) exceeds the largest error over its first 1/32 (early), ratio = late/early > 1; \
    bounded otherwise. A bounded error reaches its full oscillation within a period or two and \
    its later mean stays below that early maximum; a growing error ends above anything it \
    reached early. The constraint residual is measured against 0, the latitude over its section \
    crossings. For a failed run, the verdict is of the series up to the failure.";

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

/// A run's series kept whole for their verdicts, by integral (an array indexed by the
/// integral's discriminant: a bucket costs a push, not a map lookup).
#[derive(Debug, Clone, Default)]
pub struct Verdicts {
    initial: [Option<f64>; Integral::ALL.len()],
    buckets: [Vec<Bucket>; Integral::ALL.len()],
}

impl Verdicts {
    /// Records `I(0)` of a series (the scale of `exact`).
    pub fn initial(&mut self, integral: Integral, value: f64) {
        self.initial[integral as usize] = Some(value);
    }

    /// Records a bucket.
    pub fn push(&mut self, integral: Integral, bucket: Bucket) {
        self.buckets[integral as usize].push(bucket);
    }

    /// The buckets of one series (empty if it has none).
    pub fn buckets(&self, integral: Integral) -> &[Bucket] {
        &self.buckets[integral as usize]
    }

    /// The verdict of one series (`None` when it has no bucket: nothing to judge).
    pub fn of(&self, integral: Integral) -> Option<VerdictView> {
        let buckets = self.buckets(integral);
        if buckets.is_empty() {
            return None;
        }
        let scale = self.initial[integral as usize].unwrap_or(0.0);
        Some(classify(buckets, scale).into())
    }

    /// Every series' verdict, by integral id.
    pub fn all(&self) -> BTreeMap<String, VerdictView> {
        Integral::ALL.iter().filter_map(|&i| Some((i.id().to_owned(), self.of(i)?))).collect()
    }
}
