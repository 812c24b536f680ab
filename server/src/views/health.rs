//! [`Health`]: the answer of `GET /health`, how busy the server is, with the counters of its
//! caches ([`CachesStats`]) and how formulas run ([`FormulasHealth`]).

use serde::Serialize;
use utoipa::ToSchema;

/// The answer of `GET /health`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct Health {
    /// `ok`, or `shutting_down` (streams are ending, no new simulations).
    pub status: String,
    /// Simulations (admitted requests) holding a slot right now.
    pub simulations: usize,
    /// Most simulations at once; one more gets 503.
    pub max_simulations: usize,
    /// Simulation runs computing right now (one per method of a simulation).
    pub active_runs: usize,
    /// Bytes the answers in flight hold (their estimates, reserved from admission until the
    /// answer is written or dropped).
    pub answer_bytes: u64,
    /// The most bytes the answers in flight have held at once since the server started.
    pub answer_bytes_peak: u64,
    /// Most bytes the answers in flight may hold together; beyond, 503.
    pub max_inflight_bytes: u64,
    /// Hits, misses and entries of the latitude-axis and reference caches.
    pub cache: CachesStats,
    /// Whether systems given as formulas run as machine code or on the interpreter.
    pub formulas: FormulasHealth,
}

/// How systems given as formulas run, as `GET /health` reports it: compiled to machine code
/// (Cranelift), or on the interpreter, which gives the same numbers, slower.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, ToSchema)]
pub struct FormulasHealth {
    /// Whether formulas are compiled to machine code (all but the very longest): the server
    /// is built with the JIT and it has never failed in this process.
    pub native: bool,
    /// Why not, when they run on the interpreter: the server built without the `jit`
    /// feature, or Cranelift's first failure on this host; null when `native`.
    pub why: Option<String>,
}

impl From<nhlab_core::formula::NativeCodeStatus> for FormulasHealth {
    fn from(status: nhlab_core::formula::NativeCodeStatus) -> Self {
        Self { native: status.native(), why: status.why_not() }
    }
}

/// One cache's counters, as `GET /health` reports them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
pub struct CacheStats {
    /// Lookups answered from the cache.
    pub hits: u64,
    /// Lookups that computed.
    pub misses: u64,
    /// Entries held now (at most 256).
    pub entries: usize,
}

/// The counters of both caches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
pub struct CachesStats {
    /// Latitude monodromy axes (by system, params, q, v).
    pub latitude: CacheStats,
    /// Dop853 references of `/work-precision` (by scene, t_end, tolerance).
    pub reference: CacheStats,
}
