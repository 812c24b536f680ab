//! [`Collector`]: the observer of a JSON request's run: keeps every bucket, stops when the
//! request is cancelled.

use crate::{Cancel, SeriesView};
use nhlab_core::{Bucket, Integral, Observer};
use std::collections::BTreeMap;
use std::ops::ControlFlow;

/// Collects a run's series.
#[derive(Debug)]
pub struct Collector {
    /// Series by integral id (every integral of the plan, possibly empty).
    pub series: BTreeMap<String, SeriesView>,
    cancel: Cancel,
}

impl Collector {
    /// A collector for `integrals`, stopping when `cancel` is set.
    pub fn new(integrals: &[Integral], cancel: Cancel) -> Self {
        let series = integrals.iter().map(|i| (i.id().to_owned(), SeriesView::default())).collect();
        Self { series, cancel }
    }
}

impl Observer for Collector {
    fn points(&mut self, integral: Integral, bucket: Bucket) {
        self.series.entry(integral.id().to_owned()).or_default().push(bucket);
    }

    fn progress(&mut self, _steps_done: u64, _t: f64) -> ControlFlow<()> {
        if self.cancel.is_cancelled() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }
}
