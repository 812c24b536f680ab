//! [`Verdicts`]: a run's series kept whole, with their initial values, to classify each one
//! ([`VerdictView`]) once the run has ended: a verdict needs the whole series; and their
//! gaps ([`GapView`]). Both observers keep one.

use crate::views::{GapView, VerdictView};
use nhlab_core::{Bucket, Gap, Integral, PreparedScene, classify};
use std::collections::BTreeMap;
use std::sync::Arc;

/// The API names of a scene's integrals: the fixed ones', and its system's invariants'.
#[derive(Debug, Clone, Default)]
pub struct IntegralNames(Arc<[String]>);

impl IntegralNames {
    /// The names of `prepared`'s integrals.
    pub fn of(prepared: &PreparedScene) -> Self {
        Self(prepared.scene.system.invariant_names().into())
    }

    /// The API name of `integral`.
    pub fn name(&self, integral: Integral) -> String {
        match integral {
            Integral::Invariant(k) => {
                self.0.get(k as usize).cloned().unwrap_or_else(|| format!("invariant{k}"))
            }
            _ => integral.id().to_owned(),
        }
    }
}

/// A run's series kept whole for their verdicts, by integral (an array indexed by the
/// integral's dense index: a bucket costs a push, not a map lookup).
#[derive(Debug, Clone, Default)]
pub struct Verdicts {
    names: IntegralNames,
    initial: [Option<f64>; Integral::COUNT],
    buckets: [Vec<Bucket>; Integral::COUNT],
    gaps: [Option<Gap>; Integral::COUNT],
}

impl Verdicts {
    /// Verdicts of series named by `names`.
    pub fn new(names: IntegralNames) -> Self {
        Self { names, ..Self::default() }
    }

    /// The API name of `integral`.
    pub fn name(&self, integral: Integral) -> String {
        self.names.name(integral)
    }

    /// Every integral a run may have, in order.
    fn every() -> impl Iterator<Item = Integral> {
        (0..Integral::COUNT).filter_map(Integral::of_index)
    }

    /// Records `I(0)` of a series (the scale of `exact`).
    pub fn initial(&mut self, integral: Integral, value: f64) {
        self.initial[integral.index()] = Some(value);
    }

    /// Records a bucket.
    pub fn push(&mut self, integral: Integral, bucket: Bucket) {
        self.buckets[integral.index()].push(bucket);
    }

    /// Records a series' gap.
    pub fn gap(&mut self, integral: Integral, gap: Gap) {
        self.gaps[integral.index()] = Some(gap);
    }

    /// The gap of one series, if it has one.
    pub fn gap_of(&self, integral: Integral) -> Option<GapView> {
        self.gaps[integral.index()].map(GapView::from)
    }

    /// Every series' gap, by integral id (only those that have one).
    pub fn gaps(&self) -> BTreeMap<String, GapView> {
        Self::every().filter_map(|i| Some((self.name(i), self.gap_of(i)?))).collect()
    }

    /// The buckets of one series (empty if it has none).
    pub fn buckets(&self, integral: Integral) -> &[Bucket] {
        &self.buckets[integral.index()]
    }

    /// The verdict of one series (`None` when it has no bucket: nothing to judge).
    pub fn of(&self, integral: Integral) -> Option<VerdictView> {
        let buckets = self.buckets(integral);
        if buckets.is_empty() {
            return None;
        }
        let scale = self.initial[integral.index()].unwrap_or(0.0);
        Some(classify(buckets, scale).into())
    }

    /// Every series' verdict, by integral id.
    pub fn all(&self) -> BTreeMap<String, VerdictView> {
        Self::every().filter_map(|i| Some((self.name(i), self.of(i)?))).collect()
    }
}
