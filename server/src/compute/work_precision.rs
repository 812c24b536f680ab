//! [`WorkPrecisionJob`]: a `/work-precision` request checked and priced before admission:
//! its scene as `/simulate` checks it, the step sizes (`steps`, or `levels` halvings of the
//! scene's step), the repetitions, every run's steps within `max_steps_json` and their CPU
//! within `max_request_seconds`.

use super::{Caches, Delivery, Plan, Priced, check_price, observables_of};
use crate::config::Config;
use crate::error::AppError;
use crate::request::{SimulateRequest, WorkPrecisionRequest};
use nhlab_core::catalogue::cost::run_cost_of;
use nhlab_core::measure::observables::Observables;
use nhlab_core::{Scene, SceneRequest, Short};
use std::sync::Arc;

/// Most step sizes per request (`levels`, or entries of `steps`).
pub const MAX_LEVELS: usize = 12;
/// Most timing repetitions per run.
pub const MAX_REPEATS: i64 = 10;
/// Halvings when neither `steps` nor `levels` is given.
pub const DEFAULT_LEVELS: i64 = 4;
/// Repetitions when `repeats` is not given.
pub const DEFAULT_REPEATS: i64 = 3;

/// A checked `/work-precision` request: its scene and methods, the step sizes and the
/// timing repetitions.
pub struct WorkPrecisionJob {
    /// The scene and methods, checked as `/simulate` checks them.
    pub plan: Plan,
    /// The step sizes, each at most t_end.
    pub steps: Vec<f64>,
    /// Timing repetitions per run.
    pub repeats: u32,
    /// The quantities taken at t_end, if any were asked for.
    pub observables: Option<Arc<Observables>>,
}

impl WorkPrecisionJob {
    /// Checks `req` field by field and prices its runs (the rows' runs × `repeats`).
    pub fn check(
        req: &WorkPrecisionRequest,
        config: &Config,
        caches: &Caches,
    ) -> Result<Self, AppError> {
        // One bucket per series: its max is the integral's largest error.
        let mut sim = req.to_simulate(req.methods.clone(), Some(1));
        if let (Some(steps), None, None) = (&req.steps, req.step, req.levels) {
            // The scene's own step is not run: the largest step asked for stands in for it,
            // once the steps are checked against t_end (the preset's step might not even fit
            // a short t_end, and the error would name the wrong field).
            let t_end = scene_t_end(&sim, config)?;
            sim.step = given_steps(steps, t_end)?.into_iter().reduce(f64::max);
        }
        let plan = Plan::resolve(&sim, config, caches, Delivery::JsonOnly)?;
        if let Some(i) = plan.methods.iter().position(|m| m.info().instrument) {
            return Err(AppError::invalid(
                format!("methods[{i}]"),
                format!(
                    "{} is what work–precision measures the methods against (its row is the \
                     answer's `reference`); list methods under study only",
                    plan.methods[i].label()
                ),
            ));
        }
        let (t_end, h) = (plan.prepared.scene.t_end, plan.prepared.scene.step);
        let (steps, field) = match (&req.steps, req.levels) {
            (Some(_), Some(_)) => {
                return Err(AppError::invalid(
                    "levels",
                    "give either steps (a list of step sizes) or levels (halvings of the \
                     scene's step), not both",
                ));
            }
            (Some(steps), None) => (given_steps(steps, t_end)?, "steps"),
            (None, levels) => (halvings(h, levels.unwrap_or(DEFAULT_LEVELS))?, "levels"),
        };
        let repeats = req.repeats.unwrap_or(DEFAULT_REPEATS);
        if !(1..=MAX_REPEATS).contains(&repeats) {
            return Err(AppError::invalid(
                "repeats",
                format!("repeats must be between 1 and {MAX_REPEATS}, got {repeats}"),
            ));
        }
        // Every run of every row, as `measure` rounds them; in f64 so that no input overflows.
        // A composed method's step counts its stages' sub-steps.
        let per_method: f64 = steps.iter().map(|&s| (t_end / s).round().max(1.0)).sum();
        let stages: usize = plan.methods.iter().map(|m| m.stages()).sum();
        let total = per_method * stages as f64 * repeats as f64;
        let limit = config.max_steps_json;
        if total > limit as f64 {
            let methods = if stages == plan.methods.len() {
                format!("{} methods", plan.methods.len())
            } else {
                format!("{} methods, {stages} sub-steps per step in all", plan.methods.len())
            };
            return Err(AppError::invalid(
                field,
                format!(
                    "{total:.3e} steps in all ({methods} × {repeats} repeats × {per_method:.3e} \
                     steps per method) exceed the limit of {limit} steps per request; use fewer \
                     or larger steps, fewer repeats or methods, or a shorter t_end"
                ),
            ));
        }
        let system = &plan.prepared.scene.system;
        let priced: Vec<Priced> = plan
            .methods
            .iter()
            .flat_map(|m| {
                steps.iter().map(move |&s| {
                    let cost = run_cost_of(system, m, (t_end / s).round().max(1.0));
                    Priced::new(m.label(), repeats as f64, cost)
                })
            })
            .collect();
        let advice = "use fewer or larger steps, fewer repeats or methods, or a shorter t_end";
        check_price(&priced, config, field, advice)?;
        let observables = observables_of(req.observables.as_ref(), &plan.prepared, config)?;
        Ok(Self { plan, steps, repeats: repeats as u32, observables })
    }
}

/// The t_end `sim` resolves to, whatever its step.
fn scene_t_end(sim: &SimulateRequest, config: &Config) -> Result<f64, AppError> {
    // Any step that fits every t_end: only t_end is wanted here.
    let req = SceneRequest { step: Some(f64::MIN_POSITIVE), ..sim.scene_request() };
    let scene = Scene::resolve_within(&req, &config.formulas)?;
    Ok(scene.t_end)
}

fn given_steps(steps: &[f64], t_end: f64) -> Result<Vec<f64>, AppError> {
    if steps.is_empty() || steps.len() > MAX_LEVELS {
        return Err(AppError::invalid(
            "steps",
            format!("steps must list 1 to {MAX_LEVELS} step sizes, got {}", steps.len()),
        ));
    }
    for (i, &h) in steps.iter().enumerate() {
        if !(h.is_finite() && h > 0.0 && h <= t_end) {
            return Err(AppError::invalid(
                format!("steps[{i}]"),
                format!(
                    "each step must be positive and at most t_end = {}, got {}",
                    Short(t_end),
                    Short(h)
                ),
            ));
        }
    }
    Ok(steps.to_vec())
}

fn halvings(h: f64, levels: i64) -> Result<Vec<f64>, AppError> {
    if !(1..=MAX_LEVELS as i64).contains(&levels) {
        return Err(AppError::invalid(
            "levels",
            format!("levels must be between 1 and {MAX_LEVELS}, got {levels}"),
        ));
    }
    Ok((0..levels).map(|k| h / 2f64.powi(k as i32)).collect())
}
