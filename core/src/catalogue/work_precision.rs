//! Work–precision measurements (after DiffEqDevTools' WorkPrecisionSet): for each method and step,
//! what a run costs (the minimum wall time of a few repetitions, so a short run is not timed by
//! noise) and what it buys — the final error in (q, q̇) against the Dop853 reference at t_end, and
//! the largest error of each integral. A caller that must be able to stop (a server whose client
//! went away) passes a `stop` flag to [`reference_until`] and [`measure_until`], looked at
//! about every [`AIM`](crate::measure::pace::AIM) of a solve or a run (paced by the clock,
//! whatever a step costs) and between repetitions.

use crate::catalogue::registry::ReferenceState;
use crate::measure::reference::{ReferenceError, TOL};
use crate::{Bucket, Integral, Method, Observer, PreparedScene, RunConfig, RunError, RunOutcome};
use std::collections::BTreeMap;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};

/// One method at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The method.
    pub method: Method,
    /// Step size.
    pub step: f64,
    /// Steps taken.
    pub steps: u64,
    /// Minimum wall time over the repetitions, in milliseconds.
    pub elapsed_ms: f64,
    /// `‖(q, q̇)(t_end) − reference‖∞`, `None` when the run failed.
    pub final_error: Option<f64>,
    /// Largest `|I − I(0)|` of each integral.
    pub max_error: BTreeMap<Integral, f64>,
    /// Why the run failed, if it did.
    pub error: Option<String>,
    /// The state (q, q̇) at t_end, in the user's order; `None` when the run failed.
    pub end: Option<(Vec<f64>, Vec<f64>)>,
}

/// The reference and its cost.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceSummary {
    /// The solution at t_end.
    pub state: ReferenceState,
    /// Its wall time, in milliseconds.
    pub elapsed_ms: f64,
    /// Whether it is the system's exact solution (`SystemInfo::exact`) rather than a
    /// numerical one.
    pub exact: bool,
}

struct Watch<'a> {
    max: BTreeMap<Integral, f64>,
    end: Option<(Vec<f64>, Vec<f64>)>,
    stop: &'a dyn Fn() -> bool,
}

impl Observer for Watch<'_> {
    fn points(&mut self, integral: Integral, bucket: Bucket) {
        let m = self.max.entry(integral).or_insert(0.0);
        *m = m.max(bucket.max);
    }
    fn finish(&mut self, q: &[f64], v: &[f64]) {
        self.end = Some((q.to_vec(), v.to_vec()));
    }
    fn progress(&mut self, _steps_done: u64, _t: f64) -> ControlFlow<()> {
        if (self.stop)() { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }
}

/// Solves the reference for `scene` (its t_end) once: its exact solution where the system has
/// one.
pub fn reference(scene: &PreparedScene) -> Result<ReferenceSummary, ReferenceError> {
    reference_until(scene, &|| false)
}

/// [`reference`], ended with [`ReferenceError::Cancelled`] when `stop()` turns true (looked
/// at about every [`AIM`](crate::measure::pace::AIM)).
pub fn reference_until(
    scene: &PreparedScene,
    stop: &dyn Fn() -> bool,
) -> Result<ReferenceSummary, ReferenceError> {
    let t = Instant::now();
    if let Some((q, v)) = scene.scene.exact() {
        let state = ReferenceState { q, v, constraint_residual: 0.0, evaluations: 0, steps: 0 };
        return Ok(ReferenceSummary { state, elapsed_ms: 0.0, exact: true });
    }
    let state = scene.scene.reference_until(TOL, stop)?;
    Ok(ReferenceSummary { state, elapsed_ms: t.elapsed().as_secs_f64() * 1e3, exact: false })
}

/// Runs `method` on `scene` with a step near `step`, `reps` times (at least once), and
/// measures it against `reference`. The step is rounded to `t_end / n` so that the run ends
/// exactly at the reference's t_end; the row reports the step used.
pub fn measure(
    scene: &PreparedScene,
    reference: &ReferenceState,
    method: &Method,
    step: f64,
    reps: u32,
) -> Row {
    measure_until(scene, reference, method, step, reps, &|| false)
}

/// [`measure`], stopped when `stop()` turns true: the run in progress ends as cancelled
/// (the row reports it failed, without a final error) and no further repetition starts.
pub fn measure_until(
    scene: &PreparedScene,
    reference: &ReferenceState,
    method: &Method,
    step: f64,
    reps: u32,
    stop: &dyn Fn() -> bool,
) -> Row {
    measure_within(scene, reference, method, step, reps, stop, None)
}

/// [`measure_until`], each run ending as failed ([`RunError::TimeLimit`]) past
/// `time_limit`; a repetition that failed so is the last.
pub fn measure_within(
    scene: &PreparedScene,
    reference: &ReferenceState,
    method: &Method,
    step: f64,
    reps: u32,
    stop: &dyn Fn() -> bool,
    time_limit: Option<Duration>,
) -> Row {
    let mut scene = scene.clone();
    let t_end = scene.scene.t_end;
    let step = t_end / (t_end / step).round().max(1.0);
    scene.scene.step = step;
    // Paced: the stop flag is looked at every few milliseconds at most, whatever a step
    // costs.
    let cfg = RunConfig { points: 1, paced: true, time_limit, ..RunConfig::default() };
    let mut best = f64::INFINITY;
    let mut row: Option<(RunOutcome, Watch<'_>)> = None;
    for rep in 0..reps.max(1) {
        let timed_out = row
            .as_ref()
            .is_some_and(|(out, _)| matches!(out.error, Some(RunError::TimeLimit { .. })));
        if rep > 0 && (timed_out || stop()) {
            break;
        }
        let mut watch = Watch { max: BTreeMap::new(), end: None, stop };
        let t = Instant::now();
        let out = scene.run(method, &cfg, &mut watch);
        best = best.min(t.elapsed().as_secs_f64() * 1e3);
        row.get_or_insert((out, watch));
    }
    let (out, watch) = row.expect("the first repetition always runs");
    let final_error = watch.end.as_ref().map(|(q, v)| {
        let dq = q.iter().zip(&reference.q).map(|(a, b)| (a - b).abs());
        let dv = v.iter().zip(&reference.v).map(|(a, b)| (a - b).abs());
        dq.chain(dv).fold(0.0, f64::max)
    });
    Row {
        method: *method,
        step,
        steps: out.steps,
        elapsed_ms: best,
        final_error,
        max_error: watch.max,
        error: out.error.map(|e| e.to_string()),
        end: watch.end,
    }
}
