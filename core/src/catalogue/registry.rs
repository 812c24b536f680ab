//! The registry of systems: [`SYSTEMS`], derived from the one list in
//! [`crate::model::systems`], feeds `GET /systems`, scene resolution and the dispatch.
//!
//! Systems have different fixed sizes, so each one's [`SystemCode`] holds function pointers
//! to code monomorphized for its type: the class's steps for a system of the paper's class
//! ([`SystemCode::class`]), the general steps for any other ([`SystemCode::general`]). A
//! built-in given as formulas has no code of its own: it is compiled per scene and runs on
//! the code of its sizes ([`class_code`], [`general_code`]). The [`Method`] enum dispatches
//! once per run, outside the step loop.

use crate::measure::latitude::LatitudeAxis;
use crate::measure::properties::{self, Properties};
use crate::measure::reference::{self, ReferenceError};
use crate::measure::simulate::{self, Observer, Problem, RunConfig, RunOutcome};
use crate::model::custom::{Custom, GeneralCustom, Invariants, Structure};
use crate::model::mechanical::GeneralBuiltIn;
use crate::model::mechanical::{General, Mechanical};
use crate::model::system::{BuiltIn, System, SystemInfo};
use crate::{InputError, Integral, Method, RunError, State, StepFailure, Vector};
use nalgebra::DMatrix;
use std::marker::PhantomData;
use std::sync::Arc;

/// Every system, in listing order.
pub static SYSTEMS: &[SystemEntry] = crate::with_systems!(__system_entries);

/// [`with_systems!`](crate::with_systems)'s callback that makes the registry's entries.
#[doc(hidden)]
#[macro_export]
macro_rules! __system_entries {
    (() [$(($m:ident, $t:ident, $n:literal, $r:literal)),* $(,)?]
        [$(($gm:ident, $gt:ident, $gn:literal, $gr:literal)),* $(,)?] [$($f:ident),* $(,)?]) => {
        &[
            $($crate::catalogue::registry::SystemEntry::of::<$crate::systems::$t, $n, $r>(),)*
            $($crate::catalogue::registry::SystemEntry::general::<$crate::systems::$gt, $gn, $gr>(),)*
            $($crate::catalogue::registry::SystemEntry::formulas($crate::systems::$f::info),)*
        ]
    };
}

/// The paper's six experiments (`docs/model.md` §2) as (system, preset): its figure set,
/// the scorecard's default scenes and the benchmarks' workload.
pub const PAPER_SCENES: [(&str, &str); 6] = [
    ("knife_edge", "paper"),
    ("knife_edge", "paper-perturbed"),
    ("cvt_pendulum", "oscillating"),
    ("cvt_pendulum", "rotating"),
    ("cvt_pendulum", "oscillating-perturbed"),
    ("cvt_pendulum", "rotating-perturbed"),
];

/// The figure beyond the paper (`docs/model.md` §4, Poincaré sections): the section of the
/// rotating perturbed CVT where the driver completes a turn (ζ = 2πm, either way), in the
/// passenger plane, by leap-frog and DLA^½ beside the reference; the integrals whose verdicts
/// its caption reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperSection {
    /// (system, preset).
    pub scene: (&'static str, &'static str),
    /// The section's surface, direction and plotted quantities.
    pub surface: &'static str,
    /// `up`, `down` or `both`.
    pub direction: &'static str,
    /// The plotted quantities.
    pub plot: [&'static str; 2],
    /// The integrals whose verdicts the caption reports.
    pub integrals: [&'static str; 2],
}

/// See [`PaperSection`].
pub const PAPER_SECTION: PaperSection = PaperSection {
    scene: ("cvt_pendulum", "rotating-perturbed"),
    surface: "sin(zeta/2)",
    direction: "both",
    plot: ["x1", "x2"],
    integrals: ["passenger_energy", "latitude"],
};

impl PaperSection {
    /// Its methods: leap-frog, DLA^½ and the reference.
    pub fn methods(&self) -> [Method; 3] {
        use crate::methods::{Dla, Leapfrog, ReferenceStep};
        [
            Method::from(Leapfrog),
            Method::from(Dla { alpha: 0.5, ..Dla::default() }),
            Method::from(ReferenceStep),
        ]
    }
}

/// The literature's test problems beyond the paper's (`docs/model.md` §2), as (system,
/// preset): the scorecard's scenes after the paper's six.
pub const LITERATURE_SCENES: [(&str, &str); 7] = [
    ("chaplygin_sleigh", "free"),
    ("chaplygin_sleigh", "inclined"),
    ("chaotic_oscillator", "n1"),
    ("contact_oscillator", "mp"),
    ("nonholonomic_oscillator", "default"),
    ("heisenberg", "default"),
    ("vertical_disk", "long"),
];

/// A system's parameter values and initial state, sizes erased: what its code needs of a
/// scene. q and v are in the order the code holds the coordinates (for a system given as
/// formulas found in the paper's class, the driver last).
#[derive(Debug, Clone, Copy)]
pub struct Start<'a> {
    /// Parameter values, in the order of the system's `params`.
    pub params: &'a [f64],
    /// Initial configuration.
    pub q: &'a [f64],
    /// Initial velocity.
    pub v: &'a [f64],
    /// The compilation of a system given as formulas (whose parameters are compiled into
    /// it); `None` for a built-in compiled into nhlab.
    pub formulas: Option<&'a Structure>,
    /// The invariants of a system given as formulas, when it declares any, on the code's
    /// `(q, q̇)`: the system built carries them (`System::invariants`), and a run measures them.
    pub invariants: Option<&'a Arc<Invariants>>,
}

/// What one run needs besides the method, sizes erased.
#[derive(Debug, Clone, Copy)]
pub struct RunInput<'a> {
    /// The system's parameters and the initial state.
    pub start: Start<'a>,
    /// Step size.
    pub step: f64,
    /// Number of steps.
    pub steps: u64,
    /// The integrals to measure.
    pub integrals: &'a [Integral],
    /// The monodromy axis, when the latitude is measured.
    pub latitude: Option<LatitudeAxis>,
}

/// A system's M and A at a state, as the start's checks read them (`Scene::resolve`).
#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    /// A(q), R×N.
    pub a: DMatrix<f64>,
    /// M, N×N.
    pub mass: DMatrix<f64>,
}

/// A system's code, monomorphized for its type and sizes, sizes erased.
pub struct SystemCode {
    /// Number of coordinates n.
    pub dof: usize,
    /// Number of constraints r.
    pub constraints: usize,
    /// Whether it runs the methods' general steps (`docs/model.md` §1), not the class's.
    pub general: bool,
    pub(crate) constraint: fn(Start<'_>) -> Constraint,
    pub(crate) latitude: fn(Start<'_>) -> Result<LatitudeAxis, InputError>,
    pub(crate) run: fn(&RunInput<'_>, &Method, &RunConfig, &mut dyn Observer) -> RunOutcome,
    pub(crate) properties: PropertiesFn,
    pub(crate) reference: ReferenceFn,
}

/// A registered system: its description, and its code where it is compiled into nhlab.
pub struct SystemEntry {
    info: fn() -> &'static SystemInfo,
    /// Its code; `None` for a built-in given as formulas, compiled per scene.
    pub native: Option<SystemCode>,
}

/// The property measurement of a system: start, step, method, stop flag.
type PropertiesFn =
    fn(Start<'_>, f64, &Method, &dyn Fn() -> bool) -> Result<Properties, StepFailure>;

/// The reference solve of a system: start, t_end, tolerance, stop flag.
type ReferenceFn =
    fn(Start<'_>, f64, f64, &dyn Fn() -> bool) -> Result<ReferenceState, ReferenceError>;

/// A reference solution at t_end, sizes erased.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceState {
    /// Configuration.
    pub q: Vec<f64>,
    /// Velocity.
    pub v: Vec<f64>,
    /// `|A(q) q̇|` at t_end.
    pub constraint_residual: f64,
    /// Right-hand-side evaluations.
    pub evaluations: u32,
    /// Accepted steps.
    pub steps: u32,
}

impl std::fmt::Debug for SystemEntry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SystemEntry").field("id", &self.info().id).finish()
    }
}

impl std::fmt::Debug for SystemCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SystemCode")
            .field("dof", &self.dof)
            .field("r", &self.constraints)
            .field("general", &self.general)
            .finish()
    }
}

fn vectors<const N: usize>(start: Start<'_>) -> (Vector<N>, Vector<N>) {
    (Vector::<N>::from_column_slice(start.q), Vector::<N>::from_column_slice(start.v))
}

/// How a system's code builds the system from a [`Start`].
pub trait Build<const N: usize, const R: usize> {
    /// The system built.
    type System: Send + Sync;
    /// The system of this start.
    fn build(start: &Start<'_>) -> Self::System;
}

/// A built-in of the paper's class, from its parameters.
pub struct ClassBuiltIn<S>(PhantomData<S>);
/// A built-in of the general class, from its parameters.
pub struct GeneralBuiltInOf<S>(PhantomData<S>);
/// A system given as formulas found in the paper's class.
pub struct ClassFormulas;
/// A system given as formulas in the general class.
pub struct GeneralFormulas;

impl<S: BuiltIn<N, R>, const N: usize, const R: usize> Build<N, R> for ClassBuiltIn<S> {
    type System = S;
    fn build(start: &Start<'_>) -> S {
        S::new(start.params)
    }
}

impl<S: GeneralBuiltIn<N, R>, const N: usize, const R: usize> Build<N, R> for GeneralBuiltInOf<S> {
    type System = S;
    fn build(start: &Start<'_>) -> S {
        S::new(start.params)
    }
}

impl<const N: usize, const R: usize> Build<N, R> for ClassFormulas {
    type System = Custom<N, R>;
    fn build(start: &Start<'_>) -> Custom<N, R> {
        // `Scene` pairs the code of a system given as formulas with its compilation.
        match start.formulas {
            Some(Structure::Class { compiled, .. }) => {
                Custom::new(compiled.clone()).with_invariants(start.invariants.cloned())
            }
            _ => unreachable!("a class system given as formulas runs with its compilation"),
        }
    }
}

impl<const N: usize, const R: usize> Build<N, R> for GeneralFormulas {
    type System = GeneralCustom<N, R>;
    fn build(start: &Start<'_>) -> GeneralCustom<N, R> {
        match start.formulas {
            Some(Structure::General(compiled)) => {
                GeneralCustom::new(compiled.clone()).with_invariants(start.invariants.cloned())
            }
            _ => unreachable!("a general system given as formulas runs with its compilation"),
        }
    }
}

/// M and A at a start, as matrices.
fn constraint_of<S: Mechanical<N, R>, const N: usize, const R: usize>(
    sys: &S,
    q: &Vector<N>,
) -> Constraint {
    let a = sys.constraint(q);
    Constraint {
        a: DMatrix::from_fn(R, N, |i, j| a[(i, j)]),
        mass: DMatrix::from_fn(N, N, |i, j| sys.mass().matrix()[(i, j)]),
    }
}

fn reference_state<const N: usize>(r: reference::Reference<N>) -> ReferenceState {
    ReferenceState {
        q: r.q.as_slice().to_vec(),
        v: r.v.as_slice().to_vec(),
        constraint_residual: r.constraint_residual,
        evaluations: r.evaluations,
        steps: r.steps,
    }
}

/// The outcome of a run that could not start: its first step fails (`A M⁻¹ Aᵀ` singular at
/// the start, which a scene's checks leave only for A's rank at the edge of their tolerance).
fn no_start() -> RunOutcome {
    let failure = StepFailure::Singular;
    RunOutcome { steps: 0, error: Some(RunError::Step { step: 1, t: 0.0, failure }) }
}

impl SystemCode {
    /// The code of a system of the paper's class: the methods' class steps.
    pub const fn class<B: Build<N, R>, const N: usize, const R: usize>() -> Self
    where
        B::System: System<N, R>,
    {
        Self {
            dof: N,
            constraints: R,
            general: false,
            constraint: |start| {
                let sys = B::build(&start);
                constraint_of(&General(&sys), &vectors::<N>(start).0)
            },
            latitude: |start| {
                let (q, v) = vectors::<N>(start);
                LatitudeAxis::compute(&B::build(&start), &q, &v)
            },
            reference: |start, t_end, tol, stop| {
                let (q, v) = vectors::<N>(start);
                let sys = B::build(&start);
                let r = reference::reference_until(&General(&sys), &q, &v, t_end, tol, stop)?;
                Ok(reference_state(r))
            },
            properties: |start, step, method, stop| {
                let sys = B::build(&start);
                let (q, v) = vectors::<N>(start);
                let start =
                    State::with_continuous_multiplier(&sys, q, v).ok_or(StepFailure::Singular)?;
                properties::measure(&sys, method, start, step, stop)
            },
            run: |input, method, cfg, observer| {
                let sys = B::build(&input.start);
                let (q, v) = vectors::<N>(input.start);
                let Some(start) = State::with_continuous_multiplier(&sys, q, v) else {
                    return no_start();
                };
                let problem = Problem {
                    sys: &sys,
                    start,
                    step: input.step,
                    steps: input.steps,
                    integrals: input.integrals,
                    latitude: input.latitude,
                    invariants: sys.invariants(),
                };
                simulate::run_method(&problem, method, cfg, observer)
            },
        }
    }

    /// The code of a system of the general class: the methods' general steps.
    pub const fn general<B: Build<N, R>, const N: usize, const R: usize>() -> Self
    where
        B::System: Mechanical<N, R>,
    {
        Self {
            dof: N,
            constraints: R,
            general: true,
            constraint: |start| constraint_of(&B::build(&start), &vectors::<N>(start).0),
            latitude: |_| {
                Err(InputError::LatitudeUndefined {
                    reason: "the latitude is defined on the paper's class only (docs/model.md §5)"
                        .into(),
                })
            },
            reference: |start, t_end, tol, stop| {
                let (q, v) = vectors::<N>(start);
                let sys = B::build(&start);
                Ok(reference_state(reference::reference_until(&sys, &q, &v, t_end, tol, stop)?))
            },
            properties: |start, step, method, stop| {
                let sys = B::build(&start);
                let (q, v) = vectors::<N>(start);
                let start = State::general_start(&sys, q, v).ok_or(StepFailure::Singular)?;
                properties::measure_general(&sys, method, start, step, stop)
            },
            run: |input, method, cfg, observer| {
                let sys = B::build(&input.start);
                let (q, v) = vectors::<N>(input.start);
                let Some(start) = State::general_start(&sys, q, v) else {
                    return no_start();
                };
                let problem = Problem {
                    sys: &sys,
                    start,
                    step: input.step,
                    steps: input.steps,
                    integrals: input.integrals,
                    latitude: None,
                    invariants: sys.invariants(),
                };
                simulate::run_method_general(&problem, method, cfg, observer)
            },
        }
    }
}

impl SystemEntry {
    /// The entry of a built-in of the paper's class.
    pub const fn of<S: BuiltIn<N, R>, const N: usize, const R: usize>() -> Self {
        Self { info: S::info, native: Some(SystemCode::class::<ClassBuiltIn<S>, N, R>()) }
    }

    /// The entry of a built-in of the general class.
    pub const fn general<S: GeneralBuiltIn<N, R>, const N: usize, const R: usize>() -> Self {
        Self { info: S::info, native: Some(SystemCode::general::<GeneralBuiltInOf<S>, N, R>()) }
    }

    /// The entry of a built-in given as formulas (`SystemInfo::form` is its general form).
    pub const fn formulas(info: fn() -> &'static SystemInfo) -> Self {
        Self { info, native: None }
    }

    /// Its description.
    pub fn info(&self) -> &'static SystemInfo {
        (self.info)()
    }
}

/// The code of a system given as formulas found in the paper's class, for each size it may
/// have: n passengers (2 to 6) and 1 to n − 1 constraints, as `(n + 1, r)`.
pub static CLASS_SIZES: &[SystemCode] = &[
    SystemCode::class::<ClassFormulas, 3, 1>(),
    SystemCode::class::<ClassFormulas, 4, 1>(),
    SystemCode::class::<ClassFormulas, 4, 2>(),
    SystemCode::class::<ClassFormulas, 5, 1>(),
    SystemCode::class::<ClassFormulas, 5, 2>(),
    SystemCode::class::<ClassFormulas, 5, 3>(),
    SystemCode::class::<ClassFormulas, 6, 1>(),
    SystemCode::class::<ClassFormulas, 6, 2>(),
    SystemCode::class::<ClassFormulas, 6, 3>(),
    SystemCode::class::<ClassFormulas, 6, 4>(),
    SystemCode::class::<ClassFormulas, 7, 1>(),
    SystemCode::class::<ClassFormulas, 7, 2>(),
    SystemCode::class::<ClassFormulas, 7, 3>(),
    SystemCode::class::<ClassFormulas, 7, 4>(),
    SystemCode::class::<ClassFormulas, 7, 5>(),
];

/// The code of a system given as formulas in the general class: every size up to 6
/// coordinates, and 12 coordinates for the larger ones, padded (`GeneralCustom`).
pub static GENERAL_SIZES: &[SystemCode] = &[
    SystemCode::general::<GeneralFormulas, 2, 1>(),
    SystemCode::general::<GeneralFormulas, 3, 1>(),
    SystemCode::general::<GeneralFormulas, 3, 2>(),
    SystemCode::general::<GeneralFormulas, 4, 1>(),
    SystemCode::general::<GeneralFormulas, 4, 2>(),
    SystemCode::general::<GeneralFormulas, 4, 3>(),
    SystemCode::general::<GeneralFormulas, 5, 1>(),
    SystemCode::general::<GeneralFormulas, 5, 2>(),
    SystemCode::general::<GeneralFormulas, 5, 3>(),
    SystemCode::general::<GeneralFormulas, 5, 4>(),
    SystemCode::general::<GeneralFormulas, 6, 1>(),
    SystemCode::general::<GeneralFormulas, 6, 2>(),
    SystemCode::general::<GeneralFormulas, 6, 3>(),
    SystemCode::general::<GeneralFormulas, 6, 4>(),
    SystemCode::general::<GeneralFormulas, 6, 5>(),
    SystemCode::general::<GeneralFormulas, 12, 1>(),
    SystemCode::general::<GeneralFormulas, 12, 2>(),
    SystemCode::general::<GeneralFormulas, 12, 3>(),
    SystemCode::general::<GeneralFormulas, 12, 4>(),
    SystemCode::general::<GeneralFormulas, 12, 5>(),
    SystemCode::general::<GeneralFormulas, 12, 6>(),
    SystemCode::general::<GeneralFormulas, 12, 7>(),
    SystemCode::general::<GeneralFormulas, 12, 8>(),
    SystemCode::general::<GeneralFormulas, 12, 9>(),
    SystemCode::general::<GeneralFormulas, 12, 10>(),
    SystemCode::general::<GeneralFormulas, 12, 11>(),
];

/// Most coordinates compiled as they are; a system with more runs padded to
/// [`PADDED`](self::PADDED).
const EXACT_MAX: usize = 6;
/// The size larger systems are padded to.
const PADDED: usize = crate::model::custom::MAX_COORDINATES;

/// The code of a system given as formulas found in the paper's class, of `dof` coordinates
/// (the driver last) and `constraints` rows.
pub fn class_code(dof: usize, constraints: usize) -> Option<&'static SystemCode> {
    CLASS_SIZES.iter().find(|c| c.dof == dof && c.constraints == constraints)
}

/// The code of a system given as formulas in the general class, of `dof` coordinates and
/// `constraints` rows: its own size, or a padded one (`dof` ≥ 7: 12 coordinates, each added
/// with a row of its own).
pub fn general_code(dof: usize, constraints: usize) -> Option<&'static SystemCode> {
    let (n, r) =
        if dof <= EXACT_MAX { (dof, constraints) } else { (PADDED, constraints + PADDED - dof) };
    GENERAL_SIZES.iter().find(|c| c.dof == n && c.constraints == r)
}

/// The system with this id.
pub fn system(id: &str) -> Result<&'static SystemEntry, InputError> {
    SYSTEMS.iter().find(|s| s.info().id == id).ok_or_else(|| InputError::UnknownSystem {
        id: id.into(),
        valid: SYSTEMS.iter().map(|s| s.info().id).collect::<Vec<_>>().join(", "),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every preset names only parameters its system has (`SystemInfo::preset_params` would
    /// otherwise drop a misspelled one silently).
    #[test]
    fn presets_name_only_their_systems_parameters() {
        for info in SYSTEMS.iter().map(SystemEntry::info) {
            for preset in info.presets {
                for (name, _) in preset.params {
                    assert!(
                        info.params.iter().any(|p| p.name == *name),
                        "{}/{} names an unknown parameter {name}",
                        info.id,
                        preset.id
                    );
                }
            }
        }
    }

    /// Every size a system given as formulas may have has its code.
    #[test]
    fn every_size_has_code() {
        for dof in 2..=PADDED {
            for r in 1..dof {
                assert!(general_code(dof, r).is_some(), "general ({dof}, {r})");
            }
        }
        for n in 2..=crate::model::custom::MAX_PASSENGERS {
            for r in 1..n {
                assert!(class_code(n + 1, r).is_some(), "class ({}, {r})", n + 1);
            }
        }
    }
}
