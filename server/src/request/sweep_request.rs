//! [`SweepRequest`]: the body of `POST /sweep` (and the spec file of `nhlab sweep`): a
//! `/simulate` scene and methods, and the [`AxisRequest`]s whose product is the sweep's cells.

use crate::request::{MethodRequest, ObservablesRequest, scene_body, schemas};
use serde::Deserialize;
use utoipa::ToSchema;

scene_body! {
    /// The body of `POST /sweep`: a `/simulate` scene and methods, and 1 to 3 axes. Each cell
    /// of the axes' product runs every method on the scene with the cell's values in place.
    pub struct SweepRequest {
        /// Methods, as in `/simulate` (default: the paper's five).
        #[serde(default)]
        #[schema(schema_with = schemas::methods)]
        pub methods: Option<Vec<MethodRequest>>,
        /// Buckets per series, on which each run's verdicts are taken (default 1000).
        #[serde(default)]
        #[schema(minimum = 1, maximum = 100_000)]
        pub points: Option<i64>,
        /// 1 to 3 axes; the cells are their product, the last axis varying fastest.
        #[serde(default, deserialize_with = "crate::request::objects")]
        #[schema(min_items = 1, max_items = 3)]
        pub axes: Option<Vec<AxisRequest>>,
        /// Quantities taken at t_end in each row, by name, each a formula as `/simulate`'s
        /// observables (default: none).
        #[serde(default)]
        #[schema(schema_with = schemas::observables)]
        pub observables: Option<ObservablesRequest>,
    }
}

/// One axis of a sweep: a path into the scene and its values, given as a list or spaced
/// linearly or logarithmically (exactly one of the three).
#[derive(Debug, Clone, Default, PartialEq, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct AxisRequest {
    /// What the axis sets: `params.NAME`, `q[i]`, `v[i]`, `step`, `t_end`, `methods.NAME`
    /// (parameter NAME of every listed method that has it, e.g. `methods.alpha`) or
    /// `methods[i].NAME` (of method i only).
    #[schema(example = "params.epsilon")]
    pub path: String,
    /// The values, in order.
    #[serde(default)]
    #[schema(min_items = 1, max_items = 10_000)]
    pub values: Option<Vec<f64>>,
    /// `[start, stop, n]`: n values from start to stop, both included, evenly spaced.
    #[serde(default)]
    #[schema(min_items = 3, max_items = 3)]
    pub linspace: Option<Vec<f64>>,
    /// `[start, stop, n]`: n values from start to stop (both positive, both included),
    /// evenly spaced in their logarithm.
    #[serde(default)]
    #[schema(min_items = 3, max_items = 3)]
    pub logspace: Option<Vec<f64>>,
}
