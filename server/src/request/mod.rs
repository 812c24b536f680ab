//! The request bodies: [`SimulateRequest`] (`POST /simulate`), [`ScorecardRequest`] with its
//! [`SceneSpec`]s (`POST /scorecard`), [`WorkPrecisionRequest`] (`POST /work-precision`),
//! [`SweepRequest`] with its [`AxisRequest`]s (`POST /sweep`, `nhlab sweep`), and
//! the [`MethodRequest`] they share. They are plain serde types; reading a body into one (its
//! size, its shape, the error responses) is [`JsonObject`](crate::JsonObject)'s work, and
//! checking its values against the core and the limits is [`Plan`](crate::Plan)'s. Only
//! `system` is required in a scene: a built-in's id or a system given as formulas
//! ([`SystemField`]).

mod method_request;
mod objects;
mod observables;
mod params;
mod scene_spec;
pub(crate) mod schemas;
mod scorecard_request;
mod section;
mod simulate_request;
mod sweep_request;
mod system_field;
mod tableau_field;
mod work_precision_request;

pub use method_request::MethodRequest;
pub(crate) use objects::objects;
pub use observables::ObservablesRequest;
pub use params::Params;
pub use scene_spec::SceneSpec;
pub use scorecard_request::ScorecardRequest;
pub use section::SectionRequest;
pub use simulate_request::SimulateRequest;
pub(crate) use simulate_request::scene_body;
pub use sweep_request::{AxisRequest, SweepRequest};
pub use system_field::{FormulaSystem, GeneralSystem, MassField, SystemField};
pub(crate) use tableau_field::TableauField;
pub use tableau_field::tableau_value;
pub use work_precision_request::WorkPrecisionRequest;
