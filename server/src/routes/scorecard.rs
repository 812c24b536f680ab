//! [`scorecard`]: the `POST /scorecard` handler. Methods (default: every registered method)
//! × scenes (default: the paper's six experiments) → the verdict of every integral's error
//! series per run, and each method's measured properties (reversibility, fibration) on each
//! scene. Everything is computed on request, scene after scene (each scene's runs and its
//! property measurements in parallel on the blocking pool: a scorecard takes no more threads
//! than a `/simulate`), and stopped when the client goes away, like `/simulate`.
//!
//! A scene is checked exactly as a `/simulate` body would be (its errors are reported under
//! `scenes[i]`); the methods and `points` once for all scenes. Each run is kept by a
//! [`JsonCollector`], of which only the verdicts are reported.

use crate::compute::{Cancel, Plan, Slot, lower_priority, scorecard_plans};
use crate::error::{AppError, ErrorBody};
use crate::json_object::JsonObject;
use crate::observers::{IntegralNames, JsonCollector};
use crate::request::ScorecardRequest;
use crate::state::AppState;
use crate::views::{
    CRITERION, PROPERTIES_TEST, PropertiesView, RunSummary, ScorecardResponse, ScorecardRun,
    ScorecardScene,
};
use axum::Json;
use axum::extract::State;
use nhlab_core::Method;

/// Scores methods on scenes: verdicts of every error series and measured properties.
#[utoipa::path(
    post,
    path = "/scorecard",
    tag = "nhlab",
    request_body = ScorecardRequest,
    responses(
        (status = 200, description = "Verdicts per scene, method and integral, and each \
            method's measured properties per scene. Verdict criterion: exact: the largest \
            error stays at round-off, max ≤ 1e-10·max(1, |I(0)|); drift: the mean error over \
            the last quarter of the time span exceeds the largest error over its first 1/32; \
            bounded otherwise.", body = ScorecardResponse),
        (status = 400, description = "The body is not valid JSON of the right shape", body = ErrorBody),
        (status = 413, description = "The body is too large", body = ErrorBody),
        (status = 415, description = "The body was not sent with `Content-Type: application/json`", body = ErrorBody),
        (status = 422, description = "A field is wrong (the error names it, e.g. \
            `scenes[1].preset`), or the work is estimated over max_request_seconds of CPU (the \
            estimate in the message)", body = ErrorBody),
        (status = 500, description = "Internal error", body = ErrorBody),
        (status = 503, description = "Every simulation slot is taken, or the server is \
            shutting down; retry after `Retry-After` seconds", body = ErrorBody,
            headers(("Retry-After" = u32, description = "Seconds to wait before retrying"))),
    )
)]
pub async fn scorecard(
    State(state): State<AppState>,
    JsonObject(req): JsonObject<ScorecardRequest>,
) -> Result<Json<ScorecardResponse>, AppError> {
    let (plans, held) = {
        let state = state.clone();
        state.clone().check(move |_| scorecard_plans(&req, &state.config, &state.caches)).await?
    };
    tracing::Span::current().record(
        "scene",
        format!("scorecard scenes={} methods={}", plans.len(), plans[0].methods.len()).as_str(),
    );
    // One simulation slot for the whole scorecard, like one /simulate request; its runs keep
    // their series for the verdicts until they end.
    let (slot, _budget) = state.admit(held)?;
    Ok(Json(run(&state, plans, slot).await?))
}

async fn run(
    state: &AppState,
    plans: Vec<Plan>,
    slot: Slot,
) -> Result<ScorecardResponse, AppError> {
    let cancel = Cancel::default();
    // If the client goes away, this future is dropped and the runs are stopped.
    let _on_drop = cancel.on_drop();
    let runner = state.runner().with_slot(slot.clone());
    let ids = scene_ids(&plans);
    let mut scenes = Vec::with_capacity(plans.len());
    let mut properties = Vec::new();
    // Scene after scene, each scene's runs and its property measurements at once: a
    // scorecard takes at most one thread per method (and one more) from the blocking pool,
    // like a `/simulate`, and keeps the cores as busy.
    for (plan, id) in plans.iter().zip(ids) {
        // A collector keeps the series the verdicts need; only they are reported.
        let handles: Vec<_> = (0..plan.methods.len())
            .map(|i| {
                let names = IntegralNames::of(&plan.prepared);
                let collector = JsonCollector::new(&[], names, cancel.clone());
                plan.not_applicable[i].is_none().then(|| runner.spawn(plan, i, collector))
            })
            .collect();
        let (scene, methods) = (plan.prepared.clone(), plan.methods.clone());
        let not_applicable = plan.not_applicable.clone();
        let (guard, cancel, slot) = (state.run_guard(), cancel.clone(), slot.clone());
        let measure = tokio::task::spawn_blocking(move || {
            let (_guard, _slot) = (guard, slot);
            lower_priority();
            // Stopped between two steps when the client goes away (its result is then not
            // reported).
            let stop = || cancel.is_cancelled();
            let measure = |(m, why): (&Method, &Option<String>)| {
                (!stop()).then(|| why.is_none().then(|| scene.scene.properties_until(m, &stop)))
            };
            methods.iter().zip(&not_applicable).map(measure).collect::<Vec<_>>()
        });
        let mut out = Vec::with_capacity(handles.len());
        for (i, handle) in handles.into_iter().enumerate() {
            let method = &plan.scene.methods[i];
            let Some(handle) = handle else {
                let why = plan.not_applicable[i].clone().unwrap_or_default();
                let summary = RunSummary::not_applicable(method.clone(), why);
                out.push(ScorecardRun {
                    summary,
                    verdicts: Default::default(),
                    gaps: Default::default(),
                });
                continue;
            };
            let finished = handle.await.map_err(|e| AppError::internal(format!("run {i}: {e}")))?;
            let summary = finished.summary(method.clone()).map_err(|panic| {
                AppError::internal(format!(
                    "internal error: the simulation of {} on {id} panicked: {panic}",
                    method.label
                ))
            })?;
            let verdicts = &finished.observer.verdicts;
            out.push(ScorecardRun { summary, verdicts: verdicts.all(), gaps: verdicts.gaps() });
        }
        let measured = measure.await.map_err(|e| {
            AppError::internal(format!("internal error: measuring properties on {id}: {e}"))
        })?;
        for (method, m) in plan.scene.methods.iter().zip(measured) {
            let m = m.ok_or_else(|| AppError::internal("the scorecard was cancelled"))?;
            let system = plan.scene.system.to_string();
            properties.push(match m {
                Some(measured) => PropertiesView::of(method.clone(), &system, &id, measured),
                None => PropertiesView::not_applicable(method.clone(), &system, &id),
            });
        }
        scenes.push(ScorecardScene { id, scene: plan.scene.clone(), runs: out });
    }
    Ok(ScorecardResponse {
        criterion: CRITERION.to_owned(),
        properties_test: PROPERTIES_TEST.to_owned(),
        methods: plans[0].scene.methods.clone(),
        scenes,
        properties,
    })
}

/// `system/preset` per plan, with `#i` added to a repeated one.
fn scene_ids(plans: &[Plan]) -> Vec<String> {
    let mut ids: Vec<String> = Vec::with_capacity(plans.len());
    for (i, plan) in plans.iter().enumerate() {
        let id = plan.scene.label();
        ids.push(if ids.contains(&id) { format!("{id}#{i}") } else { id });
    }
    ids
}
