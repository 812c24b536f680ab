//! [`Config`]: the server's limits, with defaults that keep one request from wedging a
//! small machine. Every limit is named in the error a request gets when it exceeds it, and
//! each is a flag and an environment variable of the binary (`nhlab --help`).

use nhlab_core::CustomLimits;
use std::time::Duration;

/// Limits on what one request may ask for, and on how much runs at once.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Most steps per run for a JSON response (which holds everything until the end).
    pub max_steps_json: u64,
    /// Most steps per run for a stream (which reports as it goes and can be cancelled).
    pub max_steps_stream: u64,
    /// Most buckets per series (`points`).
    pub max_points: u64,
    /// Most methods per request (each runs on its own thread).
    pub max_methods: usize,
    /// Largest request body, in bytes.
    pub max_body_bytes: usize,
    /// Most simulations (requests that compute: `/simulate`, `/scorecard`) at once; one more
    /// gets 503 with `Retry-After` instead of waiting in a queue. A stream holds its slot
    /// until it ends.
    pub max_simulations: usize,
    /// Most bytes one request's answer may hold at its peak (its series' buckets, columns and
    /// JSON text, estimated before any work); more is a 422 with the estimate.
    pub max_answer_bytes: u64,
    /// Most bytes all answers in flight may hold together, including those still being
    /// written to slow clients; a request that would exceed it gets 503.
    pub max_inflight_bytes: u64,
    /// Origins allowed to call the API from a browser (CORS); empty: CORS off, only the
    /// page's own origin. `*` allows any.
    pub cors_origins: Vec<String>,
    /// Time between two `progress`/`points` reports of a streamed run (a few per second:
    /// enough for a live plot, few enough to cost nothing).
    pub report_every: Duration,
    /// Debug builds only, for the fault tests: a request with exactly this `points` panics
    /// inside its simulations. The field does not exist in release builds, so no request
    /// can reach it in production.
    #[cfg(debug_assertions)]
    pub panic_on_points: Option<usize>,
    /// Time a request body has to arrive once its handler starts reading it; a body still
    /// incomplete then gets 408 (a trickling client holds no connection for long).
    pub body_timeout: Duration,
    /// Bounds on a system given as formulas: characters per formula, nesting depth, number
    /// of parameters.
    pub formulas: CustomLimits,
    /// Most cells (the product of the axes' lengths) per sweep.
    pub max_sweep_cells: u64,
    /// Most steps one sweep may take in all (cells × methods × steps per run, sub-steps of a
    /// composition counted).
    pub max_sweep_steps: u64,
    /// Longest one run may compute, in seconds of wall-clock time: past it, the run ends as
    /// `failed` ("time limit"), like a run that diverges.
    pub max_run_seconds: f64,
    /// Most CPU time one request's runs may take together, in seconds, as estimated before
    /// any work (steps × the method's cost per step on the system,
    /// [`nhlab_core::catalogue::cost`]); more is a 422 with the estimate.
    pub max_request_seconds: f64,
    /// Most crossings of a Poincaré section kept per run (a request's `max_crossings` may
    /// ask for fewer).
    pub max_crossings: u64,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            max_steps_json: 20_000_000,
            max_steps_stream: 200_000_000,
            max_points: 100_000,
            max_methods: 16,
            max_body_bytes: 64 * 1024,
            max_simulations: std::thread::available_parallelism().map_or(2, |n| n.get()),
            max_answer_bytes: 64 << 20,
            max_inflight_bytes: 256 << 20,
            cors_origins: Vec::new(),
            report_every: Duration::from_millis(200),
            #[cfg(debug_assertions)]
            panic_on_points: None,
            body_timeout: Duration::from_secs(10),
            formulas: CustomLimits::default(),
            max_sweep_cells: 10_000,
            max_sweep_steps: 2_000_000_000,
            max_run_seconds: 300.0,
            max_request_seconds: 300.0,
            max_crossings: 10_000,
        }
    }
}
