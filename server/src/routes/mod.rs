//! The handlers, one module per endpoint: [`simulate`](simulate::simulate) (its stream in
//! [`simulate_stream`]), [`scorecard`](scorecard::scorecard),
//! [`work_precision`](work_precision::work_precision), [`sweep`](sweep::sweep),
//! [`systems`](systems::systems),
//! [`health`](health::health) and the [`page`](page::page). Each reads its body with
//! [`JsonObject`](crate::JsonObject), checks it off the runtime, asks for admission, computes
//! and answers with its [view](crate::views). The router ([`app`](crate::app)) mounts them.

pub mod health;
pub mod page;
pub mod scorecard;
pub mod simulate;
pub mod simulate_stream;
pub mod sweep;
pub mod systems;
pub mod work_precision;
