//! [`Collector`]: the observer of a JSON request's run: keeps every bucket, stops when the
//! request is cancelled, and judges each series once the run has ended ([`Verdicts`]).

use crate::{Cancel, SeriesView, Verdicts};
use nhlab_core::{Bucket, Integral, Observer};
use std::collections::BTreeMap;
use std::ops::ControlFlow;

/// Collects a run's series.
#[derive(Debug)]
pub struct Collector {
    /// Series by integral id (every integral of the plan, possibly empty).
    pub series: BTreeMap<String, SeriesView>,
    /// The series kept whole for their verdicts.
    pub verdicts: Verdicts,
    cancel: Cancel,
}

impl Collector {
    /// A collector for `integrals`, stopping when `cancel` is set.
    pub fn new(integrals: &[Integral], cancel: Cancel) -> Self {
        let series = integrals.iter().map(|i| (i.id().to_owned(), SeriesView::default())).collect();
        Self { series, verdicts: Verdicts::default(), cancel }
    }

    /// The series, each with its verdict (null for an empty series).
    pub fn into_series(self) -> BTreeMap<String, SeriesView> {
        let mut series = self.series;
        for (id, s) in &mut series {
            let verdict = Integral::from_id(id).and_then(|i| self.verdicts.of(i));
            s.verdict = Some(verdict);
        }
        series
    }
}

impl Observer for Collector {
    fn initial(&mut self, integral: Integral, value: f64) {
        self.verdicts.initial(integral, value);
    }

    fn points(&mut self, integral: Integral, bucket: Bucket) {
        self.series.entry(integral.id().to_owned()).or_default().push(bucket);
        self.verdicts.push(integral, bucket);
    }

    fn progress(&mut self, _steps_done: u64, _t: f64) -> ControlFlow<()> {
        if self.cancel.is_cancelled() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }
}
