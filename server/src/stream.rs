//! [`stream`]: the server-sent-event answer to `POST /simulate` with
//! `Accept: text/event-stream`.
//!
//! The runs report into a bounded channel; the response body reads it. A coordinating task
//! sends each run's last `points` and its `run` event as it ends, then `done`. When the
//! client goes away the body is dropped, which sets the request's [`Cancel`] flag: the runs
//! see it within [`PROGRESS_EVERY`](crate::runner::PROGRESS_EVERY) steps and stop.

use crate::events::{DoneEvent, RunEvent, event};
use crate::{AppState, Cancel, Plan, Reporter, Runner, Status};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use futures_util::StreamExt;
use futures_util::stream::FuturesUnordered;
use std::convert::Infallible;
use std::time::{Duration, Instant};
use tokio::sync::mpsc;
use tokio_stream::wrappers::ReceiverStream;

/// Events buffered between the runs and the client.
const CHANNEL: usize = 64;

/// Starts the runs of `plan` and answers with their event stream.
pub fn stream(state: &AppState, plan: Plan) -> Response {
    let (tx, rx) = mpsc::channel::<Event>(CHANNEL);
    let cancel = Cancel::default();
    let on_drop = cancel.on_drop();
    // The channel is empty: the scene event always fits.
    let _ = tx.try_send(event("scene", &plan.scene));
    let every = state.config.report_every;
    tokio::spawn(coordinate(Runner::new(state), plan, every, tx, cancel));
    let body = ReceiverStream::new(rx).map(move |ev| {
        // The body owns the guard: dropping it (the client left) cancels the runs.
        let _alive = &on_drop;
        Ok::<_, Infallible>(ev)
    });
    Sse::new(body).keep_alive(KeepAlive::default()).into_response()
}

async fn coordinate(
    runner: Runner,
    plan: Plan,
    every: Duration,
    tx: mpsc::Sender<Event>,
    cancel: Cancel,
) {
    let start = Instant::now();
    let steps = plan.scene.steps;
    let mut runs: FuturesUnordered<_> = (0..plan.methods.len())
        .map(|i| {
            let reporter = Reporter::new(i, steps, every, tx.clone(), cancel.clone());
            let handle = runner.spawn(&plan, i, reporter);
            async move { (i, handle.await) }
        })
        .collect();
    let mut failed = 0;
    while let Some((i, joined)) = runs.next().await {
        let (mut events, mut verdicts) = (Vec::new(), Default::default());
        let (status, error, steps, elapsed_ms) = match joined {
            Ok(mut finished) => {
                events = finished.observer.take_points();
                verdicts = finished.observer.verdicts();
                match finished.outcome {
                    Ok(outcome) => (
                        Status::of(&outcome),
                        outcome.error.map(|e| e.to_string()),
                        outcome.steps,
                        finished.elapsed_ms,
                    ),
                    Err(panic) => (
                        Status::Failed,
                        Some(format!("internal error: the simulation panicked: {panic}")),
                        0,
                        finished.elapsed_ms,
                    ),
                }
            }
            Err(e) => (Status::Failed, Some(format!("internal error: {e}")), 0, 0.0),
        };
        failed += usize::from(status == Status::Failed);
        let method = plan.scene.methods[i].clone();
        let run = RunEvent { run: i, method, status, error, steps, elapsed_ms, verdicts };
        events.push(event("run", &run));
        for ev in events {
            if tx.send(ev).await.is_err() {
                cancel.cancel();
            }
        }
    }
    let elapsed_ms = (start.elapsed().as_secs_f64() * 1e6).round() / 1e3;
    let done = DoneEvent { runs: plan.methods.len(), failed, elapsed_ms };
    let _ = tx.send(event("done", &done)).await;
}
