//! What a run is and how it reports, shared by the class's run loop and the general one:
//! the [`Problem`] (system, start, step, what to measure), the [`Observer`] that receives
//! the series, the [`RunConfig`] and the [`RunOutcome`]; and the test that ends a run whose
//! state has diverged ([`failure_of`]).

use crate::measure::bucket::Lanes;
use crate::measure::latitude::LatitudeAxis;
use crate::measure::pace::Pace;
use crate::model::custom::Invariants;
use crate::{Bucket, Gap, Integral, RunError, State, StepFailure};
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

/// Watches a run (argmin-style observer): receives completed buckets and progress, and may
/// stop the run.
pub trait Observer {
    /// The initial value `I(0)` of a series, before any bucket (the verdict's scale).
    fn initial(&mut self, _integral: Integral, _value: f64) {}
    /// A completed bucket of one integral's error series.
    fn points(&mut self, integral: Integral, bucket: Bucket);
    /// A series that has no values from some time on, in a run that reached t_end (called
    /// once per such series, before [`Observer::finish`]).
    fn gap(&mut self, _integral: Integral, _gap: Gap) {}
    /// The final state of a run that reached t_end (work–precision measures it).
    fn finish(&mut self, _q: &[f64], _v: &[f64]) {}
    /// The state at time t, at each of the [`RunConfig::samples`] times the run samples
    /// ([`Samples`]; t = 0 first): what observables are computed from.
    fn sample(&mut self, _t: f64, _q: &[f64], _v: &[f64]) {}
    /// The state at the start and at the end of every step, when the run is asked for them
    /// ([`RunConfig::every_step`]: a Poincaré section looks at each).
    fn state(&mut self, _t: f64, _q: &[f64], _v: &[f64]) {}
    /// Called every [`RunConfig::progress_every`] steps, or about every
    /// [`AIM`](crate::measure::pace::AIM) of a [`paced`](RunConfig::paced) run; `Break`
    /// cancels the run.
    fn progress(&mut self, _steps_done: u64, _t: f64) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// An observer that collects every series in memory (tests, JSON responses).
#[derive(Debug, Clone, Default)]
pub struct Collect {
    /// Buckets per integral, in arrival order.
    pub series: std::collections::BTreeMap<Integral, Vec<Bucket>>,
    /// `I(0)` per integral.
    pub initial: std::collections::BTreeMap<Integral, f64>,
    /// Series' gaps, by integral.
    pub gaps: std::collections::BTreeMap<Integral, Gap>,
}

impl Observer for Collect {
    fn initial(&mut self, integral: Integral, value: f64) {
        self.initial.insert(integral, value);
    }
    fn points(&mut self, integral: Integral, bucket: Bucket) {
        self.series.entry(integral).or_default().push(bucket);
    }
    fn gap(&mut self, integral: Integral, gap: Gap) {
        self.gaps.insert(integral, gap);
    }
}

/// How a run reports, and how long it may take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunConfig {
    /// Buckets per series.
    pub points: usize,
    /// Steps between progress calls; at most, for a [`paced`](Self::paced) run.
    pub progress_every: u64,
    /// Progress calls paced by the clock too ([`Pace`]): every `progress_every` steps, or
    /// more often where that would take longer than about
    /// [`AIM`](crate::measure::pace::AIM) (a step of a system given as formulas may cost a
    /// millisecond). What a caller that must stop promptly asks for.
    pub paced: bool,
    /// The longest the run may take, wall clock: past it the run ends with
    /// [`RunError::TimeLimit`] (looked at with the progress calls).
    pub time_limit: Option<Duration>,
    /// States handed to [`Observer::sample`], at times spread evenly over the run from 0 to
    /// t_end ([`Samples`]); none when 0.
    pub samples: usize,
    /// Whether every step's state goes to [`Observer::state`].
    pub every_step: bool,
}

impl Default for RunConfig {
    fn default() -> Self {
        Self {
            points: 1000,
            progress_every: 4096,
            paced: false,
            time_limit: None,
            samples: 0,
            every_step: false,
        }
    }
}

/// When a run samples its state: at the `count` times t_j = j·t_end/(count − 1), the state
/// at the step k_j = round(j·steps/(count − 1)) that ends nearest each, every step once (a
/// run of fewer steps than `count` samples each step); one sample is the final state. The
/// loop compares the step with the next k_j, no division per step.
#[derive(Debug, Clone)]
pub(crate) struct Samples {
    count: u64,
    steps: u64,
    /// The next sample's index j, and its step k_j (`u64::MAX` when done).
    j: u64,
    next: u64,
}

impl Samples {
    pub(crate) fn new(count: usize, steps: u64) -> Self {
        let mut s = Self { count: count as u64, steps, j: 0, next: u64::MAX };
        if count == 1 {
            (s.j, s.next) = (0, steps);
        } else if count > 1 {
            s.next = 0;
        }
        s
    }

    /// The step of sample j.
    fn step_of(&self, j: u64) -> u64 {
        if self.count <= 1 {
            return self.steps;
        }
        (j as f64 * self.steps as f64 / (self.count - 1) as f64).round() as u64
    }

    /// Whether step k (0: the start) is sampled; moves on to the next sample.
    #[inline]
    pub(crate) fn due(&mut self, k: u64) -> bool {
        if k != self.next {
            return false;
        }
        self.advance(k);
        true
    }

    #[inline(never)]
    fn advance(&mut self, k: u64) {
        loop {
            self.j += 1;
            if self.j >= self.count.max(1) {
                self.next = u64::MAX;
                return;
            }
            let next = self.step_of(self.j);
            if next > k {
                self.next = next;
                return;
            }
        }
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutcome {
    /// Steps completed.
    pub steps: u64,
    /// Why it ended early, if it did.
    pub error: Option<RunError>,
}

/// What to integrate and what to measure.
#[derive(Debug, Clone)]
pub struct Problem<'a, S, const N: usize, const R: usize> {
    /// The system.
    pub sys: &'a S,
    /// Initial state (with the continuous multiplier).
    pub start: State<N, R>,
    /// Step size h.
    pub step: f64,
    /// Number of steps.
    pub steps: u64,
    /// Integrals whose error series are wanted.
    pub integrals: &'a [Integral],
    /// The monodromy axis, when the latitude is wanted.
    pub latitude: Option<LatitudeAxis>,
    /// The system's invariants, when any is wanted.
    pub invariants: Option<&'a Invariants>,
}

/// A state beyond this size has lost every digit that matters: the run has diverged.
pub const DIVERGED: f64 = 1e100;

/// Why a state ends its run, if it does: not finite, or beyond [`DIVERGED`]. One test
/// catches NaN, infinity and blow-up.
#[inline]
pub(crate) fn failure_of<const N: usize, const R: usize>(st: &State<N, R>) -> Option<StepFailure> {
    let size = st.q.norm_squared() + st.v.norm_squared() + st.lambda.norm_squared();
    if size.is_nan() || size > DIVERGED * DIVERGED {
        return Some(if size.is_nan() || !st.is_finite() {
            StepFailure::NonFinite
        } else {
            StepFailure::Diverged { limit: DIVERGED }
        });
    }
    None
}

/// The step integrals a run reports, sampled together: `K` lanes bucketed on one schedule, and
/// the series asked for, each reading its lane.
pub(crate) struct StepSeries<const K: usize> {
    lanes: Lanes<K>,
    series: Vec<(Integral, usize)>,
}

impl<const K: usize> StepSeries<K> {
    /// `series` (integral, lane) over `steps` samples in `points` buckets; each series' initial
    /// value (its lane's in `initial`) goes to `observer`.
    pub(crate) fn new(
        series: Vec<(Integral, usize)>,
        initial: &[f64; K],
        (steps, points): (u64, usize),
        observer: &mut dyn Observer,
    ) -> Self {
        for &(integral, lane) in &series {
            observer.initial(integral, initial[lane]);
        }
        Self { lanes: Lanes::new(steps, points), series }
    }

    /// Adds one sample of every lane at time t; a completed bucket goes to `observer`.
    #[inline]
    pub(crate) fn push(&mut self, t: f64, errors: [f64; K], observer: &mut dyn Observer) {
        if let Some(b) = self.lanes.push(t, errors) {
            self.send(b, observer);
        }
    }

    /// Releases the last buckets.
    pub(crate) fn finish(&mut self, observer: &mut dyn Observer) {
        if let Some(b) = self.lanes.finish() {
            self.send(b, observer);
        }
    }

    fn send(&self, buckets: [Bucket; K], observer: &mut dyn Observer) {
        for &(integral, lane) in &self.series {
            observer.points(integral, buckets[lane]);
        }
    }
}

/// The countdown to a run's next call of [`Observer::progress`] (no division per step, no
/// clock read between two calls), and its time limit.
pub(crate) struct Progress {
    every: u64,
    next: u64,
    /// The pace of a paced run.
    pace: Option<Pace>,
    /// When the run started, and its time limit.
    limit: Option<(Instant, Duration)>,
}

impl Progress {
    pub(crate) fn new(cfg: &RunConfig) -> Self {
        let every = cfg.progress_every.max(1);
        let pace = cfg.paced.then(|| Pace::new(every));
        let next = pace.map_or(every, |p| p.every());
        Self { every, next, pace, limit: cfg.time_limit.map(|limit| (Instant::now(), limit)) }
    }

    /// After step k, at time t: the run's outcome if it is past its time limit or the
    /// observer asks it to stop.
    #[inline]
    pub(crate) fn tick(
        &mut self,
        k: u64,
        t: f64,
        observer: &mut dyn Observer,
    ) -> Option<RunOutcome> {
        if k != self.next {
            return None;
        }
        self.call(k, t, observer)
    }

    /// The progress call itself, out of line: the loop keeps only the compare above.
    #[inline(never)]
    fn call(&mut self, k: u64, t: f64, observer: &mut dyn Observer) -> Option<RunOutcome> {
        let now = match &mut self.pace {
            Some(pace) => {
                let now = pace.look();
                self.next += pace.every();
                Some(now)
            }
            None => {
                self.next += self.every;
                self.limit.map(|_| Instant::now())
            }
        };
        if let (Some(now), Some((start, limit))) = (now, self.limit)
            && now.saturating_duration_since(start) > limit
        {
            let limit = limit.as_secs_f64();
            return Some(RunOutcome {
                steps: k,
                error: Some(RunError::TimeLimit { step: k, t, limit }),
            });
        }
        observer
            .progress(k, t)
            .is_break()
            .then_some(RunOutcome { steps: k, error: Some(RunError::Cancelled { step: k, t }) })
    }
}

#[cfg(test)]
mod tests {
    use super::Samples;

    fn steps_sampled(count: usize, steps: u64) -> Vec<u64> {
        let mut s = Samples::new(count, steps);
        (0..=steps).filter(|&k| s.due(k)).collect()
    }

    #[test]
    fn samples_are_the_steps_nearest_evenly_spread_times() {
        assert_eq!(steps_sampled(5, 100), [0, 25, 50, 75, 100]);
        assert_eq!(steps_sampled(4, 10), [0, 3, 7, 10]);
        assert_eq!(steps_sampled(2, 7), [0, 7]);
        // More samples than steps: every step once.
        assert_eq!(steps_sampled(50, 3), [0, 1, 2, 3]);
        // One: the final state; none: nothing.
        assert_eq!(steps_sampled(1, 9), [9]);
        assert!(steps_sampled(0, 9).is_empty());
    }
}
