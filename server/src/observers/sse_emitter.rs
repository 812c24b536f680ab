//! [`SseEmitter`]: the observer of a run answered as server-sent events (`/simulate` with
//! `Accept: text/event-stream`). It batches new buckets and, a few times a second, sends them
//! as `points` events followed by a `progress` event into the stream's bounded channel
//! (blocking the run when the client reads slowly). It stops the run when the request is
//! cancelled or the channel is closed (the client went away). It also keeps the whole series
//! for their verdicts ([`Verdicts`]), sent with the `run` event. Its counterpart for a JSON
//! answer is [`JsonCollector`](crate::observers::JsonCollector).

use crate::compute::Cancel;
use crate::observers::{Verdicts, sse_event};
use crate::views::{PointsEvent, ProgressEvent, SeriesView, VerdictView};
use axum::response::sse::Event;
use nhlab_core::{Bucket, Integral, Observer};
use std::collections::BTreeMap;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};
use tokio::sync::mpsc::Sender;

/// Streams a run's buckets and progress as server-sent events.
#[derive(Debug)]
pub struct SseEmitter {
    run: usize,
    steps: u64,
    tx: Sender<Event>,
    cancel: Cancel,
    pending: Vec<(Integral, SeriesView)>,
    verdicts: Verdicts,
    last: Instant,
    every: Duration,
}

impl SseEmitter {
    /// An emitter for run `run` of `steps` steps, reporting every `every`.
    pub fn new(run: usize, steps: u64, every: Duration, tx: Sender<Event>, cancel: Cancel) -> Self {
        Self {
            run,
            steps,
            tx,
            cancel,
            pending: Vec::new(),
            verdicts: Verdicts::default(),
            last: Instant::now(),
            every,
        }
    }

    /// The `points` events of the buckets not sent yet (the coordinator sends the last ones
    /// after the run, before its `run` event).
    pub fn take_points(&mut self) -> Vec<Event> {
        let run = self.run;
        self.pending
            .iter_mut()
            .filter(|(_, s)| !s.is_empty())
            .map(|(integral, series)| {
                let series = std::mem::take(series);
                sse_event(
                    "points",
                    &PointsEvent { run, integral: integral.id().to_owned(), series },
                )
            })
            .collect()
    }

    /// The run's last `progress` event, once it has ended after `steps_done` steps at time
    /// `t`: every run sends at least one, however short.
    pub fn final_progress(&self, steps_done: u64, t: f64) -> Event {
        let fraction = (steps_done as f64 / self.steps.max(1) as f64).min(1.0);
        sse_event("progress", &ProgressEvent { run: self.run, t, fraction, steps: steps_done })
    }

    /// The verdict of every series (by integral id), once the run has ended.
    pub fn verdicts(&self) -> BTreeMap<String, VerdictView> {
        self.verdicts.all()
    }

    fn send(&self, ev: Event) -> bool {
        self.tx.blocking_send(ev).is_ok()
    }
}

impl Observer for SseEmitter {
    fn initial(&mut self, integral: Integral, value: f64) {
        self.verdicts.initial(integral, value);
    }

    fn points(&mut self, integral: Integral, bucket: Bucket) {
        self.verdicts.push(integral, bucket);
        match self.pending.iter_mut().find(|(i, _)| *i == integral) {
            Some((_, series)) => series.push(bucket),
            None => {
                let mut series = SeriesView::default();
                series.push(bucket);
                self.pending.push((integral, series));
            }
        }
    }

    fn progress(&mut self, steps_done: u64, t: f64) -> ControlFlow<()> {
        if self.cancel.is_cancelled() {
            return ControlFlow::Break(());
        }
        if self.last.elapsed() < self.every {
            return ControlFlow::Continue(());
        }
        self.last = Instant::now();
        let fraction = steps_done as f64 / self.steps.max(1) as f64;
        let progress =
            sse_event("progress", &ProgressEvent { run: self.run, t, fraction, steps: steps_done });
        let sent = self.take_points().into_iter().chain([progress]).all(|ev| self.send(ev));
        if sent {
            ControlFlow::Continue(())
        } else {
            self.cancel.cancel();
            ControlFlow::Break(())
        }
    }
}
