//! [`SectionRequest`]: the `section` object of a `/simulate` request, a Poincaré section:
//! the surface s = 0 as a formula, the direction of the crossings that count, and what to
//! plot at each.

use serde::Deserialize;
use utoipa::ToSchema;

/// A Poincaré section of each run.
#[derive(Debug, Clone, PartialEq, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SectionRequest {
    /// The surface s = 0: a formula in the coordinates, their velocities (`x_dot`), `t` and
    /// the parameters, e.g. `"theta"`.
    pub surface: String,
    /// Which crossings count: `up` (s from negative to non-negative, the default), `down`
    /// or `both`.
    #[serde(default)]
    #[schema(value_type = Option<String>, example = "up")]
    pub direction: Option<String>,
    /// What to take at each crossing: each an observable's name (from `observables`) or a
    /// formula, e.g. `["x", "x_dot"]`; its text names its column.
    #[schema(min_items = 1, max_items = 16)]
    pub plot: Vec<String>,
    /// Most crossings kept per run (default and at most the server's `--max-crossings`,
    /// 10⁴ by default); the run goes on past it, keeping no more.
    #[serde(default)]
    #[schema(minimum = 1)]
    pub max_crossings: Option<i64>,
}
