//! [`Verdicts`]: a run's series kept whole, with their initial values, to classify each one
//! ([`VerdictView`]) once the run has ended: a verdict needs the whole series; and their
//! gaps ([`GapView`]). Both observers keep one.

use crate::views::{GapView, VerdictView};
use nhlab_core::{Bucket, Gap, Integral, classify};
use std::collections::BTreeMap;

/// A run's series kept whole for their verdicts, by integral (an array indexed by the
/// integral's discriminant: a bucket costs a push, not a map lookup).
#[derive(Debug, Clone, Default)]
pub struct Verdicts {
    initial: [Option<f64>; Integral::ALL.len()],
    buckets: [Vec<Bucket>; Integral::ALL.len()],
    gaps: [Option<Gap>; Integral::ALL.len()],
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

    /// Records a series' gap.
    pub fn gap(&mut self, integral: Integral, gap: Gap) {
        self.gaps[integral as usize] = Some(gap);
    }

    /// The gap of one series, if it has one.
    pub fn gap_of(&self, integral: Integral) -> Option<GapView> {
        self.gaps[integral as usize].map(GapView::from)
    }

    /// Every series' gap, by integral id (only those that have one).
    pub fn gaps(&self) -> BTreeMap<String, GapView> {
        Integral::ALL.iter().filter_map(|&i| Some((i.id().to_owned(), self.gap_of(i)?))).collect()
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
