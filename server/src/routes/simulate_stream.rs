//! [`stream`]: the server-sent-event answer to `POST /simulate` with
//! `Accept: text/event-stream`.
//!
//! The runs report into a bounded channel through their [`SseEmitter`]s; the response body
//! reads it. Each run makes its last `points` and its `run` event on its own thread as it
//! ends; a coordinating task sends them, then `done`. When the client goes away the body is
//! dropped, which sets the request's [`Cancel`] flag: the runs see it within
//! [`PROGRESS_EVERY`](crate::compute::PROGRESS_EVERY) steps or a few milliseconds, whichever
//! comes first, and stop.
//!
//! The stream holds its simulation [`Slot`] until its runs have stopped and its last event is
//! sent. On shutdown ([`AppState::shut_down`]) the runs are stopped, their `run` events sent,
//! and a `shutdown` event ends the stream instead of `done`.

use crate::compute::{BudgetGuard, Cancel, Finished, Plan, Runner, Slot, millis};
use crate::observers::{IntegralNames, SseEmitter, sse_event};
use crate::state::AppState;
use crate::views::{DoneEvent, MethodView, RunEvent, RunSummary, ShutdownEvent, Status};
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

/// Starts the runs of `plan`, admitted with `slot` and `budget`, and answers with their event
/// stream.
pub fn stream(state: &AppState, plan: Plan, slot: Slot, budget: BudgetGuard) -> Response {
    let (tx, rx) = mpsc::channel::<Event>(CHANNEL);
    let cancel = Cancel::default();
    let on_drop = cancel.on_drop();
    // The channel is empty: the scene event always fits.
    let _ = tx.try_send(sse_event("scene", &plan.scene));
    let every = state.config.report_every;
    let runner = state.runner().with_slot(slot);
    tokio::spawn(coordinate(runner, state.clone(), plan, every, tx, cancel));
    let body = ReceiverStream::new(rx).map(move |ev| {
        // The body owns the guards: dropping it (the client left) cancels the runs and gives
        // back its share of the budget of answers in flight.
        let _alive = (&on_drop, &budget);
        Ok::<_, Infallible>(ev)
    });
    Sse::new(body).keep_alive(KeepAlive::default()).into_response()
}

async fn coordinate(
    runner: Runner,
    state: AppState,
    plan: Plan,
    every: Duration,
    tx: mpsc::Sender<Event>,
    cancel: Cancel,
) {
    let start = Instant::now();
    let steps = plan.scene.steps;
    let mut runs: FuturesUnordered<_> = (0..plan.methods.len())
        .map(|i| {
            let names = IntegralNames::of(&plan.prepared);
            let emitter = SseEmitter::new((i, steps), names, every, tx.clone(), cancel.clone())
                .recording(&plan);
            let method = plan.scene.methods[i].clone();
            let step = plan.prepared.scene.step;
            let handle =
                runner.spawn_then(&plan, i, emitter, move |run| last_events(run, method, step));
            async move { (i, handle.await) }
        })
        .collect();
    let mut failed = 0;
    let shutdown = state.shutdown_requested();
    tokio::pin!(shutdown);
    let mut shutting_down = false;
    loop {
        let next = tokio::select! {
            next = runs.next() => next,
            () = &mut shutdown, if !shutting_down => {
                // The runs see the flag at their next progress call, a few milliseconds away
                // (paced by the clock), and end as cancelled.
                shutting_down = true;
                cancel.cancel();
                continue;
            }
        };
        let Some((i, joined)) = next else { break };
        let (events, status) = joined.unwrap_or_else(|e| {
            let method = plan.scene.methods[i].clone();
            let summary = RunSummary::failed(method, format!("internal error: {e}"), 0.0, None);
            let run = RunEvent {
                run: i,
                summary,
                verdicts: Default::default(),
                gaps: Default::default(),
            };
            (vec![sse_event("run", &run)], Status::Failed)
        });
        failed += usize::from(status == Status::Failed);
        for ev in events {
            if tx.send(ev).await.is_err() {
                cancel.cancel();
            }
        }
    }
    let elapsed_ms = millis(start.elapsed());
    let runs = plan.methods.len();
    let last = if shutting_down {
        let error = "the server is shutting down: the runs were stopped".to_owned();
        sse_event("shutdown", &ShutdownEvent { error, runs, elapsed_ms })
    } else {
        sse_event("done", &DoneEvent { runs, failed, elapsed_ms })
    };
    let _ = tx.send(last).await;
    // The runner (and with it the slot) is dropped here, after the last event.
    drop(runner);
}

/// A run's last `points` events, its last `progress` and its `run` event, made on the run's
/// own thread as it ends (serializing them is CPU work, and the other runs may still be
/// computing).
fn last_events(
    mut finished: Finished<SseEmitter>,
    method: MethodView,
    step: f64,
) -> (Vec<Event>, Status) {
    let mut events = finished.observer.take_points();
    let ended = finished.outcome.as_ref().ok().map(|o| (o.steps, o.steps as f64 * step));
    events.push(finished.observer.final_progress(ended));
    let (verdicts, gaps) = (finished.observer.verdicts(), finished.observer.gaps());
    let summary = finished.summary(method.clone()).unwrap_or_else(|panic| {
        let error = format!("internal error: the simulation panicked: {panic}");
        RunSummary::failed(method, error, finished.elapsed_ms, finished.cpu_ms)
    });
    let status = summary.status;
    events.push(sse_event("run", &RunEvent { run: finished.index, summary, verdicts, gaps }));
    (events, status)
}
