//! [`sweep`]: the `POST /sweep` handler. The request is checked into its cells
//! ([`Sweep::check`]) off the runtime, admitted as one simulation, and computed by one worker
//! per core on the blocking pool, each taking the next cell until none is left. The answer is
//! one JSON document (the rows by cell, then method), CSV (`Accept: text/csv`), both written
//! into the answer as the cells complete ([`answer`](crate::sweep::answer)), or a stream
//! (`Accept: text/event-stream`: `start`, a `cell` event as each cell completes, `progress`,
//! `done`). When the client goes away the workers stop within a cell's current run.

use crate::compute::{BudgetGuard, Cancel, Delivery, Slot, lower_priority, millis, time_limit};
use crate::error::{AppError, ErrorBody};
use crate::json_object::JsonObject;
use crate::observers::sse_event;
use crate::request::SweepRequest;
use crate::routes::simulate::{Answer, wants_stream};
use crate::state::AppState;
use crate::sweep::Sweep;
use crate::sweep::answer::{AnswerBody, Encoder, Format};
use crate::views::{RowStatus, ShutdownEvent, SweepCell, SweepDone, SweepProgress, SweepResponse};
use axum::body::{Body, Bytes};
use axum::extract::State;
use axum::http::{HeaderMap, header};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use futures_util::StreamExt;
use std::convert::Infallible;
use std::sync::Arc;
use std::sync::atomic::AtomicUsize;
use std::time::Instant;
use tokio::sync::mpsc;
use tokio_stream::wrappers::ReceiverStream;

/// Sweeps a scene over 1 to 3 axes: every method on every cell, a row each.
#[utoipa::path(
    post,
    path = "/sweep",
    tag = "nhlab",
    request_body = SweepRequest,
    responses(
        (status = 200, description = "One row per cell × method, by cell then method: the \
            cell's axis values, status, error, steps, cpu_ms, Newton iterations and each \
            integral's verdict, with the `/simulate` body of the row. With `Accept: text/csv`, \
            the same rows as CSV; with `Accept: text/event-stream`, server-sent events: \
            `start` (SweepHead), `cell` (SweepCell) as each cell completes, `progress` \
            (SweepProgress), `done` (SweepDone), or `shutdown` (ShutdownEvent).",
            content(
                (SweepResponse = "application/json"),
                (String = "text/csv"),
                (String = "text/event-stream"),
            )),
        (status = 400, description = "The body is not valid JSON of the right shape", body = ErrorBody),
        (status = 413, description = "The body is too large", body = ErrorBody),
        (status = 415, description = "The body was not sent with `Content-Type: application/json`", body = ErrorBody),
        (status = 422, description = "A field is wrong (the error names it, e.g. \
            `axes[0].path`), or the sweep is over a limit (cells, steps, answer size, CPU time \
            estimated against max_request_seconds)", body = ErrorBody),
        (status = 500, description = "Internal error", body = ErrorBody),
        (status = 503, description = "Every simulation slot is taken, or the server is \
            shutting down; retry after `Retry-After` seconds", body = ErrorBody,
            headers(("Retry-After" = u32, description = "Seconds to wait before retrying"))),
    )
)]
pub async fn sweep(
    State(state): State<AppState>,
    headers: HeaderMap,
    JsonObject(req): JsonObject<SweepRequest>,
) -> Result<Response, AppError> {
    let csv = wants_csv(&headers);
    let delivery = if !csv && wants_stream(&headers) { Delivery::Stream } else { Delivery::Json };
    let sweep = {
        let (config, caches) = (state.config.clone(), state.caches.clone());
        state
            .check(move |checking| {
                let axis = move |scene: &nhlab_core::Scene| caches.latitude(scene);
                Sweep::check(&req, &config, delivery, &axis, &|| checking.stop())
            })
            .await?
    };
    let sweep = Arc::new(sweep);
    let rows = sweep.cells.len() * sweep.head.methods.len();
    let summary =
        format!("sweep cells={} rows={rows} steps={}", sweep.cells.len(), sweep.total_steps);
    tracing::Span::current().record("scene", summary.as_str());
    let (slot, budget) = state.admit(sweep.held_bytes(delivery))?;
    let cancel = Cancel::default();
    let on_drop = cancel.on_drop();
    if delivery == Delivery::Stream {
        let rx = start(&state, &sweep, slot, &cancel, |cell| cell);
        return Ok(stream(state, sweep, rx, cancel, on_drop, budget));
    }
    // Each cell's rows are encoded by the worker that computed them and written into the
    // answer in cell order as they arrive: the rows are never all held.
    let format = if csv { Format::Csv } else { Format::Json };
    let encoder = Encoder::new(&sweep.head, format);
    let capacity = usize::try_from(sweep.answer_bytes()).unwrap_or(usize::MAX);
    let mut body = AnswerBody::new(&sweep.head, format, capacity)?;
    let mut rx = start(&state, &sweep, slot.clone(), &cancel, move |cell| {
        let text = encoder.cell(&cell);
        (cell.cell, text)
    });
    while let Some((c, text)) = rx.recv().await {
        body.push(c, text?);
    }
    let answer = Answer { body: body.finish(sweep.cells.len())?, _budget: budget };
    drop((slot, on_drop));
    let kind = if csv { "text/csv; charset=utf-8" } else { "application/json" };
    Ok(([(header::CONTENT_TYPE, kind)], Body::from(Bytes::from_owner(answer))).into_response())
}

/// Whether the client asked for CSV: `text/csv` in `Accept`, with a quality above 0.
fn wants_csv(headers: &HeaderMap) -> bool {
    headers
        .get_all(header::ACCEPT)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .flat_map(|v| v.split(','))
        .any(|range| {
            let mut parts = range.split(';').map(str::trim);
            parts.next().is_some_and(|m| m.eq_ignore_ascii_case("text/csv"))
                && !parts.any(|p| p.replace(' ', "").eq_ignore_ascii_case("q=0"))
        })
}

/// Starts one worker per core (at most one per cell) on the blocking pool; each holds the
/// slot until it ends. The cells arrive on the returned channel as they complete, each as
/// `encode` makes it (by the worker: encoding is CPU work too).
fn start<T: Send + 'static>(
    state: &AppState,
    sweep: &Arc<Sweep>,
    slot: Slot,
    cancel: &Cancel,
    encode: impl Fn(SweepCell) -> T + Clone + Send + 'static,
) -> mpsc::Receiver<T> {
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    let workers = cores.min(sweep.cells.len()).max(1);
    let (tx, rx) = mpsc::channel(2 * workers);
    let order: Arc<Vec<usize>> = Arc::new((0..sweep.cells.len()).collect());
    let next = Arc::new(AtomicUsize::new(0));
    let limit = time_limit(&state.config);
    for _ in 0..workers {
        let (sweep, order, next, cancel, tx, encode) = (
            sweep.clone(),
            order.clone(),
            next.clone(),
            cancel.clone(),
            tx.clone(),
            encode.clone(),
        );
        let (guard, slot, caches) = (state.run_guard(), slot.clone(), state.caches.clone());
        tokio::task::spawn_blocking(move || {
            let (_guard, _slot) = (guard, slot);
            lower_priority();
            let axis = |scene: &nhlab_core::Scene| caches.latitude(scene);
            let limits = (&cancel, Some(limit));
            sweep.work(&order, &next, limits, &axis, &mut |cell| {
                tx.blocking_send(encode(cell)).is_ok()
            });
        });
    }
    rx
}

/// The stream: `start`, then each cell as it completes, `progress` every
/// `report_every`, and `done` (or `shutdown`).
fn stream(
    state: AppState,
    sweep: Arc<Sweep>,
    mut cells: mpsc::Receiver<SweepCell>,
    cancel: Cancel,
    on_drop: crate::compute::CancelOnDrop,
    budget: BudgetGuard,
) -> Response {
    let (tx, rx) = mpsc::channel::<Event>(64);
    let _ = tx.try_send(sse_event("start", &sweep.head));
    let every = state.config.report_every;
    tokio::spawn(async move {
        let started = Instant::now();
        let (total, mut done, mut failed, mut invalid) = (sweep.cells.len(), 0, 0, 0);
        let mut tick = tokio::time::interval_at(tokio::time::Instant::now() + every, every);
        let shutdown = state.shutdown_requested();
        tokio::pin!(shutdown);
        let mut shutting_down = false;
        loop {
            let event = tokio::select! {
                cell = cells.recv() => match cell {
                    Some(cell) => {
                        done += 1;
                        failed += cell.rows.iter().filter(|r| r.status == RowStatus::Failed).count();
                        invalid += cell.rows.iter().filter(|r| r.status == RowStatus::Invalid).count();
                        sse_event("cell", &cell)
                    }
                    None => break,
                },
                _ = tick.tick() => {
                    let elapsed_ms = millis(started.elapsed());
                    sse_event("progress", &SweepProgress { cells_done: done, cells: total, elapsed_ms })
                }
                () = &mut shutdown, if !shutting_down => {
                    shutting_down = true;
                    cancel.cancel();
                    continue;
                }
            };
            if tx.send(event).await.is_err() {
                cancel.cancel();
            }
        }
        let elapsed_ms = millis(started.elapsed());
        let last = if shutting_down || done < total {
            let error = if shutting_down {
                "the server is shutting down: the sweep was stopped"
            } else {
                "the sweep was stopped"
            };
            sse_event("shutdown", &ShutdownEvent { error: error.into(), runs: done, elapsed_ms })
        } else {
            let rows = total * sweep.head.methods.len();
            sse_event("done", &SweepDone { cells: total, rows, failed, invalid, elapsed_ms })
        };
        let _ = tx.send(last).await;
    });
    let body = ReceiverStream::new(rx).map(move |ev| {
        // The body owns the guards: dropping it (the client left) stops the workers and gives
        // back the budget.
        let _alive = (&on_drop, &budget);
        Ok::<_, Infallible>(ev)
    });
    Sse::new(body).keep_alive(KeepAlive::default()).into_response()
}
