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
    Caches, Cancel, KEPT_BYTES_PER_POINT, ReferenceKey, Slot, WorkPrecisionJob, lower_priority,
    time_limit,
};
use crate::error::{AppError, ErrorBody};
use crate::json_object::JsonObject;
use crate::request::WorkPrecisionRequest;
use crate::state::AppState;
use crate::views::{ReferenceView, Status, ValuesView, WorkPrecisionResponse, WorkPrecisionRow};
use axum::Json;
use axum::extract::State;
use nhlab_core::Short;
use nhlab_core::catalogue::work_precision::{measure_within, reference_until};
use nhlab_core::measure::reference::{ReferenceError, TOL};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

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
        state
            .clone()
            .check(move |_| WorkPrecisionJob::check(&req, &state.config, &state.caches))
            .await?
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

/// Runs every row on the blocking pool.
///
/// One task runs the rows one after another rather than one task per method: the point of
/// the endpoint is the time a run takes, and runs sharing the cores (a small server has
/// fewer than the paper's five methods) would each be timed with the others' contention in
/// it, by how the scheduler happened to interleave them. Alone, each run's time is its own, and
/// the minimum over the repetitions removes the rest of the noise.
async fn run(
    state: &AppState,
    job: WorkPrecisionJob,
    slot: Slot,
) -> Result<WorkPrecisionResponse, AppError> {
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
    job: &WorkPrecisionJob,
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
    let t_end = prepared.scene.t_end;
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
                observables: job.observables.as_deref().map(|o| match &row.end {
                    Some((q, v)) => ValuesView::at(o, t_end, q, v),
                    None => ValuesView(o.names().iter().map(|n| (n.clone(), f64::NAN)).collect()),
                }),
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
            observables: job
                .observables
                .as_deref()
                .map(|o| ValuesView::at(o, t_end, &r.state.q, &r.state.v)),
        },
        rows,
    })
}

/// Milliseconds rounded to the microsecond, as the other endpoints report them.
fn micro(ms: f64) -> f64 {
    (ms * 1e3).round() / 1e3
}
