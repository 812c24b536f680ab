//! [`Slot`]: one of the `max_simulations` simulation slots, taken by
//! [`AppState::admit`](crate::state::AppState::admit). The runs of a request each hold a clone, as
//! does whatever answers the client (the JSON handler, a stream's coordinating task), so the
//! slot frees when the last of them ends: when the computation has really stopped.

use std::sync::Arc;
use tokio::sync::OwnedSemaphorePermit;

/// A simulation slot; freed when the last clone is dropped.
#[derive(Debug, Clone)]
pub struct Slot(
    #[allow(dead_code, reason = "held for its Drop, which frees the slot")]
    Arc<OwnedSemaphorePermit>,
);

impl Slot {
    pub(crate) fn new(permit: OwnedSemaphorePermit) -> Self {
        Self(Arc::new(permit))
    }
}
