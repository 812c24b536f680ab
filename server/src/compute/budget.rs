//! [`AnswerBudget`]: the memory that answers may hold, per request and server-wide.
//!
//! Every limit of a request is checked alone (points, methods, scenes), but what it holds is
//! their product: each series keeps its buckets for its verdict, a JSON answer also turns them
//! into columns and text. [`answer_bytes`] estimates that from the request alone, before any
//! work (a sweep, whose rows are written into its answer as its cells complete, counts their
//! text and its checked cells); a request over `max_answer_bytes` is refused (422, with the
//! estimate). Admitted requests reserve their estimate in the server-wide [`AnswerBudget`]
//! until their answer is written or dropped (a [`BudgetGuard`] is owned by the answer's
//! buffer, or by the stream's body, so an answer a slow client has not read yet still
//! counts); one that would exceed it gets 503. The estimates are meant as the memory the
//! answers take, not a bound far above it: peak RSS over them is measured by
//! `bench/memory.py`, the heap over them checked by the `answer_memory` test.

use crate::error::AppError;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// Bytes a bucket costs while a run keeps it for its verdict (three `f64`s, in a vector that
/// may have grown to twice its length): `/scorecard` and `/work-precision`, which answer no
/// series.
pub const KEPT_BYTES_PER_POINT: u64 = 48;

/// Bytes a bucket costs at the peak of a JSON answer: kept for the verdict, then as columns
/// (three `Option<f64>`s) beside its JSON text (three numbers of up to ~24 characters). A
/// stream costs as much: it keeps the buckets, and its events wait as JSON text.
pub const JSON_BYTES_PER_POINT: u64 = 128;

/// What one request's answer holds: `series` series of `points` buckets each, at
/// `bytes_per_point`; saturating, so no request overflows it.
pub fn answer_bytes(series: u64, points: u64, bytes_per_point: u64) -> u64 {
    series.saturating_mul(points).saturating_mul(bytes_per_point)
}

/// Bytes as MiB, for messages.
pub fn mib(bytes: u64) -> String {
    let mib = bytes as f64 / (1024.0 * 1024.0);
    if mib >= 10.0 { format!("{mib:.0} MiB") } else { format!("{mib:.1} MiB") }
}

/// The server-wide budget of answers in flight; cheap to clone.
#[derive(Debug, Clone)]
pub struct AnswerBudget {
    limit: u64,
    used: Arc<AtomicU64>,
    /// The most `used` has been.
    peak: Arc<AtomicU64>,
}

impl AnswerBudget {
    /// A budget of `limit` bytes.
    pub fn new(limit: u64) -> Self {
        Self { limit, used: Arc::default(), peak: Arc::default() }
    }

    /// Bytes reserved right now.
    pub fn used(&self) -> u64 {
        self.used.load(Ordering::SeqCst)
    }

    /// The most bytes reserved at once since the budget was made.
    pub fn peak(&self) -> u64 {
        self.peak.load(Ordering::SeqCst)
    }

    /// The limit, in bytes.
    pub fn limit(&self) -> u64 {
        self.limit
    }

    /// Reserves `bytes` until the guard is dropped, or a 503 when they do not fit beside the
    /// answers in flight.
    pub fn reserve(&self, bytes: u64) -> Result<BudgetGuard, AppError> {
        let before = self
            .used
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |used| {
                used.checked_add(bytes).filter(|&total| total <= self.limit)
            })
            .map_err(|used| {
                AppError::unavailable(format!(
                    "the server is busy: answers in flight hold {} and this one needs about {}, \
                     over the limit of {} (max_inflight_bytes); retry in a moment",
                    mib(used),
                    mib(bytes),
                    mib(self.limit)
                ))
            })?;
        self.peak.fetch_max(before + bytes, Ordering::SeqCst);
        Ok(BudgetGuard { bytes, used: self.used.clone() })
    }
}

/// Bytes reserved in an [`AnswerBudget`], given back when dropped.
#[derive(Debug)]
pub struct BudgetGuard {
    bytes: u64,
    used: Arc<AtomicU64>,
}

impl Drop for BudgetGuard {
    fn drop(&mut self) {
        self.used.fetch_sub(self.bytes, Ordering::SeqCst);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reservations_add_up_and_are_given_back() {
        let budget = AnswerBudget::new(100);
        let a = budget.reserve(60).expect("fits");
        assert!(budget.reserve(41).is_err(), "60 + 41 > 100");
        let b = budget.reserve(40).expect("60 + 40 fits");
        assert_eq!(budget.used(), 100);
        drop(a);
        assert_eq!(budget.used(), 40);
        drop(b);
        assert_eq!(budget.used(), 0);
        assert_eq!(budget.peak(), 100, "the most held at once stays");
        assert!(budget.reserve(101).is_err(), "alone over the limit");
        assert_eq!(answer_bytes(u64::MAX, 2, 3), u64::MAX, "saturates");
    }
}
