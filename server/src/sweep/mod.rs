//! Sweeps: one scene, its methods, and 1 to 3 axes whose product is a grid of cells; each
//! cell runs every method with the cell's values in place and reports a row per method (its
//! status, cost and verdicts, no series). `POST /sweep` answers with the rows (JSON, CSV or a
//! stream); `nhlab sweep` computes them without a server, whole or one shard of N, and joins
//! shards back into the same rows ([`shards`]).
//!
//! - [`axis`]: an axis, its path ([`Target`]) and values;
//! - [`plan`]: the request checked into its cells ([`Sweep`]);
//! - [`price`]: its work priced before admission;
//! - [`work`]: computing cells, a worker's loop;
//! - [`csv`]: rows as CSV;
//! - [`answer`]: `POST /sweep`'s JSON or CSV answer, written as the cells complete;
//! - [`shards`]: shard files, their resumption and their merge.

pub mod answer;
pub mod axis;
pub mod csv;
pub mod plan;
mod price;
pub mod shards;
mod work;

pub use axis::{Axis, Target};
pub use plan::{AxisSource, Cell, MAX_AXES, Sweep};
