//! [`SimulateRequest`]: the body of `POST /simulate`, read with `serde_path_to_error` so a
//! wrong type or an unknown field is reported with its path. Only `system` is required.

use crate::{AppError, openapi::schemas};
use serde::Deserialize;
use serde::de::{self, MapAccess, Visitor};
use std::collections::BTreeMap;
use std::fmt;
use utoipa::ToSchema;

/// The body of `POST /simulate`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SimulateRequest {
    /// System id (see `GET /systems`).
    #[schema(schema_with = schemas::system_id)]
    pub system: String,
    /// Preset id; fills params, q, v, step and t_end (default: the system's first preset).
    #[serde(default)]
    #[schema(schema_with = schemas::preset_id)]
    pub preset: Option<String>,
    /// Parameter overrides by name, e.g. `{"epsilon": 0.5}`.
    #[serde(default)]
    #[schema(schema_with = schemas::params)]
    pub params: Option<BTreeMap<String, f64>>,
    /// Initial configuration (one number per degree of freedom).
    #[serde(default)]
    pub q: Option<Vec<f64>>,
    /// Initial velocity, consistent with the constraints.
    #[serde(default)]
    pub v: Option<Vec<f64>>,
    /// Step size, positive.
    #[serde(default)]
    #[schema(exclusive_minimum = 0.0)]
    pub step: Option<f64>,
    /// Final time, at least one step.
    #[serde(default)]
    #[schema(exclusive_minimum = 0.0)]
    pub t_end: Option<f64>,
    /// Methods to run, each `{"id": "dla", "alpha": 0.4}` or just `"leapfrog"`
    /// (default: the paper's five).
    #[serde(default)]
    #[schema(schema_with = schemas::methods)]
    pub methods: Option<Vec<MethodRequest>>,
    /// Integrals to measure (default: all the system has).
    #[serde(default)]
    #[schema(schema_with = schemas::integrals)]
    pub integrals: Option<Vec<String>>,
    /// Buckets per series (default 1000).
    #[serde(default)]
    #[schema(minimum = 1, maximum = 100_000)]
    pub points: Option<i64>,
}

impl SimulateRequest {
    /// Reads a request body, naming the offending path on failure.
    pub fn from_json(body: &[u8]) -> Result<Self, AppError> {
        let de = &mut serde_json::Deserializer::from_slice(body);
        let req: Self = serde_path_to_error::deserialize(&mut *de)?;
        // Nothing but whitespace may follow the object (`{…} {` is not one JSON document).
        de.end().map_err(|e| AppError::malformed(&e))?;
        Ok(req)
    }
}

/// One method of a request: its id and parameter overrides, e.g. `{"id": "dla", "alpha":
/// 0.4}`; a bare string is the method with its defaults.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MethodRequest {
    /// Method id.
    pub id: String,
    /// Parameters, in the order given.
    pub params: Vec<(String, f64)>,
}

impl<'de> Deserialize<'de> for MethodRequest {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(MethodVisitor)
    }
}

struct MethodVisitor;

impl<'de> Visitor<'de> for MethodVisitor {
    type Value = MethodRequest;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a method: an object {\"id\": \"dla\", \"alpha\": 0.4} or an id string")
    }

    fn visit_str<E: de::Error>(self, id: &str) -> Result<MethodRequest, E> {
        Ok(MethodRequest { id: id.to_owned(), params: Vec::new() })
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<MethodRequest, A::Error> {
        let mut id = None;
        let mut params = Vec::new();
        while let Some(key) = map.next_key::<String>()? {
            if key == "id" {
                if id.is_some() {
                    return Err(de::Error::duplicate_field("id"));
                }
                id = Some(map.next_value::<String>()?);
            } else {
                let value = map.next_value::<f64>()?;
                params.push((key, value));
            }
        }
        let id = id.ok_or_else(|| de::Error::missing_field("id"))?;
        Ok(MethodRequest { id, params })
    }
}

/// One scene of a `POST /scorecard`: a `/simulate` body without `methods` and `points`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// System id (see `GET /systems`).
    #[schema(schema_with = schemas::system_id)]
    pub system: String,
    /// Preset id (default: the system's first preset).
    #[serde(default)]
    #[schema(schema_with = schemas::preset_id)]
    pub preset: Option<String>,
    /// Parameter overrides by name.
    #[serde(default)]
    #[schema(schema_with = schemas::params)]
    pub params: Option<BTreeMap<String, f64>>,
    /// Initial configuration.
    #[serde(default)]
    pub q: Option<Vec<f64>>,
    /// Initial velocity, consistent with the constraints.
    #[serde(default)]
    pub v: Option<Vec<f64>>,
    /// Step size, positive.
    #[serde(default)]
    #[schema(exclusive_minimum = 0.0)]
    pub step: Option<f64>,
    /// Final time, at least one step.
    #[serde(default)]
    #[schema(exclusive_minimum = 0.0)]
    pub t_end: Option<f64>,
    /// Integrals to judge (default: all the system has).
    #[serde(default)]
    #[schema(schema_with = schemas::integrals)]
    pub integrals: Option<Vec<String>>,
}

impl SceneSpec {
    /// The `/simulate` body of this scene with `methods` and `points`.
    pub fn into_simulate(
        self,
        methods: Vec<MethodRequest>,
        points: Option<i64>,
    ) -> SimulateRequest {
        SimulateRequest {
            system: self.system,
            preset: self.preset,
            params: self.params,
            q: self.q,
            v: self.v,
            step: self.step,
            t_end: self.t_end,
            methods: Some(methods),
            integrals: self.integrals,
            points,
        }
    }
}
