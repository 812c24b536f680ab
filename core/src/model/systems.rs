//! The test systems of `docs/model.md` §2, one file each, and the one list of them.
//!
//! A new system is one file in this folder plus one line in [`with_systems!`]: the list
//! declares the module, and from it derive the registry (`GET /systems`, the dispatch,
//! scenes), [`for_each_system!`](crate::for_each_system) (the tests' and benchmarks' cross
//! products) and the page, which reads `GET /systems`.

/// The one list of systems: `(module, type, N, R)` in listing order. Expands
/// `$crate::__apply_systems!` with the given arm and the list; use
/// [`for_each_system!`](crate::for_each_system) rather than this.
#[doc(hidden)]
#[macro_export]
macro_rules! with_systems {
    ($($how:tt)*) => {
        $crate::__apply_systems! { ($($how)*) [
            (knife_edge, KnifeEdge, 3, 1),
            (cvt_pendulum, CvtPendulum, 3, 1),
            (cvt, Cvt, 3, 1),
            (particle, Particle, 3, 1),
            (rolling_disk, RollingDisk, 4, 2),
            (mobile_robot, MobileRobot, 4, 2),
            (anharmonic_cvt, AnharmonicCvt, 3, 1),
        ] }
    };
}

/// What [`with_systems!`] expands to: the modules, the registry's entries, or one call per
/// system.
#[doc(hidden)]
#[macro_export]
macro_rules! __apply_systems {
    ((declare) [$(($m:ident, $t:ident, $n:literal, $r:literal)),* $(,)?]) => {
        $(mod $m; pub use self::$m::$t;)*
    };
    ((entries) [$(($m:ident, $t:ident, $n:literal, $r:literal)),* $(,)?]) => {
        &[$($crate::catalogue::registry::SystemEntry::of::<$crate::systems::$t, $n, $r>()),*]
    };
    ((each $f:ident $args:tt) [$(($m:ident, $t:ident, $n:literal, $r:literal)),* $(,)?]) => {{
        $($f::<$crate::systems::$t, $n, $r> $args;)*
    }};
}

/// Calls `f::<S, N, R>(args…)` once for every system, in listing order, with the system's
/// type and sizes: for code generic over systems (tests, benchmarks, tools).
#[macro_export]
macro_rules! for_each_system {
    ($f:ident $(, $arg:expr)* $(,)?) => {
        $crate::with_systems!(each $f ($($arg),*))
    };
}

crate::with_systems!(declare);
