//! The scorecard's views: [`ScorecardResponse`] (the answer of `POST /scorecard`), its
//! [`ScorecardScene`]s and [`ScorecardRun`]s (a [`RunSummary`] and its verdicts), and each
//! method's [`PropertiesView`] on each scene, measured as [`PROPERTIES_TEST`] says.

use crate::views::{GapView, MethodView, RunSummary, SceneView, VerdictView};
use nhlab_core::{Properties, StepFailure};
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// The answer of `POST /scorecard`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ScorecardResponse {
    /// How a series is judged `exact`, `bounded` or `drift`.
    pub criterion: String,
    /// How the properties are measured.
    pub properties_test: String,
    /// The methods, in the order of every scene's runs.
    pub methods: Vec<MethodView>,
    /// One entry per scene, in request order.
    pub scenes: Vec<ScorecardScene>,
    /// Each method's measured properties on each scene (scene-major order).
    pub properties: Vec<PropertiesView>,
}

/// One scene of the scorecard.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ScorecardScene {
    /// `system/preset`, made unique with `#i` (the scene's index) when repeated.
    pub id: String,
    /// The resolved scene (a `/simulate` body with these values reproduces the runs).
    pub scene: SceneView,
    /// One run per method.
    pub runs: Vec<ScorecardRun>,
}

/// One run of the scorecard: how it ended and its verdicts.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ScorecardRun {
    /// How the run went.
    #[serde(flatten)]
    pub summary: RunSummary,
    /// The verdict of each integral's error series (up to the failure for a failed run).
    pub verdicts: BTreeMap<String, VerdictView>,
    /// The gap of each series that has one (no values from `since` on), by integral.
    pub gaps: BTreeMap<String, GapView>,
}

/// A method's measured properties on one scene (from its start, with its step).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct PropertiesView {
    /// The method.
    pub method: MethodView,
    /// System id.
    pub system: String,
    /// The scene's id (as in `scenes[].id`).
    pub scene: String,
    /// One step, flip the velocity, one step, flip back returns the start (null: the
    /// measurement failed, see `error`).
    pub reversible: Option<bool>,
    /// One step h, then one step −h, returns the start (`Φ_{−h} ∘ Φ_h = id`, what a
    /// composition needs).
    pub symmetric: Option<bool>,
    /// The three fibration checks pass (null where the fibration is not defined: outside the
    /// paper's class).
    pub preserves_fibration: Option<bool>,
    /// Largest relative round-trip defect (reversible when ≤ 1e-11).
    pub reversibility_defect: Option<f64>,
    /// Largest relative `Φ_{−h} ∘ Φ_h` defect (symmetric when ≤ 1e-11).
    pub symmetry_defect: Option<f64>,
    /// Largest driver change caused by a passenger change (≤ 1e-12 to pass).
    pub driver_coupling: Option<f64>,
    /// Largest reduced-state change caused by a shift along a force-free fiber (≤ 1e-12).
    pub fiber_coupling: Option<f64>,
    /// Largest discrete-constraint residual, at the step's end or midpoint (≤ 1e-12).
    pub constraint_defect: Option<f64>,
    /// Why the measurement failed (a step failed), or null.
    pub error: Option<String>,
}

/// How the properties are measured (see `nhlab_core::properties`).
pub const PROPERTIES_TEST: &str = "Measured from each scene's start with its step. \
    Reversible: one step, flip the velocity, one step, flip back returns the start to \
    1e-11·max(1, |state|), from the start and three later points. Symmetric: one step h, then \
    one step −h, returns the start to the same tolerance, from the same points. Preserves the \
    fibration (the paper's class only): \
    (1) the driver is blind to the passenger: a start with the same driver state and another \
    passenger gives the same driver state after 5 steps to 1e-12; (2) the reduced state is \
    blind to shifts along force-free passenger axes, to 1e-12 after 5 steps; (3) the method \
    imposes the constraint at every step's end or midpoint, to 1e-12 over 200 steps.";

impl PropertiesView {
    /// The view of `method`'s properties `measured` on scene `scene` of `system`.
    pub fn of(
        method: MethodView,
        system: &str,
        scene: &str,
        measured: Result<Properties, StepFailure>,
    ) -> Self {
        let finite = |x: f64| x.is_finite().then_some(x);
        let (p, error) = match measured {
            Ok(p) => (Some(p), None),
            Err(e) => (None, Some(format!("a step failed while measuring: {e}"))),
        };
        Self {
            method,
            system: system.to_owned(),
            scene: scene.to_owned(),
            reversible: p.map(|p| p.reversible),
            symmetric: p.map(|p| p.symmetric),
            preserves_fibration: p.filter(|p| p.fibration_measured).map(|p| p.preserves_fibration),
            reversibility_defect: p.and_then(|p| finite(p.reversibility_defect)),
            symmetry_defect: p.and_then(|p| finite(p.symmetry_defect)),
            driver_coupling: p.and_then(|p| finite(p.driver_coupling)),
            fiber_coupling: p.and_then(|p| finite(p.fiber_coupling)),
            constraint_defect: p.and_then(|p| finite(p.constraint_defect)),
            error,
        }
    }

    /// The view of a method that has no step for the scene's system: nothing measured.
    pub fn not_applicable(method: MethodView, system: &str, scene: &str) -> Self {
        Self {
            method,
            system: system.to_owned(),
            scene: scene.to_owned(),
            reversible: None,
            symmetric: None,
            preserves_fibration: None,
            reversibility_defect: None,
            symmetry_defect: None,
            driver_coupling: None,
            fiber_coupling: None,
            constraint_defect: None,
            error: Some("the method has no step for this system".into()),
        }
    }
}
