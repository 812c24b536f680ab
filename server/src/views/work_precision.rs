//! The views of `POST /work-precision`: [`WorkPrecisionResponse`], the [`ReferenceView`] the
//! errors are measured against and one [`WorkPrecisionRow`] per method × step.

use crate::views::{MethodView, SceneView, Status, ValuesView};
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// The answer of `POST /work-precision`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct WorkPrecisionResponse {
    /// The resolved scene (its `step` is the scene's own; each row has its step).
    pub scene: SceneView,
    /// The reference the final errors are measured against.
    pub reference: ReferenceView,
    /// One row per method × step, method by method, steps in the order given.
    pub rows: Vec<WorkPrecisionRow>,
}

/// The Dop853 reference solution at t_end (relative and absolute tolerance 1e-15; an angle ζ
/// kept near 0 by whole turns, restarting every time unit).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ReferenceView {
    /// Its compute time, in milliseconds (when it was computed, for a cached one).
    pub elapsed_ms: f64,
    /// Right-hand-side evaluations.
    pub evaluations: u32,
    /// Accepted steps.
    pub steps: u32,
    /// `|A(q) q̇|` at t_end: how far the reference drifted off the constraint.
    pub constraint_residual: f64,
    /// Whether it came from the server's cache (an earlier request for the same scene).
    pub cached: bool,
    /// Whether it is the system's exact solution (the vertical disk's), not Dop853's: then
    /// it costs nothing, and its evaluations and steps are 0.
    pub exact: bool,
    /// The observables asked for, at t_end; absent when none were.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>, example = json!({"x": 0.1}))]
    pub observables: Option<ValuesView>,
}

/// One method at one step.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct WorkPrecisionRow {
    /// The method.
    pub method: MethodView,
    /// The step used: the one asked for, rounded to t_end / steps.
    pub step: f64,
    /// Steps completed.
    pub steps: u64,
    /// The fastest repetition's wall time, in milliseconds.
    pub elapsed_ms: f64,
    /// `‖(q, q̇)(t_end) − reference‖∞`; null when the run failed.
    pub final_error: Option<f64>,
    /// Largest `|I − I(0)|` of each integral asked for; null when the run failed (or the
    /// latitude had no section crossing).
    pub max_error: BTreeMap<String, Option<f64>>,
    /// `ok` or `failed`.
    pub status: Status,
    /// Why it failed, or null.
    pub error: Option<String>,
    /// The observables asked for, at t_end (null values for a run that failed); absent when
    /// none were.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>, example = json!({"x": 0.1}))]
    pub observables: Option<ValuesView>,
}
