//! [`ScorecardRequest`]: the body of `POST /scorecard`, methods × scenes, every field optional.

use crate::request::{MethodRequest, SceneSpec, schemas};
use serde::Deserialize;
use utoipa::ToSchema;

/// The body of `POST /scorecard`; every field is optional (`{}` is the paper's scorecard).
#[derive(Debug, Clone, Default, PartialEq, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct ScorecardRequest {
    /// Methods, as in `/simulate` (default: every registered method, the paper's five
    /// first).
    #[serde(default)]
    #[schema(schema_with = schemas::methods)]
    pub methods: Option<Vec<MethodRequest>>,
    /// Scenes, each like a `/simulate` body without `methods` and `points` (default: the
    /// paper's six experiments).
    #[serde(default, deserialize_with = "crate::request::objects")]
    #[schema(max_items = 16)]
    pub scenes: Option<Vec<SceneSpec>>,
    /// Buckets per series, on which the verdicts are taken (default 1000).
    #[serde(default)]
    #[schema(minimum = 1)]
    pub points: Option<i64>,
}
