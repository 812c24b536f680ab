//! [`SimulateRequest`]: the body of `POST /simulate`, and [`scene_body!`], which declares it
//! and every other body that starts with a scene ([`SceneSpec`](crate::SceneSpec),
//! [`WorkPrecisionRequest`](crate::WorkPrecisionRequest)): the scene's fields, then the
//! body's own.

use crate::request::schemas;
use crate::request::{MethodRequest, ObservablesRequest, SectionRequest};

/// Declares a request body that starts with a scene: the fields every such body shares (with
/// their docs and schemas), then its own, and the conversions to the core's
/// [`SceneRequest`](nhlab_core::SceneRequest) and to a `/simulate` body. A macro because serde
/// cannot `flatten` a shared struct into a body that denies unknown fields.
macro_rules! scene_body {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $($(#[$field_meta:meta])* pub $field:ident: $ty:ty,)*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Default, PartialEq, serde::Deserialize, utoipa::ToSchema)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            /// System id (see `GET /systems`), or a system given as formulas.
            #[schema(schema_with = $crate::request::schemas::system)]
            pub system: $crate::request::SystemField,
            /// Preset id; fills params, q, v, step and t_end (default: the system's first
            /// preset).
            #[serde(default)]
            #[schema(schema_with = $crate::request::schemas::preset_id)]
            pub preset: Option<String>,
            /// Parameter overrides by name, e.g. `{"epsilon": 0.5}`.
            #[serde(default)]
            #[schema(schema_with = $crate::request::schemas::params)]
            pub params: Option<$crate::request::Params>,
            /// Initial configuration (one number per degree of freedom, each at most 1e90 in
            /// magnitude).
            #[serde(default)]
            #[schema(schema_with = $crate::request::schemas::state)]
            pub q: Option<Vec<f64>>,
            /// Initial velocity, consistent with the constraints (each component at most
            /// 1e90 in magnitude).
            #[serde(default)]
            #[schema(schema_with = $crate::request::schemas::state)]
            pub v: Option<Vec<f64>>,
            /// Step size, positive.
            #[serde(default)]
            #[schema(exclusive_minimum = 0.0)]
            pub step: Option<f64>,
            /// Final time, at least one step.
            #[serde(default)]
            #[schema(exclusive_minimum = 0.0)]
            pub t_end: Option<f64>,
            /// Integrals to measure (default: all the system has).
            #[serde(default)]
            #[schema(schema_with = $crate::request::schemas::integrals)]
            pub integrals: Option<Vec<String>>,
            $($(#[$field_meta])* pub $field: $ty,)*
        }

        impl $name {
            /// The scene, for the core to resolve.
            pub fn scene_request(&self) -> nhlab_core::SceneRequest {
                nhlab_core::SceneRequest {
                    system: self.system.request(),
                    preset: self.preset.clone(),
                    params: self.params.iter().flat_map(|p| p.0.iter()).cloned().collect(),
                    q: self.q.clone(),
                    v: self.v.clone(),
                    step: self.step,
                    t_end: self.t_end,
                }
            }

            /// The `/simulate` body of this scene with `methods` and `points`.
            pub fn to_simulate(
                &self,
                methods: Option<Vec<$crate::request::MethodRequest>>,
                points: Option<i64>,
            ) -> $crate::request::SimulateRequest {
                $crate::request::SimulateRequest {
                    system: self.system.clone(),
                    preset: self.preset.clone(),
                    params: self.params.clone(),
                    q: self.q.clone(),
                    v: self.v.clone(),
                    step: self.step,
                    t_end: self.t_end,
                    integrals: self.integrals.clone(),
                    methods,
                    points,
                    observables: None,
                    section: None,
                }
            }
        }
    };
}
pub(crate) use scene_body;

scene_body! {
    /// The body of `POST /simulate`.
    pub struct SimulateRequest {
        /// Methods to run, each `{"id": "dla", "alpha": 0.4}`, `{"id": "dla", "params":
        /// {"alpha": 0.4}}` or just `"leapfrog"` (default: the paper's five).
        #[serde(default)]
        #[schema(schema_with = schemas::methods)]
        pub methods: Option<Vec<MethodRequest>>,
        /// Buckets per series (default 1000).
        #[serde(default)]
        #[schema(minimum = 1, maximum = 100_000)]
        pub points: Option<i64>,
        /// Quantities to sample along each run, by name, each a formula in the
        /// coordinates, their velocities (`x_dot`), `t` and the parameters; each run's
        /// answer gets them as columns (`observables`) at `points` times spread evenly over
        /// the run (default: none).
        #[serde(default)]
        #[schema(schema_with = schemas::observables)]
        pub observables: Option<ObservablesRequest>,
        /// A Poincaré section of each run: each crossing of `surface` = 0 (in `direction`),
        /// located inside its step, with the `plot` quantities there; each run's answer gets
        /// them as columns (`section`) (default: none).
        #[serde(default)]
        pub section: Option<SectionRequest>,
    }
}
