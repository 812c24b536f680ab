//! [`simulate`]: the `POST /simulate` handler. It reads and checks the request, then answers
//! with one JSON document ([`SimulateResponse`]) or, for `Accept: text/event-stream`, with the
//! event [`stream`](crate::stream()). The methods run in parallel on the blocking pool, once
//! the request is admitted ([`AppState::admit`]: a bounded number of simulations at once).

use crate::plan::Delivery;
use crate::runner::Finished;
use crate::{
    AppError, AppState, Cancel, Collector, Plan, RunView, Runner, SceneView, SimulateRequest, Slot,
    Status,
};
use axum::body::Bytes;
use axum::extract::State;
use axum::extract::rejection::BytesRejection;
use axum::http::{HeaderMap, header};
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use utoipa::ToSchema;

/// The JSON answer of `POST /simulate`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SimulateResponse {
    /// The resolved scene.
    pub scene: SceneView,
    /// One run per method, in the order of `scene.methods`.
    pub runs: Vec<RunView>,
}

/// Runs methods on a scene and reports the error of each first integral over time.
#[utoipa::path(
    post,
    path = "/simulate",
    tag = "nhlab",
    request_body = SimulateRequest,
    responses(
        (status = 200, description = "The resolved scene and one run per method. With \
            `Accept: text/event-stream`, server-sent events instead: `scene` (SceneView), \
            `progress` (ProgressEvent), `points` (PointsEvent), `run` (RunEvent), `done` \
            (DoneEvent), or `shutdown` (ShutdownEvent) instead of `done` when the \
            server shuts down.",
            content(
                (SimulateResponse = "application/json"),
                (String = "text/event-stream"),
            )),
        (status = 400, description = "The body is not valid JSON of the right shape", body = crate::ErrorBody),
        (status = 413, description = "The body is too large", body = crate::ErrorBody),
        (status = 422, description = "A field is wrong (the error names it)", body = crate::ErrorBody),
        (status = 500, description = "Internal error", body = crate::ErrorBody),
        (status = 503, description = "Every simulation slot is taken, or the server is \
            shutting down; retry after `Retry-After` seconds", body = crate::ErrorBody,
            headers(("Retry-After" = u32, description = "Seconds to wait before retrying"))),
    )
)]
pub async fn simulate(
    State(state): State<AppState>,
    headers: HeaderMap,
    body: Result<Bytes, BytesRejection>,
) -> Result<Response, AppError> {
    let body = body.map_err(|e| AppError::body(e, state.config.max_body_bytes))?;
    let req = SimulateRequest::from_json(&body)?;
    let delivery = if wants_stream(&headers) { Delivery::Stream } else { Delivery::Json };
    let plan = {
        let state = state.clone();
        crate::runner::off_runtime(move || Plan::resolve(&req, &state, delivery)).await?
    };
    let scene = &plan.scene;
    let summary = format!(
        "{}/{} steps={} methods={} {:?}",
        scene.system,
        scene.preset,
        scene.steps,
        scene.methods.len(),
        delivery
    );
    tracing::Span::current().record("scene", summary.as_str());
    let slot = state.admit()?;
    match delivery {
        Delivery::Stream => Ok(crate::stream(&state, plan, slot)),
        Delivery::Json | Delivery::JsonOnly => {
            let finished = run(&state, &plan, slot).await?;
            // Building the columns, the verdicts and ~1 MB of JSON is CPU work: off the runtime.
            let body = crate::runner::off_runtime(move || {
                let response = respond(plan, finished)?;
                // Sized up front (a number takes ~20 bytes): the buffer then never moves.
                let numbers: usize = response
                    .runs
                    .iter()
                    .flat_map(|r| r.series.values())
                    .map(|s| 3 * s.t.len())
                    .sum();
                let mut body = Vec::with_capacity(4096 + 22 * numbers);
                serde_json::to_writer(&mut body, &response).map_err(|e| {
                    AppError::internal(format!("internal error: writing JSON: {e}"))
                })?;
                Ok(body)
            })
            .await?;
            Ok(([(header::CONTENT_TYPE, "application/json")], body).into_response())
        }
    }
}

fn wants_stream(headers: &HeaderMap) -> bool {
    headers
        .get_all(header::ACCEPT)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .any(|v| v.contains("text/event-stream"))
}

/// Runs every method of `plan` in parallel and waits for them.
async fn run(
    state: &AppState,
    plan: &Plan,
    slot: Slot,
) -> Result<Vec<Finished<Collector>>, AppError> {
    let cancel = Cancel::default();
    // If the client goes away, this future is dropped and the runs are stopped.
    let _on_drop = cancel.on_drop();
    let runner = Runner::new(state).with_slot(slot);
    let handles: Vec<_> = (0..plan.methods.len())
        .map(|i| runner.spawn(plan, i, Collector::new(&plan.prepared.integrals, cancel.clone())))
        .collect();
    let mut finished = Vec::with_capacity(handles.len());
    for (i, handle) in handles.into_iter().enumerate() {
        finished.push(handle.await.map_err(|e| AppError::internal(format!("run {i}: {e}")))?);
    }
    Ok(finished)
}

/// The answer: one run view per method, with its series as columns and their verdicts.
fn respond(plan: Plan, finished: Vec<Finished<Collector>>) -> Result<SimulateResponse, AppError> {
    let mut runs = Vec::with_capacity(finished.len());
    for (i, finished) in finished.into_iter().enumerate() {
        let outcome = finished.outcome.map_err(|panic| {
            AppError::internal(format!(
                "internal error: the simulation of run {i} panicked: {panic}"
            ))
        })?;
        runs.push(RunView {
            method: plan.scene.methods[i].clone(),
            status: Status::of(&outcome),
            error: outcome.error.map(|e| e.to_string()),
            steps: outcome.steps,
            elapsed_ms: finished.elapsed_ms,
            cpu_ms: finished.cpu_ms,
            series: finished.observer.into_series(),
        });
    }
    Ok(SimulateResponse { scene: plan.scene, runs })
}
