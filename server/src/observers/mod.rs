//! The observers of a run (the core's [`Observer`](nhlab_core::Observer)): what watches a
//! simulation as it computes and turns its buckets into an answer. [`JsonCollector`] keeps a
//! run whole for a JSON answer; [`SseEmitter`] streams it as server-sent events
//! ([`sse_event`]). Both keep the [`Verdicts`] of their series.

mod json_collector;
mod recorded;
mod sse_emitter;
mod sse_event;
mod verdicts;

pub use json_collector::JsonCollector;
pub use recorded::{Crossings, Recorded, Sampled};
pub use sse_emitter::SseEmitter;
pub use sse_event::sse_event;
pub use verdicts::{IntegralNames, Verdicts};
