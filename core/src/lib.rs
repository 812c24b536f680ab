//! nhlab-core: the numerics of nhlab, without I/O.
//!
//! Modin & Verdier's nonholonomic test systems ([`systems`]), the integrators of the
//! literature ([`methods`]), the first integrals and their error series ([`Integral`],
//! [`Bucketer`]), the hidden latitude integral ([`latitude`]) and the driver that runs a
//! method on a scene and hands the downsampled error series to an [`Observer`]
//! ([`simulate`]). The [`registry`] lists every system and every method; it feeds the
//! server's `GET /systems` and the cross-product tests.
//!
//! `shared/MATH.md` of the project is the specification; names follow the paper.
#![warn(missing_docs)]

pub(crate) mod angle_tracker;
pub mod bucket;
pub mod classify;
pub(crate) mod double_double;
pub(crate) mod driver_history;
pub mod error;
pub mod integral;
pub mod latitude;
pub(crate) mod linalg;
pub mod method;
pub mod methods;
pub mod newton;
pub(crate) mod passenger_kernel;
pub mod properties;
pub mod reference;
pub mod registry;
pub mod scene;
pub mod simulate;
pub mod state;
pub mod system;
pub mod systems;
pub(crate) mod whole_turns;
pub mod work_precision;

pub use bucket::{Bucket, Bucketer};
pub use classify::{Verdict, VerdictKind, classify};
pub use error::{InputError, RunError, Short, StepFailure};
pub use integral::Integral;
pub use method::{Integrator, MethodInfo};
pub use newton::NewtonConfig;
pub use properties::Properties;
pub use registry::{
    Method, MethodSpec, PAPER_SCENES, SYSTEMS, SystemEntry, method_info, method_infos, system,
};
pub use scene::{MAX_INITIAL, PreparedScene, Scene, SceneRequest};
pub use simulate::{Collect, Observer, Problem, RunConfig, RunOutcome};
pub use state::State;
pub use system::{DriverTerms, ParamSpec, Preset, System, SystemInfo};

/// A column vector of fixed size: the numerics never allocate per step.
pub type Vector<const N: usize> = nalgebra::SVector<f64, N>;
/// A matrix of fixed size.
pub type Matrix<const R: usize, const C: usize> = nalgebra::SMatrix<f64, R, C>;
