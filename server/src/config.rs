//! [`Config`]: the server's limits, with defaults that keep one request from wedging a
//! small machine. Every limit is named in the error a request gets when it exceeds it.

use std::time::Duration;

/// Limits on what one request may ask for.
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
    /// Time between two `progress`/`points` reports of a streamed run (a few per second:
    /// enough for a live plot, few enough to cost nothing).
    pub report_every: Duration,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            max_steps_json: 20_000_000,
            max_steps_stream: 200_000_000,
            max_points: 100_000,
            max_methods: 16,
            max_body_bytes: 64 * 1024,
            report_every: Duration::from_millis(200),
        }
    }
}
