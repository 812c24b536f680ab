//! nhlab-server: nhlab's HTTP API and page.
//!
//! `GET /systems` lists what can be simulated; `POST /simulate` runs methods on a scene and
//! answers with the error series of the first integrals, as one JSON document or as
//! server-sent events; `POST /scorecard` judges methods × scenes; `POST /work-precision`
//! measures cost against accuracy; `POST /sweep` maps verdicts over parameter grids; `GET /openapi.json` describes it all; `GET /health`; `/`
//! serves the embedded page. [`app`] builds the router, so tests run it in-process.
//!
//! The crate by folder, each depending only on those listed before it:
//! - [`config`], [`error`]: the limits ([`Config`]) and the error responses ([`AppError`]);
//! - [`views`]: every response view, serialized as sent; a run is reported everywhere by one
//!   [`RunSummary`];
//! - [`request`]: the request bodies;
//! - [`compute`]: where simulations run, off the async runtime: a request checked into a
//!   [`Plan`], its admission [`Slot`], the [`Runner`] (one method per task on the blocking
//!   pool, all in parallel, stopped through a [`Cancel`] flag when the client goes away) and
//!   the [`Caches`] of latitude axes and references kept across requests;
//! - [`observers`]: what watches a run: [`JsonCollector`] for a JSON answer, [`SseEmitter`]
//!   for server-sent events;
//! - [`state`]: [`AppState`], shared by the handlers; at most `max_simulations` requests
//!   compute at once, each holding a [`Slot`] ([`AppState::admit`]); one more gets 503;
//! - [`sweep`]: parameter sweeps, checked into cells and computed by workers, for
//!   `POST /sweep` and for `nhlab sweep` (shards, their merge);
//! - [`json_object`]: [`JsonObject`], the extractor every body goes through;
//! - [`routes`]: the handlers;
//! - [`openapi`]: the document, gathered from all of the above;
//! - [`serve`]: the connection layer the binary serves [`app`] with: timeouts on request
//!   heads and stalled writes, a cap on connections, a shutdown that waits only for
//!   requests in flight.
#![warn(missing_docs)]

pub mod compute;
pub mod config;
pub mod error;
pub mod json_object;
pub mod observers;
pub mod openapi;
pub mod request;
pub mod routes;
pub mod serve;
pub mod state;
pub mod sweep;
pub mod views;

pub use compute::{Caches, Cancel, CancelOnDrop, Delivery, Plan, Runner, Slot, ThreadClock};
pub use config::Config;
pub use error::{AppError, ErrorBody};
pub use json_object::JsonObject;
pub use observers::{JsonCollector, SseEmitter, Verdicts};
pub use openapi::{ApiDoc, openapi_json};
pub use request::{
    AxisRequest, MethodRequest, SceneSpec, ScorecardRequest, SimulateRequest, SweepRequest,
    WorkPrecisionRequest,
};
pub use routes::health::health;
pub use routes::page::{Page, page};
pub use routes::scorecard::scorecard;
pub use routes::simulate::simulate;
pub use routes::simulate_stream::stream;
pub use routes::systems::systems;
pub use routes::work_precision::work_precision;
pub use state::AppState;
pub use views::{
    CRITERION, CacheStats, CachesStats, FormulasHealth, Health, LimitsView, MethodInfoView,
    MethodView, PaperScene, ParamView, PresetView, RunSummary, RunView, SceneView,
    ScorecardResponse, SeriesView, SimulateResponse, Status, SystemView, SystemsResponse,
    VerdictView, WorkPrecisionResponse,
};

use axum::Router;
use axum::body::Body;
use axum::extract::DefaultBodyLimit;
use axum::handler::Handler;
use axum::http::{HeaderValue, Method, Request, Uri, header};
use axum::response::IntoResponse;
use axum::routing::{get, post};
use tower_http::LatencyUnit;
use tower_http::catch_panic::CatchPanicLayer;
use tower_http::compression::CompressionLayer;
use tower_http::cors::{AllowOrigin, CorsLayer};
use tower_http::set_header::SetResponseHeaderLayer;
use tower_http::trace::{DefaultOnResponse, TraceLayer};
use tracing::Level;

/// The whole app: API, page, request logging (one line per request), a 500 JSON error for
/// a handler that panics, `X-Content-Type-Options: nosniff` on every response, and CORS
/// headers only for the configured origins.
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
        .route("/sweep", post(routes::sweep::sweep))
        .route("/openapi.json", get(openapi_json))
        .fallback(page.layer(CompressionLayer::new()))
        .method_not_allowed_fallback(|method: Method, uri: Uri| async move {
            AppError::method_not_allowed(method.as_str(), uri.path())
        })
        .layer(DefaultBodyLimit::max(state.config.max_body_bytes))
        .layer(CatchPanicLayer::custom(|_| {
            AppError::internal("internal error: the request handler panicked").into_response()
        }))
        .layer(SetResponseHeaderLayer::overriding(
            header::X_CONTENT_TYPE_OPTIONS,
            HeaderValue::from_static("nosniff"),
        ));
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
