//! [`scorecard`]: the `POST /scorecard` handler. Methods (default: every registered method)
//! × scenes (default: the paper's six experiments) → the verdict of every integral's error
//! series per run, and each method's measured properties (reversibility, fibration) on each
//! scene. Everything is computed on request, in parallel on the blocking pool, and stopped
//! when the client goes away, like `/simulate`.
//!
//! A scene is checked exactly as a `/simulate` body would be (its errors are reported under
//! `scenes[i]`); the methods and `points` once for all scenes.

use crate::plan::Delivery;
use crate::request::SceneSpec;
use crate::{
    AppError, AppState, CRITERION, Cancel, Collector, MethodRequest, MethodView, Plan, Runner,
    SceneView, Slot, Status, VerdictView, openapi::schemas,
};
use axum::Json;
use axum::body::Bytes;
use axum::extract::State;
use axum::extract::rejection::BytesRejection;
use nhlab_core::{Method, Properties};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// Most scenes per scorecard.
pub const MAX_SCENES: usize = 16;

/// The paper's six experiments, the default scenes.
pub use nhlab_core::PAPER_SCENES;

/// The body of `POST /scorecard`; every field is optional (`{}` is the paper's scorecard).
#[derive(Debug, Clone, Default, PartialEq, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ScorecardRequest {
    /// Methods, as in `/simulate` (default: every registered method, the paper's five
    /// first).
    #[serde(default)]
    #[schema(schema_with = schemas::methods)]
    pub methods: Option<Vec<MethodRequest>>,
    /// Scenes, each like a `/simulate` body without `methods` and `points` (default: the
    /// paper's six experiments).
    #[serde(default, deserialize_with = "crate::request::objects")]
    #[schema(max_items = 16)]
    pub scenes: Option<Vec<SceneSpec>>,
    /// Buckets per series, on which the verdicts are taken (default 1000).
    #[serde(default)]
    #[schema(minimum = 1)]
    pub points: Option<i64>,
}

/// The answer of `POST /scorecard`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ScorecardResponse {
    /// How a series is judged `exact`, `bounded` or `drift`.
    pub criterion: String,
    /// How the properties are measured.
    pub properties_test: String,
    /// The methods, in the order of every scene's runs.
    pub methods: Vec<MethodView>,
    /// One entry per scene, in request order.
    pub scenes: Vec<ScorecardScene>,
    /// Each method's measured properties on each scene (scene-major order).
    pub properties: Vec<PropertiesView>,
}

/// One scene of the scorecard.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ScorecardScene {
    /// `system/preset`, made unique with `#i` (the scene's index) when repeated.
    pub id: String,
    /// The resolved scene (a `/simulate` body with these values reproduces the runs).
    pub scene: SceneView,
    /// One run per method.
    pub runs: Vec<ScorecardRun>,
}

/// One run of the scorecard: how it ended and its verdicts.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ScorecardRun {
    /// The method.
    pub method: MethodView,
    /// `ok` or `failed`.
    pub status: Status,
    /// Why it failed, or null.
    pub error: Option<String>,
    /// Steps completed.
    pub steps: u64,
    /// Wall-clock time of the run, from its start to its end, in milliseconds. It includes
    /// the time the run waited for a core: runs beyond the server's cores share them.
    pub elapsed_ms: f64,
    /// CPU time the run's thread used, in milliseconds: what the method cost, whatever the
    /// load (null where the platform does not measure it).
    pub cpu_ms: Option<f64>,
    /// The verdict of each integral's error series (up to the failure for a failed run).
    pub verdicts: BTreeMap<String, VerdictView>,
}

/// A method's measured properties on one scene (from its start, with its step).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct PropertiesView {
    /// The method.
    pub method: MethodView,
    /// System id.
    pub system: String,
    /// The scene's id (as in `scenes[].id`).
    pub scene: String,
    /// One step, flip the velocity, one step, flip back returns the start (null: the
    /// measurement failed, see `error`).
    pub reversible: Option<bool>,
    /// The three fibration checks pass.
    pub preserves_fibration: Option<bool>,
    /// Largest relative round-trip defect (reversible when ≤ 1e-11).
    pub reversibility_defect: Option<f64>,
    /// Largest driver change caused by a passenger change (≤ 1e-12 to pass).
    pub driver_coupling: Option<f64>,
    /// Largest reduced-state change caused by a shift along a force-free fiber (≤ 1e-12).
    pub fiber_coupling: Option<f64>,
    /// Largest discrete-constraint residual, at the step's end or midpoint (≤ 1e-12).
    pub constraint_defect: Option<f64>,
    /// Why the measurement failed (a step failed), or null.
    pub error: Option<String>,
}

/// How the properties are measured (see `nhlab_core::properties`).
pub const PROPERTIES_TEST: &str = "Measured from each scene's start with its step. \
    Reversible: one step, flip the velocity, one step, flip back returns the start to \
    1e-11·max(1, |state|), from the start and three later points. Preserves the fibration: \
    (1) the driver is blind to the passenger: a start with the same driver state and another \
    passenger gives the same driver state after 5 steps to 1e-12; (2) the reduced state is \
    blind to shifts along force-free passenger axes, to 1e-12 after 5 steps; (3) the method \
    imposes the constraint at every step's end or midpoint, to 1e-12 over 200 steps.";

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
        (status = 400, description = "The body is not valid JSON of the right shape", body = crate::ErrorBody),
        (status = 413, description = "The body is too large", body = crate::ErrorBody),
        (status = 422, description = "A field is wrong (the error names it, e.g. `scenes[1].preset`)", body = crate::ErrorBody),
        (status = 500, description = "Internal error", body = crate::ErrorBody),
        (status = 503, description = "Every simulation slot is taken, or the server is \
            shutting down; retry after `Retry-After` seconds", body = crate::ErrorBody,
            headers(("Retry-After" = u32, description = "Seconds to wait before retrying"))),
    )
)]
pub async fn scorecard(
    State(state): State<AppState>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<ScorecardResponse>, AppError> {
    let body = body.map_err(|e| AppError::body(e, state.config.max_body_bytes))?;
    let req: ScorecardRequest = crate::request::read_object(&body)?;
    let plans = {
        let state = state.clone();
        crate::runner::off_runtime(move || plans(&req, &state)).await?
    };
    tracing::Span::current().record(
        "scene",
        format!("scorecard scenes={} methods={}", plans.len(), plans[0].methods.len()).as_str(),
    );
    // One simulation slot for the whole scorecard, like one /simulate request.
    let slot = state.admit()?;
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

fn plans(req: &ScorecardRequest, state: &AppState) -> Result<Vec<Plan>, AppError> {
    let scenes = match &req.scenes {
        None => PAPER_SCENES
            .iter()
            .map(|(system, preset)| SceneSpec {
                system: (*system).to_owned(),
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
    scenes
        .into_iter()
        .enumerate()
        .map(|(i, scene)| {
            let sim = scene.to_simulate(Some(methods.clone()), req.points);
            Plan::resolve(&sim, state, Delivery::JsonOnly).map_err(|mut e| {
                // Methods and points are the scorecard's own fields; the rest is the scene's.
                if let Some(path) = &e.path
                    && !path.starts_with("methods")
                    && path != "points"
                {
                    e.path = Some(format!("scenes[{i}].{path}"));
                }
                e
            })
        })
        .collect()
}

async fn run(
    state: &AppState,
    plans: Vec<Plan>,
    slot: Slot,
) -> Result<ScorecardResponse, AppError> {
    let cancel = Cancel::default();
    // If the client goes away, this future is dropped and the runs are stopped.
    let _on_drop = cancel.on_drop();
    let runner = Runner::new(state).with_slot(slot.clone());
    let ids = scene_ids(&plans);
    // Every run and every scene's property measurements start at once.
    let mut runs = Vec::new();
    let mut measures = Vec::new();
    for plan in &plans {
        runs.push(
            (0..plan.methods.len())
                // A collector keeps the series the verdicts need; only they are reported.
                .map(|i| runner.spawn(plan, i, Collector::new(&[], cancel.clone())))
                .collect::<Vec<_>>(),
        );
        let (scene, methods) = (plan.prepared.clone(), plan.methods.clone());
        let (guard, cancel, slot) = (state.run_guard(), cancel.clone(), slot.clone());
        measures.push(tokio::task::spawn_blocking(move || {
            let (_guard, _slot) = (guard, slot);
            crate::runner::lower_priority();
            let measure = |m: &Method| (!cancel.is_cancelled()).then(|| scene.scene.properties(m));
            methods.iter().map(measure).collect::<Vec<_>>()
        }));
    }
    let mut scenes = Vec::with_capacity(plans.len());
    let mut properties = Vec::new();
    for (((plan, handles), measure), id) in plans.iter().zip(runs).zip(measures).zip(ids) {
        let mut out = Vec::with_capacity(handles.len());
        for (i, handle) in handles.into_iter().enumerate() {
            let finished = handle.await.map_err(|e| AppError::internal(format!("run {i}: {e}")))?;
            let outcome = finished.outcome.map_err(|panic| {
                AppError::internal(format!(
                    "internal error: the simulation of {} on {id} panicked: {panic}",
                    plan.scene.methods[i].label
                ))
            })?;
            out.push(ScorecardRun {
                method: plan.scene.methods[i].clone(),
                status: Status::of(&outcome),
                error: outcome.error.map(|e| e.to_string()),
                steps: outcome.steps,
                elapsed_ms: finished.elapsed_ms,
                cpu_ms: finished.cpu_ms,
                verdicts: finished.observer.verdicts.all(),
            });
        }
        let measured = measure.await.map_err(|e| {
            AppError::internal(format!("internal error: measuring properties on {id}: {e}"))
        })?;
        for (method, m) in plan.scene.methods.iter().zip(measured) {
            let m = m.ok_or_else(|| AppError::internal("the scorecard was cancelled"))?;
            properties.push(PropertiesView::of(method.clone(), &plan.scene.system, &id, m));
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
        let id = format!("{}/{}", plan.scene.system, plan.scene.preset);
        ids.push(if ids.contains(&id) { format!("{id}#{i}") } else { id });
    }
    ids
}

impl PropertiesView {
    fn of(
        method: MethodView,
        system: &str,
        scene: &str,
        measured: Result<Properties, nhlab_core::StepFailure>,
    ) -> Self {
        let finite = |x: f64| x.is_finite().then_some(x);
        let (p, error) = match measured {
            Ok(p) => (Some(p), None),
            Err(e) => (None, Some(format!("a step failed while measuring: {e}"))),
        };
        Self {
            method,
            system: system.to_owned(),
            scene: scene.to_owned(),
            reversible: p.map(|p| p.reversible),
            preserves_fibration: p.map(|p| p.preserves_fibration),
            reversibility_defect: p.and_then(|p| finite(p.reversibility_defect)),
            driver_coupling: p.and_then(|p| finite(p.driver_coupling)),
            fiber_coupling: p.and_then(|p| finite(p.fiber_coupling)),
            constraint_defect: p.and_then(|p| finite(p.constraint_defect)),
            error,
        }
    }
}
