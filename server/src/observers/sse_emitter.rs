//! [`SseEmitter`]: the observer of a run answered as server-sent events (`/simulate` with
//! `Accept: text/event-stream`). It batches new buckets and, a few times a second, sends them
//! as `points` events followed by a `progress` event into the stream's bounded channel
//! (holding the run while the client reads slowly, but not past a cancellation). It stops the run when the request is
//! cancelled or the channel is closed (the client went away). It also keeps the whole series
//! for their verdicts ([`Verdicts`]), sent with the `run` event. Its counterpart for a JSON
//! answer is [`JsonCollector`](crate::observers::JsonCollector).

use crate::compute::{Cancel, Plan};
use crate::observers::{IntegralNames, Recorded, Verdicts, sse_event};
use crate::views::{
    GapView, ObservablesEvent, PointsEvent, ProgressEvent, SectionEvent, SeriesView, VerdictView,
};
use axum::response::sse::Event;
use nhlab_core::{Bucket, Gap, Integral, Observer};
use std::collections::BTreeMap;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};
use tokio::sync::mpsc::Sender;
use tokio::sync::mpsc::error::TrySendError;

/// How long a run waits before trying again to send into a full channel.
const FULL_WAIT: Duration = Duration::from_millis(2);

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
    /// Steps done and time reached at the last look at the run.
    reached: (u64, f64),
    /// The observables and section crossings not sent yet, where asked for.
    recorded: Recorded,
}

impl SseEmitter {
    /// An emitter for run `run` of `steps` steps, its series named by `names`, reporting
    /// every `every`.
    pub fn new(
        (run, steps): (usize, u64),
        names: IntegralNames,
        every: Duration,
        tx: Sender<Event>,
        cancel: Cancel,
    ) -> Self {
        Self {
            run,
            steps,
            tx,
            cancel,
            pending: Vec::new(),
            verdicts: Verdicts::new(names),
            last: Instant::now(),
            every,
            reached: (0, 0.0),
            recorded: Recorded::default(),
        }
    }

    /// The same, recording what `plan` asks of each run (sent as `observables` and `section`
    /// events with the points).
    pub fn recording(mut self, plan: &Plan) -> Self {
        self.recorded = Recorded::of(plan);
        self
    }

    /// The `points` events of the buckets not sent yet (the coordinator sends the last ones
    /// after the run, before its `run` event).
    pub fn take_points(&mut self) -> Vec<Event> {
        let run = self.run;
        let verdicts = &self.verdicts;
        let mut events: Vec<Event> = self
            .pending
            .iter_mut()
            .filter(|(_, s)| !s.is_empty())
            .map(|(integral, series)| {
                let series = std::mem::take(series);
                let integral = verdicts.name(*integral);
                sse_event("points", &PointsEvent { run, integral, series })
            })
            .collect();
        if let Some(sampled) = &mut self.recorded.observables
            && !sampled.view.t.is_empty()
        {
            let observables = sampled.view.take();
            events.push(sse_event("observables", &ObservablesEvent { run, observables }));
        }
        if let Some(crossings) = &mut self.recorded.section
            && !crossings.view.t.is_empty()
        {
            let section = crossings.view.take();
            events.push(sse_event("section", &SectionEvent { run, section }));
        }
        events
    }

    /// The run's last `progress` event, once it has ended after `steps_done` steps at time
    /// `t` (`None`: where the run was last seen, for a run that panicked): every run sends
    /// at least one, however short.
    pub fn final_progress(&self, ended: Option<(u64, f64)>) -> Event {
        let (steps_done, t) = ended.unwrap_or(self.reached);
        let fraction = (steps_done as f64 / self.steps.max(1) as f64).min(1.0);
        sse_event("progress", &ProgressEvent { run: self.run, t, fraction, steps: steps_done })
    }

    /// The verdict of every series (by integral id), once the run has ended.
    pub fn verdicts(&self) -> BTreeMap<String, VerdictView> {
        self.verdicts.all()
    }

    /// The gap of every series that has one (by integral id), once the run has ended.
    pub fn gaps(&self) -> BTreeMap<String, GapView> {
        self.verdicts.gaps()
    }

    /// Sends an event, waiting while the channel is full (the client reads slowly), but not
    /// past a cancellation (the server shutting down, the client gone): false then.
    fn send(&self, mut ev: Event) -> bool {
        loop {
            match self.tx.try_send(ev) {
                Ok(()) => return true,
                Err(TrySendError::Closed(_)) => return false,
                Err(TrySendError::Full(back)) => {
                    if self.cancel.is_cancelled() {
                        return false;
                    }
                    ev = back;
                    std::thread::sleep(FULL_WAIT);
                }
            }
        }
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

    fn gap(&mut self, integral: Integral, gap: Gap) {
        self.verdicts.gap(integral, gap);
    }

    fn sample(&mut self, t: f64, q: &[f64], v: &[f64]) {
        self.recorded.sample(t, q, v);
    }

    fn state(&mut self, t: f64, q: &[f64], v: &[f64]) {
        self.recorded.state(t, q, v);
    }

    fn progress(&mut self, steps_done: u64, t: f64) -> ControlFlow<()> {
        self.reached = (steps_done, t);
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
