//! The answer to `POST /sweep` (and the rows of `nhlab sweep`'s shard files): a head saying
//! what was swept ([`SweepHead`]) and one [`SweepRow`] per cell × method, in a fixed order
//! (by cell, then by method). A stream sends the head as `start`, each cell's rows as a
//! `cell` event ([`SweepCell`]) as the cell completes, `progress` ([`SweepProgress`]) and
//! `done` ([`SweepDone`]).

use crate::request::SystemField;
use crate::views::{GapView, MethodView, ValuesView, VerdictView};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// An axis as swept: its path and its values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct AxisView {
    /// What the axis sets, e.g. `params.epsilon`.
    pub path: String,
    /// Its values, in order.
    pub values: Vec<f64>,
}

/// What a sweep sweeps: everything about it but its rows.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SweepHead {
    /// The axes with their values; a row's `values` are in this order.
    pub axes: Vec<AxisView>,
    /// The methods as listed (a method axis changes a row's `method`, not these).
    pub methods: Vec<MethodView>,
    /// The integrals measured, in order.
    pub integrals: Vec<String>,
    /// The observables taken at t_end in each row, in the order asked for (absent when none
    /// were).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub observables: Vec<String>,
    /// Number of cells: the product of the axes' lengths.
    pub cells: usize,
    /// The verdicts' criterion.
    pub criterion: String,
}

/// The JSON answer: the head and every row.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SweepResponse {
    /// What was swept.
    #[serde(flatten)]
    pub head: SweepHead,
    /// One row per cell × method, by cell, then by method.
    pub rows: Vec<SweepRow>,
}

/// How a row ended: as a run does, or `invalid` when the cell's values made its scene or its
/// method invalid (nothing ran).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum RowStatus {
    /// It reached t_end.
    Ok,
    /// It stopped early; `error` says where and why.
    Failed,
    /// The cell's scene or method is invalid; `error` names the field and why.
    Invalid,
}

/// One method on one cell.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SweepRow {
    /// The cell's index: `(i₀·n₁ + i₁)·n₂ + i₂` for value indices `iₖ` on axes of lengths `nₖ`.
    pub cell: usize,
    /// The cell's value on each axis.
    pub values: Vec<f64>,
    /// The method's place in the listed methods.
    pub method_index: usize,
    /// The method as run on this cell (a method axis's value in place).
    pub method: MethodView,
    /// `ok`, `failed` or `invalid`.
    pub status: RowStatus,
    /// Why it failed (step and time) or is invalid (the field and why), or null.
    pub error: Option<String>,
    /// Steps completed.
    pub steps: u64,
    /// CPU time of the run, in milliseconds (null where not measured, or nothing ran).
    pub cpu_ms: Option<f64>,
    /// Newton iterations the run took (null for an explicit method, or nothing ran).
    pub newton_iterations: Option<u64>,
    /// The observables asked for, at t_end, by name (null for a run that did not reach it);
    /// absent when none were asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Object>, example = json!({"x": 0.12}))]
    pub observables: Option<ValuesView>,
    /// Each measured series' verdict, by integral (none for a series without values).
    pub verdicts: BTreeMap<String, VerdictView>,
    /// The gap of each series that has one (no values from `since` on), by integral.
    pub gaps: BTreeMap<String, GapView>,
    /// The `/simulate` body that runs this row on its own (its series are one request away).
    pub simulate: SimulateEcho,
}

/// A `/simulate` body: the cell's scene, every value resolved where it could be, and the one
/// method.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SimulateEcho {
    /// System id, or the system given as formulas.
    #[schema(schema_with = crate::request::schemas::system)]
    pub system: SystemField,
    /// Preset id (none for a system given as formulas).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// Parameter values by name.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub params: BTreeMap<String, f64>,
    /// Initial configuration.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub q: Option<Vec<f64>>,
    /// Initial velocity.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub v: Option<Vec<f64>>,
    /// Step size.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step: Option<f64>,
    /// Final time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_end: Option<f64>,
    /// Integrals measured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub integrals: Option<Vec<String>>,
    /// The one method, as a request gives it.
    #[schema(value_type = Vec<Object>)]
    pub methods: Vec<BTreeMap<String, serde_json::Value>>,
    /// Buckets per series.
    pub points: usize,
}

/// `cell`: a cell completed (cells complete in any order).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SweepCell {
    /// The cell's index.
    pub cell: usize,
    /// Its value on each axis.
    pub values: Vec<f64>,
    /// Its rows, by method.
    pub rows: Vec<SweepRow>,
}

/// `progress`: how far a sweep is (a few per second).
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SweepProgress {
    /// Cells completed.
    pub cells_done: usize,
    /// Cells in all.
    pub cells: usize,
    /// Wall-clock time so far, in milliseconds.
    pub elapsed_ms: f64,
}

/// `done`: every cell completed; the stream closes.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SweepDone {
    /// Cells.
    pub cells: usize,
    /// Rows.
    pub rows: usize,
    /// Rows whose run failed.
    pub failed: usize,
    /// Rows whose cell or method was invalid.
    pub invalid: usize,
    /// Wall-clock time of the whole sweep, in milliseconds.
    pub elapsed_ms: f64,
}
