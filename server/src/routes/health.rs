//! [`health`]: the `GET /health` handler, which answers from the async runtime alone (no
//! simulation ever runs there) with the simulation slots taken, the runs computing, the bytes
//! the answers in flight hold, the caches' counters and whether formulas run as machine code.

use crate::state::AppState;
use crate::views::Health;
use axum::Json;
use axum::extract::State;

/// Says the server is up, and how busy.
#[utoipa::path(get, path = "/health", tag = "nhlab", responses((status = 200, body = Health)))]
pub async fn health(State(state): State<AppState>) -> Json<Health> {
    let status = if state.is_shutting_down() { "shutting_down" } else { "ok" };
    let (answer_bytes, max_inflight_bytes) = state.answers_in_flight();
    Json(Health {
        status: status.into(),
        simulations: state.busy_slots(),
        max_simulations: state.config.max_simulations,
        active_runs: state.active_runs(),
        answer_bytes,
        answer_bytes_peak: state.answers_peak(),
        max_inflight_bytes,
        cache: state.caches.stats(),
        // A lock and a clone once the first call has tried Cranelift (main does at startup).
        formulas: nhlab_core::formula::native_code_status().into(),
    })
}
