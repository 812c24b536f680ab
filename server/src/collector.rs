//! [`Collector`]: the observer of a JSON request's run: keeps every bucket, stops when the
//! request is cancelled, and judges each series once the run has ended ([`Verdicts`]).

use crate::{Cancel, SeriesView, Verdicts};
use nhlab_core::{Bucket, Integral, Observer};
use std::collections::BTreeMap;
use std::ops::ControlFlow;

/// Collects a run's series.
#[derive(Debug)]
pub struct Collector {
    /// Series by integral (every integral of the plan, possibly empty); keyed by the
    /// integral, not its id, so that a bucket costs no string allocation.
    pub series: BTreeMap<Integral, SeriesView>,
    /// The series kept whole for their verdicts.
    pub verdicts: Verdicts,
    cancel: Cancel,
}

impl Collector {
    /// A collector for `integrals`, stopping when `cancel` is set.
    pub fn new(integrals: &[Integral], cancel: Cancel) -> Self {
        let series = integrals.iter().map(|&i| (i, SeriesView::default())).collect();
        Self { series, verdicts: Verdicts::default(), cancel }
    }

    /// The series by integral id, each with its verdict (null for an empty series).
    pub fn into_series(self) -> BTreeMap<String, SeriesView> {
        let verdicts = self.verdicts;
        self.series
            .into_iter()
            .map(|(i, mut s)| {
                s.verdict = Some(verdicts.of(i));
                (i.id().to_owned(), s)
            })
            .collect()
    }
}

impl Observer for Collector {
    fn initial(&mut self, integral: Integral, value: f64) {
        self.verdicts.initial(integral, value);
    }

    fn points(&mut self, integral: Integral, bucket: Bucket) {
        self.series.entry(integral).or_default().push(bucket);
        self.verdicts.push(integral, bucket);
    }

    fn progress(&mut self, _steps_done: u64, _t: f64) -> ControlFlow<()> {
        if self.cancel.is_cancelled() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }
}
