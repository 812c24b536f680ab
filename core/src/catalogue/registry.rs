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
use crate::model::system::{System, SystemInfo};
use crate::{InputError, Integral, Method, RunError, State, StepFailure, Vector};

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

/// A registered system: its description and its code, monomorphized for its sizes.
pub struct SystemEntry {
    info: fn() -> &'static SystemInfo,
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

fn vectors<const N: usize>(start: Start<'_>) -> (Vector<N>, Vector<N>) {
    (Vector::<N>::from_column_slice(start.q), Vector::<N>::from_column_slice(start.v))
}

impl SystemEntry {
    /// The entry of `S`.
    pub const fn of<S: System<N, R>, const N: usize, const R: usize>() -> Self {
        Self {
            info: S::info,
            dof: N,
            constraints: R,
            residual: |start| {
                let (q, v) = vectors::<N>(start);
                S::new(start.params).constraint_residual(&q, &v)
            },
            latitude: |start| {
                let (q, v) = vectors::<N>(start);
                LatitudeAxis::compute(&S::new(start.params), &q, &v)
            },
            reference: |start, t_end, tol, stop| {
                let (q, v) = vectors::<N>(start);
                let sys = S::new(start.params);
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
                let sys = S::new(start.params);
                let (q, v) = vectors::<N>(start);
                let start =
                    State::with_continuous_multiplier(&sys, q, v).ok_or(StepFailure::Singular)?;
                properties::measure(&sys, method, start, step)
            },
            run: |input, method, cfg, observer| {
                let sys = S::new(input.start.params);
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

    /// Its description.
    pub fn info(&self) -> &'static SystemInfo {
        (self.info)()
    }
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
