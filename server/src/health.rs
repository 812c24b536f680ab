//! [`Health`]: `GET /health`, which answers from the async runtime alone (no simulation
//! ever runs there), with the simulation slots taken, the runs computing and the caches'
//! counters.

use crate::{AppState, CachesStats};
use axum::Json;
use axum::extract::State;
use serde::Serialize;
use utoipa::ToSchema;

/// The answer of `GET /health`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct Health {
    /// `ok`, or `shutting_down` (streams are ending, no new simulations).
    pub status: String,
    /// Simulations (admitted requests) holding a slot right now.
    pub simulations: usize,
    /// Most simulations at once; one more gets 503.
    pub max_simulations: usize,
    /// Simulation runs computing right now (one per method of a simulation).
    pub active_runs: usize,
    /// Hits, misses and entries of the latitude-axis and reference caches.
    pub cache: CachesStats,
}

/// Says the server is up, and how busy.
#[utoipa::path(get, path = "/health", tag = "nhlab", responses((status = 200, body = Health)))]
pub async fn health(State(state): State<AppState>) -> Json<Health> {
    let status = if state.is_shutting_down() { "shutting_down" } else { "ok" };
    Json(Health {
        status: status.into(),
        simulations: state.busy_slots(),
        max_simulations: state.config.max_simulations,
        active_runs: state.active_runs(),
        cache: state.caches.stats(),
    })
}
