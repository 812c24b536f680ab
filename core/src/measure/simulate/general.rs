//! The run loop on the general class (`docs/model.md` §4): a method's general step, and after
//! each step the energy `H = ½ q̇ᵀM q̇ + V`, the constraint residual and the invariants asked
//! for, downsampled as in a class run. A state that stops being finite or grows beyond
//! [`DIVERGED`](super::DIVERGED), and a constraint matrix that loses rank ([`Rank`]), end the
//! run.

use super::invariant_series::InvariantSeries;
use super::problem::{
    Observer, Problem, Progress, RunConfig, RunOutcome, Samples, StepSeries, failure_of,
};
use super::rank::Rank;
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::{GeneralStepper, Stepper};
use crate::methods::{Method, Visitor};
use crate::model::mechanical::Mechanical;
use crate::{Integral, RunError, StepFailure};

/// Runs `method`'s general step on `problem`, streaming to `observer`.
pub fn run_general<S: Mechanical<N, R>, M: GeneralStepper, const N: usize, const R: usize>(
    problem: &Problem<'_, S, N, R>,
    method: &M,
    cfg: &RunConfig,
    observer: &mut dyn Observer,
) -> RunOutcome {
    let (sys, h) = (problem.sys, problem.step);
    let mut st = problem.start;
    let mut memory = GeneralMemory::empty();
    let mut a_before = sys.constraint(&st.q);
    let rank = Rank::new(&a_before);
    let values = |st: &crate::State<N, R>, memory: &GeneralMemory<N, R>| {
        let a = memory.constraint(sys, &st.q);
        (sys.mass().kinetic_energy(&st.v) + memory.potential(sys, &st.q), (a * st.v).norm(), a)
    };
    let (h0, _, _) = values(&st, &memory);
    // Lane 0: H, lane 1: the residual (reported as is: its ideal is 0).
    let series: Vec<(Integral, usize)> = problem
        .integrals
        .iter()
        .filter_map(|&i| match i {
            Integral::Energy => Some((i, 0)),
            Integral::Constraint => Some((i, 1)),
            _ => None,
        })
        .collect();
    let mut lanes = StepSeries::new(series, &[h0, 0.0], (problem.steps, cfg.points), observer);
    let mut invariants = InvariantSeries::new(problem, &st.q, &st.v, cfg, observer);
    let mut progress = Progress::new(cfg);
    let mut samples = Samples::new(cfg.samples, problem.steps);
    if samples.due(0) {
        observer.sample(0.0, st.q.as_slice(), st.v.as_slice());
    }
    if cfg.every_step {
        observer.state(0.0, st.q.as_slice(), st.v.as_slice());
    }
    for k in 1..=problem.steps {
        let t0 = (k - 1) as f64 * h;
        let failed = |failure| RunOutcome {
            steps: k - 1,
            error: Some(RunError::Step { step: k, t: t0, failure }),
        };
        if let Err(failure) = method.step_general(sys, &mut st, &mut memory, h) {
            return failed(failure);
        }
        if let Some(failure) = failure_of(&st) {
            return failed(failure);
        }
        let t = k as f64 * h;
        let (energy, residual, a) = values(&st, &memory);
        if !(energy + residual).is_finite() {
            return failed(StepFailure::NonFinite);
        }
        if let Err(failure) = rank.check(&a_before, &a) {
            return failed(failure);
        }
        a_before = a;
        lanes.push(t, [(energy - h0).abs(), residual], observer);
        if let Some(series) = invariants.as_mut()
            && let Err(failure) = series.push(t, &st.q, &st.v, observer)
        {
            return failed(failure);
        }
        if samples.due(k) {
            observer.sample(t, st.q.as_slice(), st.v.as_slice());
        }
        if cfg.every_step {
            observer.state(t, st.q.as_slice(), st.v.as_slice());
        }
        if let Some(cancelled) = progress.tick(k, t, observer) {
            return cancelled;
        }
    }
    lanes.finish(observer);
    if let Some(series) = invariants.as_mut() {
        series.finish(observer);
    }
    observer.finish(st.q.as_slice(), st.v.as_slice());
    RunOutcome { steps: problem.steps, error: None }
}

/// Runs a configured method's general step: one dispatch to its own type, outside the loop.
pub fn run_method_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
    problem: &Problem<'_, S, N, R>,
    method: &Method,
    cfg: &RunConfig,
    observer: &mut dyn Observer,
) -> RunOutcome {
    struct Run<'p, 'o, S, const N: usize, const R: usize> {
        problem: &'p Problem<'p, S, N, R>,
        cfg: &'p RunConfig,
        observer: &'o mut dyn Observer,
    }
    impl<S: Mechanical<N, R>, const N: usize, const R: usize> Visitor for Run<'_, '_, S, N, R> {
        type Output = RunOutcome;
        fn visit<M: Stepper + GeneralStepper>(self, method: &M) -> RunOutcome {
            run_general(self.problem, method, self.cfg, self.observer)
        }
    }
    method.visit(Run { problem, cfg, observer })
}
