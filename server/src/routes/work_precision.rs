//! [`work_precision`]: the `POST /work-precision` handler. A scene as `/simulate` takes it,
//! methods, and step sizes (`steps`, or `levels` halvings of the scene's step) → for every
//! method × step what a run costs (its wall time, the minimum over `repeats`) and what it
//! buys: the final error in (q, q̇) against a Dop853 reference at t_end, and the largest
//! error of each integral (`nhlab_core::work_precision`).
//!
//! Like `/simulate`: input checked field by field before admission (the rows' runs priced
//! against `max_request_seconds`), one simulation slot, the computation on the blocking pool,
//! stopped when the client goes away — the reference solve too, which looks at the flag every
//! few milliseconds ([`AIM`]). Each run, and the reference solve, ends past
//! `max_run_seconds`. The reference is kept across requests in [`Caches`]
//! (`reference.cached` says whether this request reused one) unless it was stopped. Its solve
//! fails beyond [`MAX_STEPS`] Dop853 steps, so its cost is bounded whatever t_end is; its
//! memory does not grow with the steps.
//!
//! [`AIM`]: nhlab_core::measure::pace::AIM
//! [`MAX_STEPS`]: nhlab_core::measure::reference::MAX_STEPS

use crate::compute::{
    Caches, Cancel, Delivery, KEPT_BYTES_PER_POINT, Plan, Priced, ReferenceKey, Slot, check_price,
    lower_priority, time_limit,
};
use crate::config::Config;
use crate::error::{AppError, ErrorBody};
use crate::json_object::JsonObject;
use crate::request::{SimulateRequest, WorkPrecisionRequest};
use crate::state::AppState;
use crate::views::{ReferenceView, Status, WorkPrecisionResponse, WorkPrecisionRow};
use axum::Json;
use axum::extract::State;
use nhlab_core::catalogue::cost::run_cost_of;
use nhlab_core::catalogue::work_precision::{measure_within, reference_until};
use nhlab_core::measure::reference::{ReferenceError, TOL};
use nhlab_core::{Scene, SceneRequest, Short};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

/// Most step sizes per request (`levels`, or entries of `steps`).
pub const MAX_LEVELS: usize = 12;
/// Most timing repetitions per run.
pub const MAX_REPEATS: i64 = 10;
/// Halvings when neither `steps` nor `levels` is given.
pub const DEFAULT_LEVELS: i64 = 4;
/// Repetitions when `repeats` is not given.
pub const DEFAULT_REPEATS: i64 = 3;

/// Measures the final error and run time of methods at several step sizes.
#[utoipa::path(
    post,
    path = "/work-precision",
    tag = "nhlab",
    request_body = WorkPrecisionRequest,
    responses(
        (status = 200, description = "The resolved scene, the reference and one row per \
            method × step: wall time (fastest of `repeats`), final error against the \
            reference at t_end and the largest error of each integral.",
            body = WorkPrecisionResponse),
        (status = 400, description = "The body is not valid JSON of the right shape", body = ErrorBody),
        (status = 413, description = "The body is too large", body = ErrorBody),
        (status = 415, description = "The body was not sent with `Content-Type: application/json`", body = ErrorBody),
        (status = 422, description = "A field is wrong (the error names it, e.g. `steps[2]`), \
            the work is estimated over max_request_seconds of CPU (the estimate in the \
            message), or the reference solve failed (at `t_end`)", body = ErrorBody),
        (status = 500, description = "Internal error", body = ErrorBody),
        (status = 503, description = "Every simulation slot is taken, or the server is \
            shutting down; retry after `Retry-After` seconds", body = ErrorBody,
            headers(("Retry-After" = u32, description = "Seconds to wait before retrying"))),
    )
)]
pub async fn work_precision(
    State(state): State<AppState>,
    JsonObject(req): JsonObject<WorkPrecisionRequest>,
) -> Result<Json<WorkPrecisionResponse>, AppError> {
    let job = {
        let state = state.clone();
        state.clone().check(move |_| Job::resolve(&req, &state)).await?
    };
    tracing::Span::current().record(
        "scene",
        format!(
            "work-precision {} steps={:?} methods={} repeats={}",
            job.plan.scene.label(),
            job.steps,
            job.plan.methods.len(),
            job.repeats
        )
        .as_str(),
    );
    // One bucket per series, kept for one run at a time.
    let (slot, _budget) = state.admit(job.plan.held_bytes(KEPT_BYTES_PER_POINT))?;
    Ok(Json(run(&state, job, slot).await?))
}

/// A checked request.
struct Job {
    plan: Plan,
    steps: Vec<f64>,
    repeats: u32,
}

impl Job {
    fn resolve(req: &WorkPrecisionRequest, state: &AppState) -> Result<Self, AppError> {
        // One bucket per series: its max is the integral's largest error.
        let mut sim = req.to_simulate(req.methods.clone(), Some(1));
        if let (Some(steps), None, None) = (&req.steps, req.step, req.levels) {
            // The scene's own step is not run: the largest step asked for stands in for it,
            // once the steps are checked against t_end (the preset's step might not even fit
            // a short t_end, and the error would name the wrong field).
            let t_end = scene_t_end(&sim, &state.config)?;
            sim.step = given_steps(steps, t_end)?.into_iter().reduce(f64::max);
        }
        let plan = Plan::resolve(&sim, &state.config, &state.caches, Delivery::JsonOnly)?;
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
        let limit = state.config.max_steps_json;
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
        check_price(&priced, &state.config, field, advice)?;
        Ok(Self { plan, steps, repeats: repeats as u32 })
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

/// Runs every row on the blocking pool.
///
/// One task runs the rows one after another rather than one task per method: the point of
/// the endpoint is the time a run takes, and runs sharing the cores (a small server has
/// fewer than the paper's five methods) would each be timed with the others' contention in
/// it, by how the scheduler happened to interleave them. Alone, each run's time is its own, and
/// the minimum over the repetitions removes the rest of the noise.
async fn run(state: &AppState, job: Job, slot: Slot) -> Result<WorkPrecisionResponse, AppError> {
    let cancel = Cancel::default();
    // If the client goes away, this future is dropped and the rows stop.
    let _on_drop = cancel.on_drop();
    let (guard, caches) = (state.run_guard(), state.caches.clone());
    let limit = time_limit(&state.config);
    let task = tokio::task::spawn_blocking(move || {
        let (_guard, _slot) = (guard, slot);
        lower_priority();
        catch_unwind(AssertUnwindSafe(|| compute(&job, &caches, &cancel, limit)))
            .map_err(|_| AppError::internal("internal error: the work-precision run panicked"))?
    });
    task.await.map_err(|e| AppError::internal(format!("work-precision task: {e}")))?
}

fn compute(
    job: &Job,
    caches: &Caches,
    cancel: &Cancel,
    limit: Duration,
) -> Result<WorkPrecisionResponse, AppError> {
    let prepared = &job.plan.prepared;
    let key = ReferenceKey::of(&prepared.scene, TOL);
    let stop = || cancel.is_cancelled();
    // The reference solve stops when the client goes away, or past the time limit of a run.
    let started = Instant::now();
    let stop_solve = || stop() || started.elapsed() > limit;
    let (solved, cached) = caches.reference.get_or_compute_keeping(
        key,
        || reference_until(prepared, &stop_solve),
        |r| !matches!(r, Err(ReferenceError::Cancelled { .. })),
    );
    let r = solved.map_err(|e| match e {
        ReferenceError::Cancelled { .. } if stop() => {
            AppError::internal("the work-precision run was cancelled")
        }
        ReferenceError::Cancelled { t } => AppError::invalid(
            "t_end",
            format!(
                "time limit: the reference solve (Dop853) took longer than {} s and was stopped \
                 at t = {} of t_end = {} (max_run_seconds); try a shorter t_end",
                Short(limit.as_secs_f64()),
                Short(t),
                Short(prepared.scene.t_end)
            ),
        ),
        e => AppError::invalid("t_end", format!("{e}, at tolerance {TOL:e}; try a shorter t_end")),
    })?;
    let mut rows = Vec::with_capacity(job.plan.methods.len() * job.steps.len());
    for (method, view) in job.plan.methods.iter().zip(&job.plan.scene.methods) {
        for &h in &job.steps {
            if stop() {
                return Err(AppError::internal("the work-precision run was cancelled"));
            }
            let row =
                measure_within(prepared, &r.state, method, h, job.repeats, &stop, Some(limit));
            let finite = |x: f64| x.is_finite().then_some(x);
            let max_error = prepared
                .integrals
                .iter()
                .map(|i| {
                    (prepared.integral_name(*i), row.max_error.get(i).copied().and_then(finite))
                })
                .collect();
            rows.push(WorkPrecisionRow {
                method: view.clone(),
                step: row.step,
                steps: row.steps,
                elapsed_ms: micro(row.elapsed_ms),
                final_error: row.final_error.and_then(finite),
                max_error,
                status: if row.error.is_none() { Status::Ok } else { Status::Failed },
                error: row.error,
            });
        }
    }
    Ok(WorkPrecisionResponse {
        scene: job.plan.scene.clone(),
        reference: ReferenceView {
            elapsed_ms: micro(r.elapsed_ms),
            evaluations: r.state.evaluations,
            steps: r.state.steps,
            constraint_residual: r.state.constraint_residual,
            cached,
            exact: r.exact,
        },
        rows,
    })
}

/// Milliseconds rounded to the microsecond, as the other endpoints report them.
fn micro(ms: f64) -> f64 {
    (ms * 1e3).round() / 1e3
}
