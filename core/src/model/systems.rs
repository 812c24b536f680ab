//! The test systems of `docs/model.md` §2, one file each, and the one list of them.
//!
//! A new system is one file in this folder plus one line in [`with_systems!`]: the list
//! declares the module, and from it derive the registry (`GET /systems`, the dispatch,
//! scenes), [`for_each_system!`](crate::for_each_system) (the tests' and benchmarks' cross
//! products) and the page, which reads `GET /systems`.

/// The one list of systems, in listing order, in three parts: built-ins of the paper's class
/// `(module, type, N, R)` (their type implements [`System`](crate::System)), built-ins of the
/// general class `(module, type, N, R)` (their type implements
/// [`Mechanical`](crate::model::mechanical::Mechanical)), and built-ins given as formulas (a
/// module with `fn info()` whose form is the general one; compiled per scene, the paper's
/// class found in them where it holds). Expands `$crate::__apply_systems!` with the given arm
/// and the list; use [`for_each_system!`](crate::for_each_system) rather than this.
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
        ] [
            (chaplygin_sleigh, ChaplyginSleigh, 3, 1),
        ] [
            chaotic_oscillator,
            contact_oscillator,
            nonholonomic_oscillator,
            heisenberg,
            vertical_disk,
        ] }
    };
}

/// What [`with_systems!`] expands to: the modules, the registry's entries, or one call per
/// system.
#[doc(hidden)]
#[macro_export]
macro_rules! __apply_systems {
    ((declare) [$(($m:ident, $t:ident, $n:literal, $r:literal)),* $(,)?]
        [$(($gm:ident, $gt:ident, $gn:literal, $gr:literal)),* $(,)?] [$($f:ident),* $(,)?]) => {
        $(mod $m; pub use self::$m::$t;)*
        $(mod $gm; pub use self::$gm::$gt;)*
        $(pub(crate) mod $f;)*
    };
    ((entries) [$(($m:ident, $t:ident, $n:literal, $r:literal)),* $(,)?]
        [$(($gm:ident, $gt:ident, $gn:literal, $gr:literal)),* $(,)?] [$($f:ident),* $(,)?]) => {
        &[
            $($crate::catalogue::registry::SystemEntry::of::<$crate::systems::$t, $n, $r>(),)*
            $($crate::catalogue::registry::SystemEntry::general::<$crate::systems::$gt, $gn, $gr>(),)*
            $($crate::catalogue::registry::SystemEntry::formulas($crate::systems::$f::info),)*
        ]
    };
    ((each $f:ident $args:tt) [$(($m:ident, $t:ident, $n:literal, $r:literal)),* $(,)?]
        $general:tt $formulas:tt) => {{
        $($f::<$crate::systems::$t, $n, $r> $args;)*
    }};
    ((each_general $f:ident $args:tt) $class:tt
        [$(($gm:ident, $gt:ident, $gn:literal, $gr:literal)),* $(,)?] $formulas:tt) => {{
        $($f::<$crate::systems::$gt, $gn, $gr> $args;)*
    }};
}

/// Calls `f::<S, N, R>(args…)` once for every built-in of the paper's class, in listing
/// order, with the system's type and sizes: for code generic over systems (tests,
/// benchmarks, tools).
#[macro_export]
macro_rules! for_each_system {
    ($f:ident $(, $arg:expr)* $(,)?) => {
        $crate::with_systems!(each $f ($($arg),*))
    };
}

/// Calls `f::<S, N, R>(args…)` once for every built-in of the general class compiled into
/// nhlab (its type implements `Mechanical`).
#[macro_export]
macro_rules! for_each_general_system {
    ($f:ident $(, $arg:expr)* $(,)?) => {
        $crate::with_systems!(each_general $f ($($arg),*))
    };
}

crate::with_systems!(declare);
