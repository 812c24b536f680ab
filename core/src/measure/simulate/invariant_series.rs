//! [`InvariantSeries`]: the error series `|I(t) − I(0)|` of a system's invariants asked for,
//! bucketed together, beside a run's other series (class and general runs alike).

use super::problem::{Observer, Problem, RunConfig};
use crate::measure::bucket::Lanes;
use crate::model::custom::Invariants;
use crate::{Integral, MAX_INVARIANTS, StepFailure, Vector};

/// See the module's doc.
pub(super) struct InvariantSeries<'a> {
    invariants: &'a Invariants,
    initial: [f64; MAX_INVARIANTS],
    lanes: Lanes<MAX_INVARIANTS>,
    /// The invariants asked for, by index.
    wanted: Vec<usize>,
}

impl<'a> InvariantSeries<'a> {
    /// The series of the invariants `problem` asks for from `(q₀, q̇₀)`, their initial values
    /// given to `observer`; `None` when it asks for none.
    pub(super) fn new<S, const N: usize, const R: usize>(
        problem: &Problem<'a, S, N, R>,
        q: &Vector<N>,
        v: &Vector<N>,
        cfg: &RunConfig,
        observer: &mut dyn Observer,
    ) -> Option<Self> {
        let invariants = problem.invariants?;
        let wanted: Vec<usize> = problem
            .integrals
            .iter()
            .filter_map(|i| match i {
                Integral::Invariant(k) => Some(*k as usize),
                _ => None,
            })
            .collect();
        if wanted.is_empty() {
            return None;
        }
        let mut initial = [0.0; MAX_INVARIANTS];
        invariants.eval(q.as_slice(), v.as_slice(), &mut initial);
        for &k in &wanted {
            observer.initial(Integral::Invariant(k as u8), initial[k]);
        }
        Some(Self { invariants, initial, lanes: Lanes::new(problem.steps, cfg.points), wanted })
    }

    /// Adds the values at `(q, q̇)`, at time t; a value that is not finite ends the run.
    #[inline]
    pub(super) fn push<const N: usize>(
        &mut self,
        t: f64,
        q: &Vector<N>,
        v: &Vector<N>,
        observer: &mut dyn Observer,
    ) -> Result<(), StepFailure> {
        let mut now = [0.0; MAX_INVARIANTS];
        self.invariants.eval(q.as_slice(), v.as_slice(), &mut now);
        let errors = std::array::from_fn(|k| (now[k] - self.initial[k]).abs());
        if self.wanted.iter().any(|&k| !errors[k].is_finite()) {
            return Err(StepFailure::NonFinite);
        }
        if let Some(b) = self.lanes.push(t, errors) {
            self.send(b, observer);
        }
        Ok(())
    }

    /// Releases the last buckets.
    pub(super) fn finish(&mut self, observer: &mut dyn Observer) {
        if let Some(b) = self.lanes.finish() {
            self.send(b, observer);
        }
    }

    fn send(&self, buckets: [crate::Bucket; MAX_INVARIANTS], observer: &mut dyn Observer) {
        for &k in &self.wanted {
            observer.points(Integral::Invariant(k as u8), buckets[k]);
        }
    }
}
