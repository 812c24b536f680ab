//! The lists of all systems and all methods: they feed `GET /systems`, input validation
//! and the cross-product tests. A new system or method is one file plus one line here.
//!
//! Systems have different fixed sizes, so each [`SystemEntry`] holds function pointers to
//! code monomorphized for its `System<N, R>`; the [`Method`] enum dispatches once per run,
//! outside the step loop.

use crate::latitude::LatitudeAxis;
use crate::method::{Integrator, MethodInfo};
use crate::methods::{Dd, DdAvf, Dla, Dla01, Leapfrog, Rk4};
use crate::properties::{self, Properties};
use crate::reference::{self, ReferenceError};
use crate::scene::{PreparedScene, Scene};
use crate::simulate::{self, Observer, Problem, RunConfig, RunOutcome};
use crate::system::{System, SystemInfo};
use crate::systems::{Cvt, CvtPendulum, KnifeEdge, MobileRobot, Particle, RollingDisk};
use crate::{InputError, RunError, State, StepFailure, Vector};

/// Every system, in listing order.
pub static SYSTEMS: &[SystemEntry] = &[
    SystemEntry::of::<KnifeEdge, 3, 1>(),
    SystemEntry::of::<CvtPendulum, 3, 1>(),
    SystemEntry::of::<Cvt, 3, 1>(),
    SystemEntry::of::<Particle, 3, 1>(),
    SystemEntry::of::<RollingDisk, 4, 2>(),
    SystemEntry::of::<MobileRobot, 4, 2>(),
];

/// Calls `f::<S, N, R>(args…)` once for every system of [`SYSTEMS`], in its order, with the
/// system's type and sizes: for code generic over systems (tests, benchmarks, tools). Kept
/// beside `SYSTEMS`, against which a test checks it.
#[macro_export]
macro_rules! for_each_system {
    ($f:ident $(, $arg:expr)* $(,)?) => {{
        use $crate::systems::*;
        $f::<KnifeEdge, 3, 1>($($arg),*);
        $f::<CvtPendulum, 3, 1>($($arg),*);
        $f::<Cvt, 3, 1>($($arg),*);
        $f::<Particle, 3, 1>($($arg),*);
        $f::<RollingDisk, 4, 2>($($arg),*);
        $f::<MobileRobot, 4, 2>($($arg),*);
    }};
}

/// The paper's six experiments (MATH.md §6) as (system, preset): its figure set, the
/// scorecard's default scenes and the benchmarks' workload.
pub const PAPER_SCENES: [(&str, &str); 6] = [
    ("knife_edge", "paper"),
    ("knife_edge", "paper-perturbed"),
    ("cvt_pendulum", "oscillating"),
    ("cvt_pendulum", "rotating"),
    ("cvt_pendulum", "oscillating-perturbed"),
    ("cvt_pendulum", "rotating-perturbed"),
];

macro_rules! methods {
    ($($variant:ident),* $(,)?) => {
        /// A configured method of the registry.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub enum Method {
            $(
                #[doc = concat!("`", stringify!($variant), "`")]
                $variant($variant),
            )*
        }

        /// Every method's description, in listing order.
        pub fn method_infos() -> Vec<&'static MethodInfo> {
            vec![$(<$variant as Integrator>::info()),*]
        }

        impl Method {
            fn build(id: &str, params: &[f64]) -> Option<Result<Self, InputError>> {
                $(
                    if id == <$variant as Integrator>::info().id {
                        return Some($variant::from_params(params).map(Method::$variant));
                    }
                )*
                None
            }
            /// Its description.
            pub fn info(&self) -> &'static MethodInfo {
                match self { $(Method::$variant(_) => <$variant as Integrator>::info()),* }
            }
            /// Short label, e.g. `DLA^0.4`.
            pub fn label(&self) -> String {
                match self { $(Method::$variant(m) => m.label()),* }
            }
            /// Order of convergence.
            pub fn order(&self) -> u32 {
                match self { $(Method::$variant(m) => m.order()),* }
            }
            /// Parameter values with their names.
            pub fn params(&self) -> Vec<(&'static str, f64)> {
                let values = match self { $(Method::$variant(m) => m.params()),* };
                self.info().params.iter().map(|p| p.name).zip(values).collect()
            }
            /// One step (for tests and tools; runs dispatch once, in [`Method::run`]).
            pub fn step<S: System<N, R>, const N: usize, const R: usize>(
                &self, sys: &S, state: &mut State<N, R>, h: f64,
            ) -> Result<(), StepFailure> {
                match self { $(Method::$variant(m) => m.step(sys, state, h)),* }
            }
            /// `n` steps with one dispatch, as a run takes them but without integrals: what
            /// the ns/step benchmarks time.
            pub fn steps<S: System<N, R>, const N: usize, const R: usize>(
                &self, sys: &S, state: &mut State<N, R>, h: f64, n: u64,
            ) -> Result<(), StepFailure> {
                match self { $(Method::$variant(m) => (0..n).try_for_each(|_| m.step(sys, state, h))),* }
            }
            /// Runs the method on a problem.
            pub fn run<S: System<N, R>, const N: usize, const R: usize>(
                &self, problem: &Problem<'_, S, N, R>, cfg: &RunConfig, observer: &mut dyn Observer,
            ) -> RunOutcome {
                match self { $(Method::$variant(m) => simulate::run(problem, m, cfg, observer)),* }
            }
        }
    };
}

methods!(Dla, Dla01, Leapfrog, Dd, DdAvf, Rk4);

/// A method as a user names it: an id and parameter overrides.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MethodSpec {
    /// Method id.
    pub id: String,
    /// Parameters by name.
    pub params: Vec<(String, f64)>,
}

impl MethodSpec {
    /// A spec with no parameters.
    pub fn new(id: &str) -> Self {
        Self { id: id.into(), params: Vec::new() }
    }
    /// Adds a parameter.
    pub fn with(mut self, name: &str, value: f64) -> Self {
        self.params.push((name.into(), value));
        self
    }
}

/// The description of the method with this id.
pub fn method_info(id: &str) -> Option<&'static MethodInfo> {
    method_infos().into_iter().find(|m| m.id == id)
}

impl Method {
    /// The same method on its general Newton path (`fast_path: false`), for a method that has
    /// a faster one: what the fast paths are tested against (`tests/fast_path.rs`) and
    /// benchmarked beside. `None` for the others.
    pub fn general_path(&self) -> Option<Method> {
        Some(match *self {
            Method::Dla(m) => Method::Dla(Dla { fast_path: false, ..m }),
            Method::Dla01(m) => Method::Dla01(Dla01 { fast_path: false, ..m }),
            Method::Dd(m) => Method::Dd(Dd { fast_path: false, ..m }),
            Method::DdAvf(m) => Method::DdAvf(DdAvf { fast_path: false, ..m }),
            Method::Leapfrog(_) | Method::Rk4(_) => return None,
        })
    }

    /// Builds a method from a spec, checking its parameters (field paths are relative to
    /// the method object, e.g. `alpha`).
    pub fn from_spec(spec: &MethodSpec) -> Result<Self, InputError> {
        let info = method_info(&spec.id).ok_or_else(|| InputError::UnknownMethod {
            field: "id".into(),
            id: spec.id.clone(),
            valid: method_infos().iter().map(|m| m.id).collect::<Vec<_>>().join(", "),
        })?;
        let mut values: Vec<f64> = info.params.iter().map(|p| p.default).collect();
        for (name, value) in &spec.params {
            let Some(i) = info.params.iter().position(|p| p.name == name) else {
                let valid = info.params.iter().map(|p| p.name).collect::<Vec<_>>();
                return Err(InputError::UnknownParam {
                    field: name.clone(),
                    name: name.clone(),
                    owner: format!("method {}", info.id),
                    valid: if valid.is_empty() { "none".into() } else { valid.join(", ") },
                });
            };
            let p = &info.params[i];
            if !value.is_finite() {
                return Err(InputError::NonFinite { field: name.clone(), value: *value });
            }
            if !p.contains(*value) {
                return Err(InputError::ParamOutOfRange {
                    field: name.clone(),
                    name: name.clone(),
                    value: *value,
                    range: p.range(),
                });
            }
            values[i] = *value;
        }
        Self::build(info.id, &values).expect("method_info found the id")
    }

    /// The paper's five: DLA^0.5, DLA^0.4, DLA^{0,1}, LF, DD.
    pub fn paper_five() -> [Method; 5] {
        [
            Method::Dla(Dla { alpha: 0.5, ..Dla::default() }),
            Method::Dla(Dla { alpha: 0.4, ..Dla::default() }),
            Method::Dla01(Dla01::default()),
            Method::Leapfrog(Leapfrog),
            Method::Dd(Dd::default()),
        ]
    }

    /// Every registered method with its default parameters, the paper's five first (so DLA^α
    /// twice, at α = ½ and 0.4): what the scorecard, the benchmarks and the tools run.
    pub fn all() -> Vec<Method> {
        let mut out = Self::paper_five().to_vec();
        for info in method_infos() {
            if !out.iter().any(|m| m.info().id == info.id) {
                // A registered id with its defaults always builds.
                out.extend(Self::from_spec(&MethodSpec::new(info.id)));
            }
        }
        out
    }
}

/// A registered system: its description and its code, monomorphized for its sizes.
pub struct SystemEntry {
    info: fn() -> &'static SystemInfo,
    /// Number of coordinates n.
    pub dof: usize,
    /// Number of constraints r.
    pub constraints: usize,
    pub(crate) residual: fn(&Scene) -> f64,
    pub(crate) latitude: fn(&Scene) -> Result<LatitudeAxis, InputError>,
    pub(crate) run: fn(&PreparedScene, &Method, &RunConfig, &mut dyn Observer) -> RunOutcome,
    pub(crate) properties: fn(&Scene, &Method) -> Result<Properties, StepFailure>,
    pub(crate) reference: fn(&Scene, f64) -> Result<ReferenceState, ReferenceError>,
}

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

fn vectors<const N: usize>(scene: &Scene) -> (Vector<N>, Vector<N>) {
    (Vector::<N>::from_column_slice(&scene.q), Vector::<N>::from_column_slice(&scene.v))
}

impl SystemEntry {
    /// The entry of `S`.
    pub const fn of<S: System<N, R>, const N: usize, const R: usize>() -> Self {
        Self {
            info: S::info,
            dof: N,
            constraints: R,
            residual: |scene| {
                let (q, v) = vectors::<N>(scene);
                S::new(&scene.params).constraint_residual(&q, &v)
            },
            latitude: |scene| {
                let (q, v) = vectors::<N>(scene);
                LatitudeAxis::compute(&S::new(&scene.params), &q, &v)
            },
            reference: |scene, tol| {
                let (q, v) = vectors::<N>(scene);
                let r = reference::reference(&S::new(&scene.params), &q, &v, scene.t_end, tol)?;
                Ok(ReferenceState {
                    q: r.q.as_slice().to_vec(),
                    v: r.v.as_slice().to_vec(),
                    constraint_residual: r.constraint_residual,
                    evaluations: r.evaluations,
                    steps: r.steps,
                })
            },
            properties: |scene, method| {
                let sys = S::new(&scene.params);
                let (q, v) = vectors::<N>(scene);
                let start =
                    State::with_continuous_multiplier(&sys, q, v).ok_or(StepFailure::Singular)?;
                properties::measure(&sys, method, start, scene.step)
            },
            run: |prepared, method, cfg, observer| {
                let scene = &prepared.scene;
                let sys = S::new(&scene.params);
                let (q, v) = vectors::<N>(scene);
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
                    step: scene.step,
                    steps: scene.steps(),
                    integrals: &prepared.integrals,
                    latitude: prepared.latitude,
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

    fn push_id<S: System<N, R>, const N: usize, const R: usize>(ids: &mut Vec<&'static str>) {
        ids.push(S::info().id);
    }

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

    /// `for_each_system!` covers `SYSTEMS`, in its order.
    #[test]
    fn for_each_system_follows_the_registry() {
        let mut ids = Vec::new();
        crate::for_each_system!(push_id, &mut ids);
        let registry: Vec<_> = SYSTEMS.iter().map(|s| s.info().id).collect();
        assert_eq!(ids, registry);
    }
}
