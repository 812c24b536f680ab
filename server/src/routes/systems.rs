//! [`systems`]: the `GET /systems` handler, the listing of [`SystemsResponse`] with this
//! server's limits.

use crate::state::AppState;
use crate::views::SystemsResponse;
use axum::Json;
use axum::extract::State;

/// Lists the systems, methods and limits.
#[utoipa::path(get, path = "/systems", tag = "nhlab", responses((status = 200, body = SystemsResponse)))]
pub async fn systems(State(state): State<AppState>) -> Json<SystemsResponse> {
    Json(SystemsResponse::new(&state.config))
}
