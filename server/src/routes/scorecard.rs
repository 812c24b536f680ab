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

use crate::compute::{
    Cancel, Delivery, KEPT_BYTES_PER_POINT, Plan, Priced, Slot, check_answer_bytes, check_price,
    lower_priority,
};
use crate::error::{AppError, ErrorBody};
use crate::json_object::JsonObject;
use crate::observers::{IntegralNames, JsonCollector};
use crate::request::{MethodRequest, SceneSpec, ScorecardRequest};
use crate::state::AppState;
use crate::views::{
    CRITERION, PROPERTIES_TEST, PropertiesView, RunSummary, ScorecardResponse, ScorecardRun,
    ScorecardScene,
};
use axum::Json;
use axum::extract::State;
use nhlab_core::catalogue::cost::run_cost_of;
use nhlab_core::catalogue::registry::LITERATURE_SCENES;
use nhlab_core::{Method, PAPER_SCENES};

/// Most scenes per scorecard.
pub const MAX_SCENES: usize = 16;

/// Steps that measuring a method's properties on a scene takes (round trips from four
/// points, the coupling checks, the manifold check's 200), rounded up: priced with its runs.
const PROPERTY_STEPS: f64 = 400.0;

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
        state.clone().check(move |_| plans(&req, &state)).await?
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

/// Every registered method, the paper's five first ([`Method::all`]).
fn all_methods() -> Vec<MethodRequest> {
    Method::all()
        .iter()
        .map(|m| {
            let params = m.params().into_iter().map(|(n, v)| (n.to_owned(), v)).collect();
            MethodRequest::new(m.info().id, params)
        })
        .collect()
}

/// The checked scenes, and the bytes their runs will hold at once: the series of one
/// scene's runs, kept for their verdicts (the scenes run one after another, and a scene's
/// series are dropped once judged; what the answer keeps of them, the verdicts, is small).
fn plans(req: &ScorecardRequest, state: &AppState) -> Result<(Vec<Plan>, u64), AppError> {
    let scenes = match &req.scenes {
        None => PAPER_SCENES
            .iter()
            .chain(&LITERATURE_SCENES)
            .map(|(system, preset)| SceneSpec {
                system: (*system).into(),
                preset: Some((*preset).to_owned()),
                ..SceneSpec::default()
            })
            .collect(),
        Some(s) if s.is_empty() => {
            return Err(AppError::invalid(
                "scenes",
                "scenes must not be empty; leave it out for the paper's six experiments",
            ));
        }
        Some(s) if s.len() > MAX_SCENES => {
            return Err(AppError::invalid(
                "scenes",
                format!("{} scenes exceed the limit of {MAX_SCENES} per scorecard", s.len()),
            ));
        }
        Some(s) => s.clone(),
    };
    let methods = req.methods.clone().unwrap_or_else(all_methods);
    let plans = scenes
        .into_iter()
        .enumerate()
        .map(|(i, scene)| {
            let sim = scene.to_simulate(Some(methods.clone()), req.points);
            Plan::resolve_all(&sim, &state.config, &state.caches, Delivery::JsonOnly).map_err(
                |mut e| {
                    // Methods and points are the scorecard's own fields; the rest is the scene's.
                    if let Some(path) = &e.path
                        && !path.starts_with("methods")
                        && path != "points"
                    {
                        e.path = Some(format!("scenes[{i}].{path}"));
                    }
                    e
                },
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let held = plans.iter().map(|p| p.held_bytes(KEPT_BYTES_PER_POINT)).max().unwrap_or(0);
    let what = " (a scene's runs' series, kept for their verdicts: series × points × bytes \
                per point)";
    check_answer_bytes(held, &state.config, what)?;
    let mut priced = Vec::new();
    for plan in &plans {
        priced.extend(plan.priced());
        let system = &plan.prepared.scene.system;
        for (m, why) in plan.methods.iter().zip(&plan.not_applicable) {
            if why.is_none() {
                let cost = run_cost_of(system, m, PROPERTY_STEPS);
                priced.push(Priced::new(format!("{}'s properties", m.label()), 1.0, cost));
            }
        }
    }
    check_price(&priced, &state.config, "scenes", "shorten t_end, use fewer scenes or methods")?;
    Ok((plans, held))
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
