//! The API against the real server, one answer at a time: every endpoint's numbers, errors
//! and streams. One test binary, with a module per subject, so that the workspace links one
//! binary for all of them, not one each. What measures the process itself stays apart: the
//! counting allocator (`answer_memory.rs`), the service under load and its timings
//! (`service.rs`, `budgets.rs`, `bounded_work.rs`, `connections.rs`, `responsive.rs`), the page
//! in a browser (`browser/`).

mod api;
mod api_errors;
mod api_scorecard;
mod api_work_precision;
mod compositions;
mod exact_numbers;
mod formulas;
mod general_form;
mod hostile;
mod observables;
mod sweep;
mod tableaux;
