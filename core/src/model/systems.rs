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
/// class found in them where it holds). `with_systems!(callback args)` expands
/// `$crate::callback! { (args) [class…] [general…] [formulas…] }`: the declarations here, the
/// registry's entries in the catalogue (`catalogue::registry`), the cross products of
/// [`for_each_system!`](crate::for_each_system).
#[doc(hidden)]
#[macro_export]
macro_rules! with_systems {
    ($callback:ident $($args:tt)*) => {
        $crate::$callback! { ($($args)*) [
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

/// [`with_systems!`]'s callback that declares the systems' modules.
#[doc(hidden)]
#[macro_export]
macro_rules! __declare_systems {
    (() [$(($m:ident, $t:ident, $n:literal, $r:literal)),* $(,)?]
        [$(($gm:ident, $gt:ident, $gn:literal, $gr:literal)),* $(,)?] [$($f:ident),* $(,)?]) => {
        $(mod $m; pub use self::$m::$t;)*
        $(mod $gm; pub use self::$gm::$gt;)*
        $(pub(crate) mod $f;)*
    };
}

/// [`with_systems!`]'s callback that calls `f::<S, N, R>(args…)` for each built-in of the
/// paper's class.
#[doc(hidden)]
#[macro_export]
macro_rules! __each_system {
    (($f:ident $args:tt) [$(($m:ident, $t:ident, $n:literal, $r:literal)),* $(,)?]
        $general:tt $formulas:tt) => {{
        $($f::<$crate::systems::$t, $n, $r> $args;)*
    }};
}

/// [`with_systems!`]'s callback that calls `f::<S, N, R>(args…)` for each built-in of the
/// general class compiled into nhlab.
#[doc(hidden)]
#[macro_export]
macro_rules! __each_general_system {
    (($f:ident $args:tt) $class:tt
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
        $crate::with_systems!(__each_system $f ($($arg),*))
    };
}

/// Calls `f::<S, N, R>(args…)` once for every built-in of the general class compiled into
/// nhlab (its type implements `Mechanical`).
#[macro_export]
macro_rules! for_each_general_system {
    ($f:ident $(, $arg:expr)* $(,)?) => {
        $crate::with_systems!(__each_general_system $f ($($arg),*))
    };
}

crate::with_systems!(__declare_systems);
