//! The driver: runs one method on one problem and streams the downsampled error series to
//! an [`Observer`], without storing the trajectory (memory is O(points), whatever the
//! number of steps). This is the loop of the paper's class (its integrals E, h and the
//! latitude, whole turns of an angle ζ taken off); [`general`]'s is the general class's.
//!
//! Problem / algorithm / solve, as in OrdinaryDiffEq: a [`Problem`] holds the system, the
//! start and what to measure, the method is a small config struct, [`run`] owns the loop.
//! Only the integrals asked for are evaluated. A step that fails or produces a non-finite
//! number ends the run with a [`RunError`] naming the step and time; the buckets completed
//! by then have already been handed over.

mod general;
mod invariant_series;
mod problem;
mod rank;

pub use general::{run_general, run_method_general};
pub use problem::{Collect, DIVERGED, Observer, Problem, RunConfig, RunOutcome};

use self::invariant_series::InvariantSeries;
use self::problem::{Progress, Samples, StepSeries, failure_of};
use self::rank::Rank;
use crate::measure::latitude::LatitudeTracker;
use crate::methods::integrator::{GeneralStepper, Stepper};
use crate::methods::memory::{Memory, Recall, driver_potential_and_constraint};
use crate::methods::{Method, Visitor};
use crate::model::system::System;
use crate::{Bucketer, Gap, GapReason, Integral, RunError, State, StepFailure};

/// The values of the step integrals at one state. The two energies are evaluated once and
/// H = E + h derived, so asking for all three costs one potential evaluation, not three.
#[inline]
fn values<S: System<N, R>, M: Recall<N, R>, const N: usize, const R: usize>(
    sys: &S,
    st: &State<N, R>,
    memory: &M,
    energies: bool,
    constraint: bool,
) -> [f64; 4] {
    if !energies && !constraint {
        return [0.0; 4];
    }
    // V_d(ζ) and A(ζ) together (one sin/cos), or as the step remembered them.
    let (v_d, a) = driver_potential_and_constraint(memory, sys, st);
    let zeta_dot = st.v[N - 1];
    let (e, h) = (sys.passenger_energy(&st.q, &st.v), 0.5 * zeta_dot * zeta_dot + v_d);
    let c = if constraint { (a * st.v).norm() } else { 0.0 };
    [e + h, e, h, c]
}

/// The lane of a step integral (the latitude and the invariants have their own).
#[inline]
fn index_of(integral: Integral) -> usize {
    match integral {
        Integral::Energy => 0,
        Integral::PassengerEnergy => 1,
        Integral::DriverEnergy => 2,
        Integral::Constraint | Integral::Latitude | Integral::Invariant(_) => 3,
    }
}

/// Runs a configured method on a class system: one dispatch to its own type, outside the loop.
pub fn run_method<S: System<N, R>, const N: usize, const R: usize>(
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
    impl<S: System<N, R>, const N: usize, const R: usize> Visitor for Run<'_, '_, S, N, R> {
        type Output = RunOutcome;
        fn visit<M: Stepper + GeneralStepper>(self, method: &M) -> RunOutcome {
            run(self.problem, method, self.cfg, self.observer)
        }
    }
    method.visit(Run { problem, cfg, observer })
}

/// The latitude's last value and whether the crossings since had none ([`Gap`]).
#[derive(Debug, Clone, Copy, Default)]
struct Trail {
    last: f64,
    undefined: bool,
}

impl Trail {
    /// Notes a crossing's value; whether it is defined. Near rest `a·u/|u|` is 0/0 or
    /// overflows, so any value that is not finite is undefined and left out (a run that
    /// diverges fails on its energies, checked at every step, not here).
    #[inline]
    fn defined(&mut self, t: f64, value: f64) -> bool {
        self.undefined = !value.is_finite();
        if !self.undefined {
            self.last = t;
        }
        !self.undefined
    }

    /// The gap at the end of a run to `t_end`, if the series has one: the last crossings'
    /// values undefined, or no crossing in the last two driver periods.
    fn gap(&self, t_end: f64, period: f64) -> Option<Gap> {
        let reason = if self.undefined {
            GapReason::PassengerAtRest
        } else if t_end - self.last > 2.0 * period {
            GapReason::NoCrossing
        } else {
            return None;
        };
        Some(Gap { since: self.last, reason })
    }
}

/// Runs `method` on `problem`, streaming to `observer`.
pub fn run<S: System<N, R>, M: Stepper, const N: usize, const R: usize>(
    problem: &Problem<'_, S, N, R>,
    method: &M,
    cfg: &RunConfig,
    observer: &mut dyn Observer,
) -> RunOutcome {
    let (sys, h) = (problem.sys, problem.step);
    let mut st = problem.start;
    let mut memory = M::Memory::<N, R>::empty();
    // Where ζ is an angle the state keeps it within a turn, and counts the turns taken off
    // here, for what needs ζ as the run started it (the latitude's sections, the final state).
    let take_turns = |st: &mut State<N, R>, memory: &mut M::Memory<N, R>| {
        if sys.zeta_is_angle() { st.take_whole_turns(memory) } else { 0.0 }
    };
    let mut turns = take_turns(&mut st, &mut memory);
    let energies = problem.integrals.iter().any(|&i| index_of(i) < 3);
    let constraint = problem.integrals.contains(&Integral::Constraint);
    let v0 = values(sys, &st, &memory, energies, constraint);
    // Where A's rank may be lost (a system given as formulas), it is watched step by step;
    // the built-ins' A has full rank everywhere (`System::rank_is_constant`).
    let mut rank = (!sys.rank_is_constant()).then(|| {
        let a = sys.constraint(st.q[N - 1]);
        (Rank::new(&a), a)
    });
    // The four step integrals share every sample time: one set of lanes buckets them all
    // (lanes not asked for carry zeros), and the series asked for read their lane.
    let mut initial = v0;
    // The constraint residual is reported as is: its ideal value is 0, not its start.
    initial[index_of(Integral::Constraint)] = 0.0;
    let series: Vec<(Integral, usize)> = problem
        .integrals
        .iter()
        .filter(|&&i| i != Integral::Latitude && !matches!(i, Integral::Invariant(_)))
        .map(|&i| (i, index_of(i)))
        .collect();
    let mut lanes = StepSeries::new(series, &initial, (problem.steps, cfg.points), observer);
    let mut latitude =
        problem.latitude.filter(|_| problem.integrals.contains(&Integral::Latitude)).map(|axis| {
            observer.initial(Integral::Latitude, axis.latitude0);
            let planned = axis.crossings_until(problem.steps as f64 * h);
            let tracker = LatitudeTracker::new(axis, &problem.start.q, &problem.start.v);
            (tracker, Bucketer::new(planned, cfg.points), Trail::default())
        });
    let mut invariants =
        InvariantSeries::new(problem, &problem.start.q, &problem.start.v, cfg, observer);
    let mut progress = Progress::new(cfg);
    let mut samples = Samples::new(cfg.samples, problem.steps);
    if samples.due(0) {
        observer.sample(0.0, problem.start.q.as_slice(), problem.start.v.as_slice());
    }
    if cfg.every_step {
        observer.state(0.0, problem.start.q.as_slice(), problem.start.v.as_slice());
    }
    for k in 1..=problem.steps {
        let t0 = (k - 1) as f64 * h;
        let failed = |failure| RunOutcome {
            steps: k - 1,
            error: Some(RunError::Step { step: k, t: t0, failure }),
        };
        if let Err(failure) = method.step(sys, &mut st, &mut memory, h) {
            return failed(failure);
        }
        if let Some(failure) = failure_of(&st) {
            return failed(failure);
        }
        turns += take_turns(&mut st, &mut memory);
        let t = k as f64 * h;
        let now = values(sys, &st, &memory, energies, constraint);
        if let Some((rank, a_before)) = rank.as_mut() {
            let a = driver_potential_and_constraint(&memory, sys, &st).1;
            if let Err(failure) = rank.check(a_before, &a) {
                return failed(failure);
            }
            *a_before = a;
        }
        // A potential can overflow where the state does not (a quartic U at |x| ~ 1e77).
        if !(now[0] + now[3]).is_finite() {
            return failed(StepFailure::NonFinite);
        }
        lanes.push(t, std::array::from_fn(|i| (now[i] - initial[i]).abs()), observer);
        if let Some(series) = invariants.as_mut()
            && let Err(failure) = series.push(t, &st.q_with_turns(turns), &st.v, observer)
        {
            return failed(failure);
        }
        if let Some((tracker, buckets, trail)) = latitude.as_mut()
            && let Some((tc, e)) = tracker.observe(sys, t, &st.q_with_turns(turns), &st.v)
            && trail.defined(tc, e)
            && let Some(b) = buckets.push(tc, e)
        {
            observer.points(Integral::Latitude, b);
        }
        if samples.due(k) {
            observer.sample(t, st.q_with_turns(turns).as_slice(), st.v.as_slice());
        }
        if cfg.every_step {
            observer.state(t, st.q_with_turns(turns).as_slice(), st.v.as_slice());
        }
        if let Some(cancelled) = progress.tick(k, t, observer) {
            return cancelled;
        }
    }
    lanes.finish(observer);
    if let Some(series) = invariants.as_mut() {
        series.finish(observer);
    }
    if let Some((tracker, buckets, trail)) = latitude.as_mut() {
        if let Some(b) = buckets.finish() {
            observer.points(Integral::Latitude, b);
        }
        let period = tracker.period();
        if let Some(gap) = trail.gap(problem.steps as f64 * h, period) {
            observer.gap(Integral::Latitude, gap);
        }
    }
    observer.finish(st.q_with_turns(turns).as_slice(), st.v.as_slice());
    RunOutcome { steps: problem.steps, error: None }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trail_reports_a_gap_only_where_values_stop_before_the_end() {
        let period = 10.0;
        let mut trail = Trail::default();
        assert!(trail.defined(10.0, 0.1) && trail.defined(20.0, 0.2));
        // Crossings up to the last period: no gap.
        assert_eq!(trail.gap(35.0, period), None);
        // None in the last two periods and more: the driver stopped returning.
        let gap = trail.gap(45.0, period);
        assert_eq!(gap, Some(Gap { since: 20.0, reason: GapReason::NoCrossing }));
        // Undefined values at the last crossings: left out, and the passenger is at rest.
        assert!(!trail.defined(30.0, f64::NAN));
        let gap = trail.gap(35.0, period);
        assert_eq!(gap, Some(Gap { since: 20.0, reason: GapReason::PassengerAtRest }));
        // A value again: the gap closes.
        assert!(trail.defined(40.0, 0.3));
        assert_eq!(trail.gap(45.0, period), None);
        // No crossing at all in a long run: a gap since 0.
        let gap = Trail::default().gap(100.0, period);
        assert_eq!(gap, Some(Gap { since: 0.0, reason: GapReason::NoCrossing }));
    }
}
