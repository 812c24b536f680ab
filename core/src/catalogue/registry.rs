//! The registry of systems: [`SYSTEMS`], derived from the one list in
//! [`crate::model::systems`], feeds `GET /systems`, scene resolution and the dispatch.
//!
//! Systems have different fixed sizes, so each [`SystemEntry`] holds function pointers to
//! code monomorphized for its `System<N, R>`; the [`Method`] enum dispatches once per run,
//! outside the step loop.

use crate::measure::latitude::LatitudeAxis;
use crate::measure::properties::{self, Properties};
use crate::measure::reference::{self, ReferenceError};
use crate::measure::simulate::{Observer, Problem, RunConfig, RunOutcome};
use crate::model::custom::{Compiled, Custom};
use crate::model::system::{BuiltIn, System, SystemInfo};
use crate::{InputError, Integral, Method, RunError, State, StepFailure, Vector};
use std::sync::Arc;

/// Every system, in listing order.
pub static SYSTEMS: &[SystemEntry] = crate::with_systems!(entries);

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

/// A system's parameter values and initial state, sizes erased: what its code needs of a
/// scene.
#[derive(Debug, Clone, Copy)]
pub struct Start<'a> {
    /// Parameter values, in the order of the system's `params`.
    pub params: &'a [f64],
    /// Initial configuration.
    pub q: &'a [f64],
    /// Initial velocity.
    pub v: &'a [f64],
    /// The compiled formulas of a system given as formulas (whose parameters are compiled
    /// into them); `None` for a built-in.
    pub custom: Option<&'a Arc<Compiled>>,
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

/// A system's code, monomorphized for its type and sizes, sizes erased: the built-ins' and
/// the sizes a system given as formulas may have ([`CUSTOM_SIZES`]).
pub struct SystemCode {
    /// Number of coordinates n.
    pub dof: usize,
    /// Number of constraints r.
    pub constraints: usize,
    pub(crate) residual: fn(Start<'_>) -> f64,
    pub(crate) latitude: fn(Start<'_>) -> Result<LatitudeAxis, InputError>,
    pub(crate) run: fn(&RunInput<'_>, &Method, &RunConfig, &mut dyn Observer) -> RunOutcome,
    pub(crate) properties: fn(Start<'_>, f64, &Method) -> Result<Properties, StepFailure>,
    pub(crate) reference: ReferenceFn,
}

/// A registered system: its description and its code.
pub struct SystemEntry {
    info: fn() -> &'static SystemInfo,
    /// Number of coordinates n.
    pub dof: usize,
    /// Number of constraints r.
    pub constraints: usize,
    /// Its code.
    pub code: SystemCode,
}

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
        f.debug_struct("SystemCode").field("dof", &self.dof).field("r", &self.constraints).finish()
    }
}

fn vectors<const N: usize>(start: Start<'_>) -> (Vector<N>, Vector<N>) {
    (Vector::<N>::from_column_slice(start.q), Vector::<N>::from_column_slice(start.v))
}

/// How a system's code builds the system from a [`Start`].
pub trait FromStart<const N: usize, const R: usize>: System<N, R> {
    /// The system of this start.
    fn from_start(start: &Start<'_>) -> Self;
}

impl<S: BuiltIn<N, R>, const N: usize, const R: usize> FromStart<N, R> for S {
    fn from_start(start: &Start<'_>) -> Self {
        S::new(start.params)
    }
}

impl<const N: usize, const R: usize> FromStart<N, R> for Custom<N, R> {
    fn from_start(start: &Start<'_>) -> Self {
        // `Scene` pairs a custom system's code with its compilation: never absent here.
        let compiled = start.custom.expect("a system given as formulas runs with its compilation");
        Custom::new(compiled.clone())
    }
}

impl SystemCode {
    /// The code of `S`.
    pub const fn of<S: FromStart<N, R>, const N: usize, const R: usize>() -> Self {
        Self {
            dof: N,
            constraints: R,
            residual: |start| {
                let (q, v) = vectors::<N>(start);
                S::from_start(&start).constraint_residual(&q, &v)
            },
            latitude: |start| {
                let (q, v) = vectors::<N>(start);
                LatitudeAxis::compute(&S::from_start(&start), &q, &v)
            },
            reference: |start, t_end, tol, stop| {
                let (q, v) = vectors::<N>(start);
                let sys = S::from_start(&start);
                let r = reference::reference_until(&sys, &q, &v, t_end, tol, stop)?;
                Ok(ReferenceState {
                    q: r.q.as_slice().to_vec(),
                    v: r.v.as_slice().to_vec(),
                    constraint_residual: r.constraint_residual,
                    evaluations: r.evaluations,
                    steps: r.steps,
                })
            },
            properties: |start, step, method| {
                let sys = S::from_start(&start);
                let (q, v) = vectors::<N>(start);
                let start =
                    State::with_continuous_multiplier(&sys, q, v).ok_or(StepFailure::Singular)?;
                properties::measure(&sys, method, start, step)
            },
            run: |input, method, cfg, observer| {
                let sys = S::from_start(&input.start);
                let (q, v) = vectors::<N>(input.start);
                let Some(start) = State::with_continuous_multiplier(&sys, q, v) else {
                    let failure = StepFailure::Singular;
                    return RunOutcome {
                        steps: 0,
                        error: Some(RunError::Step { step: 1, t: 0.0, failure }),
                    };
                };
                let problem = Problem {
                    sys: &sys,
                    start,
                    step: input.step,
                    steps: input.steps,
                    integrals: input.integrals,
                    latitude: input.latitude,
                };
                method.run(&problem, cfg, observer)
            },
        }
    }
}

impl SystemEntry {
    /// The entry of `S`.
    pub const fn of<S: BuiltIn<N, R>, const N: usize, const R: usize>() -> Self {
        Self { info: S::info, dof: N, constraints: R, code: SystemCode::of::<S, N, R>() }
    }

    /// Its description.
    pub fn info(&self) -> &'static SystemInfo {
        (self.info)()
    }
}

/// The code of a system given as formulas, for each size it may have: n passengers (2 to
/// 6) and 1 to n − 1 constraints, as `(n + 1, r)`.
pub static CUSTOM_SIZES: &[SystemCode] = &[
    SystemCode::of::<Custom<3, 1>, 3, 1>(),
    SystemCode::of::<Custom<4, 1>, 4, 1>(),
    SystemCode::of::<Custom<4, 2>, 4, 2>(),
    SystemCode::of::<Custom<5, 1>, 5, 1>(),
    SystemCode::of::<Custom<5, 2>, 5, 2>(),
    SystemCode::of::<Custom<5, 3>, 5, 3>(),
    SystemCode::of::<Custom<6, 1>, 6, 1>(),
    SystemCode::of::<Custom<6, 2>, 6, 2>(),
    SystemCode::of::<Custom<6, 3>, 6, 3>(),
    SystemCode::of::<Custom<6, 4>, 6, 4>(),
    SystemCode::of::<Custom<7, 1>, 7, 1>(),
    SystemCode::of::<Custom<7, 2>, 7, 2>(),
    SystemCode::of::<Custom<7, 3>, 7, 3>(),
    SystemCode::of::<Custom<7, 4>, 7, 4>(),
    SystemCode::of::<Custom<7, 5>, 7, 5>(),
];

/// The code for a system given as formulas of these sizes.
pub fn custom_code(dof: usize, constraints: usize) -> Option<&'static SystemCode> {
    CUSTOM_SIZES.iter().find(|c| c.dof == dof && c.constraints == constraints)
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
}
