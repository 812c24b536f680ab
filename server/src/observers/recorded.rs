//! What a run records of its own states for the answer: [`Sampled`], its observables at
//! the sampled times, and [`Crossings`], its crossings of a Poincaré section; both as
//! columns ([`ObservablesView`]). [`Recorded`] holds what a plan asks for of both; the JSON
//! collector and the stream's emitter each hold one.

use crate::compute::{Plan, SectionPlan};
use crate::views::ObservablesView;
use nhlab_core::measure::observables::{Observables, Scratch};
use nhlab_core::measure::section::SectionTracker;
use std::sync::Arc;

/// What a run records of its states, as its plan asks: the observables sampled, the section's
/// crossings (none of either where the plan asks for none).
#[derive(Debug, Default)]
pub struct Recorded {
    /// The observables sampled so far.
    pub observables: Option<Sampled>,
    /// The section's crossings so far.
    pub section: Option<Crossings>,
}

impl Recorded {
    /// What `plan` asks each run to record.
    pub fn of(plan: &Plan) -> Self {
        let dof = plan.prepared.scene.system.dof();
        Self {
            observables: plan.observables.as_ref().map(|o| Sampled::new(o.clone(), plan.points)),
            section: plan.section.as_ref().map(|s| Crossings::new(s.clone(), dof)),
        }
    }

    /// A sampled state ([`Observer::sample`](nhlab_core::Observer::sample)).
    #[inline]
    pub fn sample(&mut self, t: f64, q: &[f64], v: &[f64]) {
        if let Some(sampled) = &mut self.observables {
            sampled.push(t, q, v);
        }
    }

    /// A step's end state ([`Observer::state`](nhlab_core::Observer::state)).
    #[inline]
    pub fn state(&mut self, t: f64, q: &[f64], v: &[f64]) {
        if let Some(crossings) = &mut self.section {
            crossings.observe(t, q, v);
        }
    }
}

/// Observables being sampled: what computes them, its scratch, the columns and a row.
#[derive(Debug)]
pub struct Sampled {
    observables: Arc<Observables>,
    scratch: Scratch,
    row: Vec<f64>,
    /// The columns so far.
    pub view: ObservablesView,
}

impl Sampled {
    /// Columns for `observables`, room for `points` samples.
    pub fn new(observables: Arc<Observables>, points: usize) -> Self {
        let view = ObservablesView::new(observables.names(), points);
        let (scratch, row) = (observables.scratch(), vec![0.0; observables.names().len()]);
        Self { observables, scratch, row, view }
    }

    /// Computes and adds the sample of state (q, v) at t.
    pub fn push(&mut self, t: f64, q: &[f64], v: &[f64]) {
        self.observables.eval(t, q, v, &mut self.scratch, &mut self.row);
        self.view.push(t, &self.row);
    }
}

/// A section's crossings: the tracker, the columns (the crossing times and the plotted
/// quantities), and how many more may be kept.
#[derive(Debug)]
pub struct Crossings {
    plan: Arc<SectionPlan>,
    tracker: SectionTracker,
    row: Vec<f64>,
    left: usize,
    /// The columns so far.
    pub view: ObservablesView,
}

impl Crossings {
    /// Columns for `plan`'s crossings of a run on `dof` coordinates.
    pub fn new(plan: Arc<SectionPlan>, dof: usize) -> Self {
        let names = plan.section.plot.names();
        let view = ObservablesView::new(names, 0);
        let (tracker, row) = (SectionTracker::new(&plan.section, dof), vec![0.0; names.len()]);
        let left = plan.max_crossings;
        Self { plan, tracker, row, left, view }
    }

    /// Looks at a step's end state; keeps a crossing inside the step, while there is room.
    #[inline]
    pub fn observe(&mut self, t: f64, q: &[f64], v: &[f64]) {
        if self.left == 0 {
            return;
        }
        if let Some(tc) = self.tracker.observe(&self.plan.section, t, q, v, &mut self.row) {
            self.view.push(tc, &self.row);
            self.left -= 1;
        }
    }
}
