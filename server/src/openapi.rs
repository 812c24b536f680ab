//! [`ApiDoc`]: the OpenAPI document served at `GET /openapi.json`, gathered from the
//! handlers' paths and the views' schemas. Ids (systems, methods, integrals) are listed as
//! enums and parameter bounds as minimum/maximum, taken from the core's registry
//! (`request/schemas.rs`), so a fuzzer generates meaningful bodies.
//! This module reads every other; only the router reads it.

use crate::error::ErrorBody;
use crate::routes::{health, scorecard, simulate, sweep, systems, work_precision};
use crate::views::{
    DoneEvent, ObservablesEvent, PointsEvent, ProgressEvent, RunEvent, SceneView, SectionEvent,
    ShutdownEvent, SweepCell, SweepDone, SweepHead, SweepProgress, VerdictView,
};
use axum::Json;
use utoipa::OpenApi;

/// The API's OpenAPI document.
#[derive(OpenApi)]
#[openapi(
    info(
        title = "nhlab",
        description = "Long-time behaviour of nonholonomic integrators (Modin & Verdier): \
            test systems, the integrators of the literature and the error of every first \
            integral over time, each judged exact, bounded or drift; a scorecard of methods × \
            scenes with the methods' measured reversibility and fibration preservation; \
            work–precision: run time against final error for each method and step size; sweeps: verdicts over grids of parameters, steps, \
            initial states and method parameters."
    ),
    paths(
        simulate::simulate,
        scorecard::scorecard,
        work_precision::work_precision,
        sweep::sweep,
        systems::systems,
        health::health,
        openapi_json
    ),
    components(schemas(
        SceneView,
        VerdictView,
        ProgressEvent,
        PointsEvent,
        ObservablesEvent,
        SectionEvent,
        RunEvent,
        DoneEvent,
        ShutdownEvent,
        SweepHead,
        SweepCell,
        SweepProgress,
        SweepDone,
        ErrorBody
    ))
)]
pub struct ApiDoc;

/// This document.
#[utoipa::path(get, path = "/openapi.json", tag = "nhlab", responses((status = 200, description = "OpenAPI 3.1 document")))]
pub async fn openapi_json() -> Json<utoipa::openapi::OpenApi> {
    Json(ApiDoc::openapi())
}
