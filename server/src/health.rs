//! [`Health`]: `GET /health`, which answers from the async runtime alone (no simulation
//! ever runs there), with the number of runs computing.

use crate::AppState;
use axum::Json;
use axum::extract::State;
use serde::Serialize;
use utoipa::ToSchema;

/// The answer of `GET /health`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct Health {
    /// Always `ok`.
    pub status: String,
    /// Simulation runs computing right now.
    pub active_runs: usize,
}

/// Says the server is up.
#[utoipa::path(get, path = "/health", tag = "nhlab", responses((status = 200, body = Health)))]
pub async fn health(State(state): State<AppState>) -> Json<Health> {
    Json(Health { status: "ok".into(), active_runs: state.active_runs() })
}
