//! [`JsonCollector`]: the observer of a run answered in one JSON document (`/simulate`
//! without a stream, `/scorecard`): keeps every bucket, stops when the request is cancelled,
//! and once the run has ended turns each series into columns with its verdict. The buckets
//! are kept once, in [`Verdicts`] (which needs them whole), and become [`SeriesView`] columns
//! only at the end. Its counterpart for a stream is [`SseEmitter`](crate::observers::SseEmitter).

use crate::compute::{Cancel, Plan};
use crate::observers::{IntegralNames, Recorded, Sampled, Verdicts};
use crate::views::{ObservablesView, SeriesView};
use nhlab_core::measure::observables::Observables;
use nhlab_core::{Bucket, Gap, Integral, Observer};
use std::collections::BTreeMap;
use std::ops::ControlFlow;
use std::sync::Arc;

/// Collects a run's series for a JSON answer.
#[derive(Debug)]
pub struct JsonCollector {
    /// The integrals of the plan, each of which gets a series (possibly empty).
    integrals: Vec<Integral>,
    /// The buckets and initial values, by integral.
    pub verdicts: Verdicts,
    cancel: Cancel,
    /// The observables and section crossings so far, where asked for.
    recorded: Recorded,
}

impl JsonCollector {
    /// A collector for `integrals` named by `names`, stopping when `cancel` is set.
    pub fn new(integrals: &[Integral], names: IntegralNames, cancel: Cancel) -> Self {
        Self {
            integrals: integrals.to_vec(),
            verdicts: Verdicts::new(names),
            cancel,
            recorded: Recorded::default(),
        }
    }

    /// The same, recording what `plan` asks of each run (observables, a section).
    pub fn recording(mut self, plan: &Plan) -> Self {
        self.recorded = Recorded::of(plan);
        self
    }

    /// The same, sampling `observables` once, at the end of the run (a sweep's rows).
    pub fn sampling_at_end(mut self, observables: Arc<Observables>) -> Self {
        self.recorded.observables = Some(Sampled::new(observables, 1));
        self
    }

    /// The observables' columns, if any were asked for.
    pub fn take_observables(&mut self) -> Option<ObservablesView> {
        self.recorded.observables.take().map(|s| s.view)
    }

    /// The section's columns, if one was asked for.
    pub fn take_section(&mut self) -> Option<ObservablesView> {
        self.recorded.section.take().map(|s| s.view)
    }

    /// The series by integral id, each with its verdict (null for an empty series).
    pub fn into_series(self) -> BTreeMap<String, SeriesView> {
        self.integrals
            .iter()
            .map(|&i| {
                let mut series = SeriesView::with_capacity(self.verdicts.buckets(i).len());
                for &b in self.verdicts.buckets(i) {
                    series.push(b);
                }
                series.verdict = Some(self.verdicts.of(i));
                series.gap = Some(self.verdicts.gap_of(i));
                (self.verdicts.name(i), series)
            })
            .collect()
    }
}

impl Observer for JsonCollector {
    fn initial(&mut self, integral: Integral, value: f64) {
        self.verdicts.initial(integral, value);
    }

    fn points(&mut self, integral: Integral, bucket: Bucket) {
        self.verdicts.push(integral, bucket);
    }

    fn gap(&mut self, integral: Integral, gap: Gap) {
        self.verdicts.gap(integral, gap);
    }

    fn sample(&mut self, t: f64, q: &[f64], v: &[f64]) {
        self.recorded.sample(t, q, v);
    }

    fn state(&mut self, t: f64, q: &[f64], v: &[f64]) {
        self.recorded.state(t, q, v);
    }

    fn progress(&mut self, _steps_done: u64, _t: f64) -> ControlFlow<()> {
        if self.cancel.is_cancelled() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }
}
