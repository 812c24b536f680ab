//! [`SimulateResponse`]: the JSON answer of `POST /simulate`, the resolved scene and one
//! [`RunView`] per method.

use crate::views::{RunView, SceneView};
use serde::Serialize;
use utoipa::ToSchema;

/// The JSON answer of `POST /simulate`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SimulateResponse {
    /// The resolved scene.
    pub scene: SceneView,
    /// One run per method, in the order of `scene.methods`.
    pub runs: Vec<RunView>,
}
