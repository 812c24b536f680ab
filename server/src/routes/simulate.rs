//! [`simulate`]: the `POST /simulate` handler. It reads and checks the request, then answers
//! with one JSON document ([`SimulateResponse`], each run kept by a [`JsonCollector`]) or, for
//! `Accept: text/event-stream`, with the event [`stream`]. The
//! methods run in parallel on the blocking pool, once the request is admitted
//! ([`AppState::admit`]: a bounded number of simulations at once).

use crate::compute::{
    BudgetGuard, Cancel, Delivery, Finished, JSON_BYTES_PER_POINT, Plan, Slot, off_runtime,
};
use crate::error::{AppError, ErrorBody};
use crate::json_object::JsonObject;
use crate::observers::{IntegralNames, JsonCollector};
use crate::request::SimulateRequest;
use crate::routes::simulate_stream::stream;
use crate::state::AppState;
use crate::views::{RunView, SimulateResponse};
use axum::body::{Body, Bytes};
use axum::extract::State;
use axum::http::{HeaderMap, header};
use axum::response::{IntoResponse, Response};

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
        (status = 400, description = "The body is not valid JSON of the right shape", body = ErrorBody),
        (status = 413, description = "The body is too large", body = ErrorBody),
        (status = 415, description = "The body was not sent with `Content-Type: application/json`", body = ErrorBody),
        (status = 422, description = "A field is wrong (the error names it), or the work is \
            estimated over max_request_seconds of CPU (the estimate in the message)", body = ErrorBody),
        (status = 500, description = "Internal error", body = ErrorBody),
        (status = 503, description = "Every simulation slot is taken, or the server is \
            shutting down; retry after `Retry-After` seconds", body = ErrorBody,
            headers(("Retry-After" = u32, description = "Seconds to wait before retrying"))),
    )
)]
pub async fn simulate(
    State(state): State<AppState>,
    headers: HeaderMap,
    JsonObject(req): JsonObject<SimulateRequest>,
) -> Result<Response, AppError> {
    let delivery = if wants_stream(&headers) { Delivery::Stream } else { Delivery::Json };
    let plan = {
        let (config, caches) = (state.config.clone(), state.caches.clone());
        state.check(move |_| Plan::resolve(&req, &config, &caches, delivery)).await?
    };
    let scene = &plan.scene;
    let summary = format!(
        "{} steps={} methods={} {:?}",
        scene.label(),
        scene.steps,
        scene.methods.len(),
        delivery
    );
    tracing::Span::current().record("scene", summary.as_str());
    let (slot, budget) = state.admit(plan.held_bytes(JSON_BYTES_PER_POINT))?;
    match delivery {
        Delivery::Stream => Ok(stream(&state, plan, slot, budget)),
        Delivery::Json | Delivery::JsonOnly => {
            let finished = run(&state, &plan, slot.clone()).await?;
            // Building the columns, the verdicts and ~1 MB of JSON is CPU work: off the runtime,
            // within the slot, and with the budget going along whatever happens to the client.
            let answer = off_runtime(move || {
                let _slot = slot;
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
                Ok(Answer { body, _budget: budget })
            })
            .await?;
            let body = Body::from(Bytes::from_owner(answer));
            Ok(([(header::CONTENT_TYPE, "application/json")], body).into_response())
        }
    }
}

/// Whether the client asked for server-sent events: `text/event-stream` in `Accept` with a
/// quality above 0 and not below that of `application/json` (or of the ranges that cover it:
/// `application/*`, `*/*`); a tie streams.
pub(crate) fn wants_stream(headers: &HeaderMap) -> bool {
    let quality = |wanted: &str| {
        headers
            .get_all(header::ACCEPT)
            .iter()
            .filter_map(|v| v.to_str().ok())
            .flat_map(|v| v.split(','))
            .filter_map(|range| {
                let mut parts = range.split(';').map(str::trim);
                let media = parts.next()?;
                media.eq_ignore_ascii_case(wanted).then(|| {
                    parts
                        .filter_map(|p| p.split_once('='))
                        .find(|(k, _)| k.trim().eq_ignore_ascii_case("q"))
                        .map_or(1.0, |(_, q)| q.trim().parse::<f32>().unwrap_or(0.0))
                })
            })
            .fold(None, |best: Option<f32>, q| Some(best.map_or(q, |b| b.max(q))))
    };
    // JSON's quality: its own, else that of `application/*`, else that of `*/*`.
    let json = quality("application/json").or_else(|| quality("application/*"));
    match quality("text/event-stream") {
        Some(sse) if sse > 0.0 => sse >= json.or_else(|| quality("*/*")).unwrap_or(0.0),
        _ => false,
    }
}

/// A JSON answer and its share of the budget of answers in flight, given back when the
/// answer's memory is: once the connection has written its last byte, or is dropped.
pub(crate) struct Answer {
    pub(crate) body: Vec<u8>,
    pub(crate) _budget: BudgetGuard,
}

impl AsRef<[u8]> for Answer {
    fn as_ref(&self) -> &[u8] {
        &self.body
    }
}

/// Runs every method of `plan` in parallel and waits for them.
async fn run(
    state: &AppState,
    plan: &Plan,
    slot: Slot,
) -> Result<Vec<Finished<JsonCollector>>, AppError> {
    let cancel = Cancel::default();
    // If the client goes away, this future is dropped and the runs are stopped.
    let _on_drop = cancel.on_drop();
    let runner = state.runner().with_slot(slot);
    let handles: Vec<_> = (0..plan.methods.len())
        .map(|i| {
            let names = IntegralNames::of(&plan.prepared);
            runner.spawn(
                plan,
                i,
                JsonCollector::new(&plan.prepared.integrals, names, cancel.clone()).recording(plan),
            )
        })
        .collect();
    let mut finished = Vec::with_capacity(handles.len());
    for (i, handle) in handles.into_iter().enumerate() {
        finished.push(handle.await.map_err(|e| AppError::internal(format!("run {i}: {e}")))?);
    }
    Ok(finished)
}

/// The answer: one run view per method, with its series as columns and their verdicts.
fn respond(
    plan: Plan,
    finished: Vec<Finished<JsonCollector>>,
) -> Result<SimulateResponse, AppError> {
    let mut runs = Vec::with_capacity(finished.len());
    for (i, finished) in finished.into_iter().enumerate() {
        let summary = finished.summary(plan.scene.methods[i].clone()).map_err(|panic| {
            AppError::internal(format!(
                "internal error: the simulation of run {i} panicked: {panic}"
            ))
        })?;
        let mut observer = finished.observer;
        let (observables, section) = (observer.take_observables(), observer.take_section());
        runs.push(RunView { summary, series: observer.into_series(), observables, section });
    }
    Ok(SimulateResponse { scene: plan.scene, runs })
}
