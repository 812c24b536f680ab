//! [`SeriesView`]: one integral's error series as columns `t`, `mean`, `max` (the core's
//! buckets). Non-finite values (a diverging run) are written as JSON `null`. In the JSON
//! response each series also carries its [`VerdictView`]; a stream's `points` events carry
//! none (the `run` event has the verdicts, which need the whole series), and no gap.

use crate::views::{GapView, VerdictView};
use nhlab_core::Bucket;
use serde::Serialize;
use utoipa::ToSchema;

/// Buckets of one error series, as columns.
#[derive(Debug, Clone, Default, PartialEq, Serialize, ToSchema)]
pub struct SeriesView {
    /// Time of each bucket's last sample.
    pub t: Vec<Option<f64>>,
    /// Mean error over each bucket (null if not finite).
    pub mean: Vec<Option<f64>>,
    /// Max error over each bucket (null if not finite).
    pub max: Vec<Option<f64>>,
    /// What the series does over time (JSON response only, null for an empty series; left
    /// out of `points` events).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<VerdictView>)]
    pub verdict: Option<Option<VerdictView>>,
    /// Why the series has no values from some time on although its run went on (JSON
    /// response only: null for a series without one; left out of `points` events).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<GapView>)]
    pub gap: Option<Option<GapView>>,
}

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl SeriesView {
    /// An empty series with room for `n` buckets.
    pub fn with_capacity(n: usize) -> Self {
        Self {
            t: Vec::with_capacity(n),
            mean: Vec::with_capacity(n),
            max: Vec::with_capacity(n),
            verdict: None,
            gap: None,
        }
    }

    /// Appends a bucket.
    pub fn push(&mut self, b: Bucket) {
        self.t.push(finite(b.t));
        self.mean.push(finite(b.mean));
        self.max.push(finite(b.max));
    }

    /// Whether it holds no bucket.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
}
