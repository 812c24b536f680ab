//! nhlab-core: the numerics of nhlab, without I/O.
//!
//! Six wings, each a folder:
//! - [`model`]: the class of nonholonomically coupled systems ([`System`]), the test
//!   systems ([`systems`]) and the state a step moves ([`State`]);
//! - [`methods`]: the integrators, one file or folder each, with the [`Integrator`] trait
//!   and each method's own memory ([`methods::Memory`]); [`Method`] is the one list of them;
//! - [`solver`]: the kernels the implicit methods share (Newton, small linear algebra,
//!   double-double arithmetic, angle tracking);
//! - [`measure`]: what a run measures (integrals, the latitude, buckets, verdicts,
//!   properties, the reference solution, work–precision) and the driver that runs a method
//!   on a problem and hands the error series to an [`Observer`];
//! - [`formula`]: the small compiler behind systems given as formulas (parse, symbolic
//!   derivatives, tapes);
//! - [`catalogue`]: the registry of systems and the scenes users ask for.
//!
//! The mathematics is written up in `docs/model.md`; the code cites its sections. Names
//! follow the paper (Modin & Verdier, *What makes nonholonomic integrators work?*).
#![warn(missing_docs)]

pub mod catalogue;
pub mod error;
pub mod formula;
pub(crate) mod linalg;
pub mod measure;
pub mod methods;
pub mod model;
pub mod solver;

pub use catalogue::custom::CustomSystem;
pub use catalogue::registry::{
    PAPER_SCENES, PAPER_SECTION, SYSTEMS, SystemCode, SystemEntry, system,
};
pub use catalogue::scene::{
    CompiledSystems, MAX_INITIAL, PreparedScene, Scene, SceneRequest, SceneSystem, SystemRequest,
};
pub use error::{InputError, RunError, Short, StepFailure};
pub use measure::bucket::{Bucket, Bucketer};
pub use measure::classify::{Verdict, VerdictKind, classify};
pub use measure::gap::{Gap, GapReason};
pub use measure::properties::Properties;
pub use measure::simulate::{Collect, Observer, Problem, RunConfig, RunOutcome};
pub use methods::integrator::{Integrator, MethodInfo, Stepper};
pub use methods::{
    BaseMethod, Composed, Composition, GeneralMemory, Method, MethodMemory, MethodSpec,
    method_info, method_infos,
};
pub use model::custom::{CustomLimits, FormulaSpec, GeneralSpec};
pub use model::integral::{Integral, MAX_INVARIANTS};
pub use model::mechanical::{General, Mechanical};
pub use model::state::State;
pub use model::system::{BuiltIn, DriverTerms, ParamSpec, Preset, System, SystemInfo};
pub use model::systems;
pub use solver::newton::NewtonConfig;

/// A column vector of fixed size: the numerics never allocate per step.
pub type Vector<const N: usize> = nalgebra::SVector<f64, N>;
/// A matrix of fixed size.
pub type Matrix<const R: usize, const C: usize> = nalgebra::SMatrix<f64, R, C>;
