//! [`Caches`]: what a request computes from its scene alone and a later request for the same
//! scene can reuse: the latitude's monodromy axis (a Dop853 solve over one driver period,
//! needed by every `/simulate`, `/scorecard` and `/work-precision` that measures the
//! latitude) and the Dop853 reference at t_end of `/work-precision`.
//!
//! Keys hold the f64 inputs by bit pattern (`0.1` and `0.1000000000000000055` are the same
//! number, `0.0` and `-0.0` are not the same key, which costs at most a recomputation).
//! Each cache is bounded ([`CAPACITY`] entries, the oldest evicted first) and guarded by a
//! `Mutex` that is held only to look up or insert, never while computing nor across an
//! await: two requests missing the same key at once both compute it, and the second insert
//! is a no-op. Results are deterministic functions of their key, so errors are cached too
//! (a scene whose axis is undefined stays so), except a reference solve cancelled because its
//! client went away ([`Cache::get_or_compute_keeping`]), which says nothing of the scene.
//! Hits, misses and sizes are reported by `GET /health` as `cache`.

use crate::views::{CacheStats, CachesStats};
use nhlab_core::catalogue::work_precision::ReferenceSummary;
use nhlab_core::measure::latitude::LatitudeAxis;
use nhlab_core::measure::reference::ReferenceError;
use nhlab_core::{InputError, Scene};
use std::collections::{HashMap, VecDeque};
use std::hash::Hash;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

/// Most entries per cache: a few hundred scenes, each entry well under a kilobyte.
pub const CAPACITY: usize = 256;

/// The caches of the app, shared by every request.
#[derive(Debug, Default)]
pub struct Caches {
    /// Latitude axes by system, params, q and v.
    pub latitude: Cache<SceneKey, Result<LatitudeAxis, InputError>>,
    /// References by scene, t_end and tolerance.
    pub reference: Cache<ReferenceKey, Result<ReferenceSummary, ReferenceError>>,
}

impl Caches {
    /// The latitude axis of `scene`, from the cache or computed (on the calling thread).
    pub fn latitude(&self, scene: &Scene) -> Result<LatitudeAxis, InputError> {
        self.latitude.get_or_compute(SceneKey::of(scene), || scene.latitude_axis()).0
    }

    /// What `GET /health` reports.
    pub fn stats(&self) -> CachesStats {
        CachesStats { latitude: self.latitude.stats(), reference: self.reference.stats() }
    }
}

/// The start of a scene: what its latitude axis depends on.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct SceneKey {
    system: String,
    params: Vec<u64>,
    q: Vec<u64>,
    v: Vec<u64>,
}

impl SceneKey {
    /// The key of `scene`'s system, parameters and initial state.
    pub fn of(scene: &Scene) -> Self {
        let bits = |x: &[f64]| x.iter().map(|x| x.to_bits()).collect();
        Self {
            system: scene.system.key(),
            params: bits(&scene.params),
            q: bits(&scene.q),
            v: bits(&scene.v),
        }
    }
}

/// What a reference depends on: the scene's start, t_end and the solver's tolerance.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ReferenceKey {
    scene: SceneKey,
    t_end: u64,
    tol: u64,
}

impl ReferenceKey {
    /// The key of `scene`'s reference at tolerance `tol`.
    pub fn of(scene: &Scene, tol: f64) -> Self {
        Self { scene: SceneKey::of(scene), t_end: scene.t_end.to_bits(), tol: tol.to_bits() }
    }
}

/// A bounded map with first-in, first-out eviction and hit/miss counters.
#[derive(Debug)]
pub struct Cache<K, V> {
    entries: Mutex<Entries<K, V>>,
    hits: AtomicU64,
    misses: AtomicU64,
}

#[derive(Debug)]
struct Entries<K, V> {
    map: HashMap<K, V>,
    order: VecDeque<K>,
}

impl<K, V> Default for Cache<K, V> {
    fn default() -> Self {
        Self {
            entries: Mutex::new(Entries { map: HashMap::new(), order: VecDeque::new() }),
            hits: AtomicU64::new(0),
            misses: AtomicU64::new(0),
        }
    }
}

impl<K: Clone + Eq + Hash, V: Clone> Cache<K, V> {
    /// The value of `key`, and whether it came from the cache; on a miss `compute` runs
    /// without the lock held and its value is kept.
    pub fn get_or_compute(&self, key: K, compute: impl FnOnce() -> V) -> (V, bool) {
        self.get_or_compute_keeping(key, compute, |_| true)
    }

    /// [`get_or_compute`](Self::get_or_compute), keeping the computed value only if `keep`
    /// says so (a computation that was interrupted is not the key's value).
    pub fn get_or_compute_keeping(
        &self,
        key: K,
        compute: impl FnOnce() -> V,
        keep: impl FnOnce(&V) -> bool,
    ) -> (V, bool) {
        if let Some(v) = self.lock().map.get(&key).cloned() {
            self.hits.fetch_add(1, Ordering::Relaxed);
            return (v, true);
        }
        self.misses.fetch_add(1, Ordering::Relaxed);
        let value = compute();
        if !keep(&value) {
            return (value, false);
        }
        let mut entries = self.lock();
        if !entries.map.contains_key(&key) {
            if entries.map.len() >= CAPACITY
                && let Some(oldest) = entries.order.pop_front()
            {
                entries.map.remove(&oldest);
            }
            entries.order.push_back(key.clone());
            entries.map.insert(key, value.clone());
        }
        (value, false)
    }

    /// Hits, misses and entries so far.
    pub fn stats(&self) -> CacheStats {
        CacheStats {
            hits: self.hits.load(Ordering::Relaxed),
            misses: self.misses.load(Ordering::Relaxed),
            entries: self.lock().map.len(),
        }
    }

    // Nothing panics while the lock is held (map operations only), so a poisoned lock still
    // holds a consistent map.
    fn lock(&self) -> MutexGuard<'_, Entries<K, V>> {
        self.entries.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lookup_hits_and_the_oldest_entry_goes_first() {
        let cache: Cache<u32, u32> = Cache::default();
        assert_eq!(cache.get_or_compute(1, || 10), (10, false));
        assert_eq!(cache.get_or_compute(1, || panic!("cached")), (10, true));
        for k in 2..=(CAPACITY as u32 + 1) {
            cache.get_or_compute(k, || k * 10);
        }
        let stats = cache.stats();
        assert_eq!((stats.hits, stats.misses, stats.entries), (1, CAPACITY as u64 + 1, CAPACITY));
        // Key 1 was the oldest: evicted; key 2 is still there.
        assert_eq!(cache.get_or_compute(2, || 0), (20, true));
        assert_eq!(cache.get_or_compute(1, || 11), (11, false));
    }

    #[test]
    fn a_value_not_kept_is_computed_again() {
        let cache: Cache<u32, Result<u32, ()>> = Cache::default();
        let kept = |v: &Result<u32, ()>| v.is_ok();
        assert_eq!(cache.get_or_compute_keeping(1, || Err(()), kept), (Err(()), false));
        assert_eq!(cache.stats().entries, 0);
        assert_eq!(cache.get_or_compute_keeping(1, || Ok(7), kept), (Ok(7), false));
        assert_eq!(cache.get_or_compute_keeping(1, || Ok(8), kept), (Ok(7), true));
    }
}
