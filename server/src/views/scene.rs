//! [`SceneView`]: the resolved scene as the API reports it (the JSON response's `scene`, the
//! stream's `scene` event): every field after presets and defaults were applied.

use crate::request::SystemField;
use crate::views::{MethodView, PaperClassView};
use nhlab_core::{Method, PreparedScene};
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// A resolved scene.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SceneView {
    /// System id, or the system given as formulas (its parameters at their values here).
    #[schema(schema_with = crate::request::schemas::system)]
    pub system: SystemField,
    /// The preset it started from (null for a system given as formulas).
    pub preset: Option<String>,
    /// Every parameter of the system with its value.
    pub params: BTreeMap<String, f64>,
    /// Initial configuration.
    pub q: Vec<f64>,
    /// Initial velocity.
    pub v: Vec<f64>,
    /// Step size.
    pub step: f64,
    /// Final time.
    pub t_end: f64,
    /// Steps per run, `⌊t_end/step + 1e-9⌋`.
    pub steps: u64,
    /// The methods, in run order (a run's index is its place here).
    pub methods: Vec<MethodView>,
    /// The integrals measured.
    pub integrals: Vec<String>,
    /// Buckets per series (at most; fewer when there are fewer samples).
    pub points: usize,
    /// Whether the system is in the paper's class as nhlab finds it (the class's steps run,
    /// and E, h and the latitude are defined), and as what.
    pub paper_class: PaperClassView,
}

impl SceneView {
    /// `system/preset`, or the name of a system given as formulas: for ids, logs and labels.
    pub fn label(&self) -> String {
        match &self.preset {
            Some(preset) => format!("{}/{preset}", self.system),
            None => self.system.to_string(),
        }
    }

    /// The view of a prepared scene run with `methods` and `points`.
    pub fn of(prepared: &PreparedScene, methods: &[Method], points: usize) -> Self {
        let scene = &prepared.scene;
        Self {
            system: match scene.system.custom() {
                None => SystemField::Id(scene.system.id().to_owned()),
                Some(c) => SystemField::of(&c.spec_at_values()),
            },
            preset: scene.preset.map(str::to_owned),
            params: scene.named_params().into_iter().map(|(n, v)| (n.to_owned(), v)).collect(),
            q: scene.q.clone(),
            v: scene.v.clone(),
            step: scene.step,
            t_end: scene.t_end,
            steps: scene.steps(),
            methods: methods.iter().map(MethodView::of).collect(),
            integrals: prepared.integrals.iter().map(|&i| prepared.integral_name(i)).collect(),
            points,
            paper_class: PaperClassView::of(scene),
        }
    }
}
