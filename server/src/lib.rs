//! nhlab-server: nhlab's HTTP API and page.
//!
//! `GET /systems` lists what can be simulated; `POST /simulate` runs methods on a scene and
//! answers with the error series of the first integrals, as one JSON document or as
//! server-sent events ([`stream()`]); `POST /scorecard` judges methods × scenes;
//! `POST /work-precision` measures cost against accuracy ([`work_precision()`]);
//! `GET /openapi.json` describes it all; `GET /health`; `/` serves the embedded page. [`app`]
//! builds the router, so tests run it in-process. Latitude axes and references are kept
//! across requests in [`Caches`].
//!
//! Simulations never run on the async runtime: each method of a request is one task on the
//! blocking pool ([`Runner`]), all in parallel, stopped through a [`Cancel`] flag when the
//! client goes away. At most `max_simulations` requests compute at once, each holding a
//! [`Slot`] ([`AppState::admit`]); one more gets 503. [`Config`] holds the limits.
#![warn(missing_docs)]

mod cache;
mod collector;
mod config;
mod error;
pub mod events;
mod health;
pub mod openapi;
mod page;
mod plan;
mod reporter;
mod request;
mod run_view;
pub mod runner;
mod scene_view;
pub mod scorecard;
mod series_view;
mod simulate;
mod slot;
mod state;
mod stream;
mod systems;
mod thread_clock;
mod verdict_view;
pub mod work_precision;

pub use cache::{CacheStats, Caches, CachesStats};
pub use collector::Collector;
pub use config::Config;
pub use error::{AppError, ErrorBody};
pub use health::{Health, health};
pub use openapi::{ApiDoc, openapi_json};
pub use page::{Page, page};
pub use plan::{Delivery, Plan};
pub use reporter::Reporter;
pub use request::{MethodRequest, SceneSpec, SimulateRequest};
pub use run_view::{RunView, Status};
pub use runner::{Cancel, CancelOnDrop, Runner};
pub use scene_view::{MethodView, SceneView};
pub use scorecard::{ScorecardRequest, ScorecardResponse, scorecard};
pub use series_view::SeriesView;
pub use simulate::{SimulateResponse, simulate};
pub use slot::Slot;
pub use state::AppState;
pub use stream::stream;
pub use systems::{
    LimitsView, MethodInfoView, PaperScene, ParamView, PresetView, SystemView, SystemsResponse,
    systems,
};
pub use thread_clock::ThreadClock;
pub use verdict_view::{CRITERION, VerdictView, Verdicts};
pub use work_precision::{WorkPrecisionRequest, WorkPrecisionResponse, work_precision};

use axum::Router;
use axum::body::Body;
use axum::extract::DefaultBodyLimit;
use axum::http::{HeaderValue, Method, Request, Uri, header};
use axum::response::IntoResponse;
use axum::routing::{get, post};
use tower_http::LatencyUnit;
use tower_http::catch_panic::CatchPanicLayer;
use tower_http::cors::{AllowOrigin, CorsLayer};
use tower_http::trace::{DefaultOnResponse, TraceLayer};
use tracing::Level;

/// The whole app: API, page, request logging (one line per request), a 500 JSON error for
/// a handler that panics, and CORS headers only for the configured origins.
pub fn app(state: AppState) -> Router {
    let cors = cors(&state.config.cors_origins);
    let trace = TraceLayer::new_for_http()
        .make_span_with(|req: &Request<Body>| {
            tracing::info_span!(
                "request",
                method = %req.method(),
                uri = %req.uri(),
                scene = tracing::field::Empty,
            )
        })
        .on_response(DefaultOnResponse::new().level(Level::INFO).latency_unit(LatencyUnit::Millis));
    let router = Router::new()
        .route("/health", get(health))
        .route("/systems", get(systems))
        .route("/simulate", post(simulate))
        .route("/scorecard", post(scorecard))
        .route("/work-precision", post(work_precision))
        .route("/openapi.json", get(openapi_json))
        .fallback(page)
        .method_not_allowed_fallback(|method: Method, uri: Uri| async move {
            AppError::method_not_allowed(method.as_str(), uri.path())
        })
        .layer(DefaultBodyLimit::max(state.config.max_body_bytes))
        .layer(CatchPanicLayer::custom(|_| {
            AppError::internal("internal error: the request handler panicked").into_response()
        }));
    let router = match cors {
        Some(cors) => router.layer(cors),
        None => router,
    };
    router.layer(trace).with_state(state)
}

/// CORS for `origins` (`*`: any), or none at all when the list is empty. Origins that are
/// not valid header values are skipped with a warning (the binary checks them at start).
fn cors(origins: &[String]) -> Option<CorsLayer> {
    if origins.is_empty() {
        return None;
    }
    let allow = if origins.iter().any(|o| o == "*") {
        AllowOrigin::any()
    } else {
        AllowOrigin::list(origins.iter().filter_map(|o| {
            HeaderValue::from_str(o)
                .inspect_err(|_| tracing::warn!(origin = %o, "invalid CORS origin, skipped"))
                .ok()
        }))
    };
    Some(
        CorsLayer::new()
            .allow_origin(allow)
            .allow_methods([Method::GET, Method::POST])
            .allow_headers([header::CONTENT_TYPE, header::ACCEPT]),
    )
}
