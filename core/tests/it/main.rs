//! nhlab-core's integration tests, one module per area, built as one test binary.
//!
//! One binary rather than one per file, for build time: each file used to be a crate of its
//! own that instantiated nhlab-core's generic numerics (const-generic systems × methods) anew
//! and was linked on its own; as modules of one crate they are instantiated once and linked
//! once. Run one module's tests with `cargo test -p nhlab-core --test it <module>::`, e.g.
//! `cargo test -p nhlab-core --test it compositions::`.

#[macro_use]
mod common;

mod anharmonic_cvt;
mod at_rest;
mod compositions;
mod convergence;
mod derivatives;
mod driver;
mod exact_energy;
mod fast_path;
mod formula_convergence;
mod formula_systems;
mod formulas;
mod general;
mod inputs;
mod latitude;
mod newton_stopping;
mod paper_table;
mod parametric;
mod prk;
mod properties;
mod props;
mod quadratic_shortcuts;
mod reference;
mod reference_bounds;
mod spark;
mod stress;
mod structure;
mod work_precision;
