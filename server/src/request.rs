//! The bodies that describe a scene: [`SimulateRequest`] (`POST /simulate`), [`SceneSpec`]
//! (a scene of `POST /scorecard`) and, through [`scene_body!`], `POST /work-precision`'s. They
//! are read with `serde_path_to_error`, so a wrong type or an unknown field is reported with
//! its path. Only `system` is required.

use crate::{AppError, openapi::schemas};
use serde::Deserialize;
use serde::de::{self, MapAccess, Visitor};
use std::fmt;

/// Declares a request body that starts with a scene: the fields every such body shares (with
/// their docs and schemas), then its own, and the conversions to the core's
/// [`SceneRequest`](nhlab_core::SceneRequest) and to a `/simulate` body. A macro because serde cannot `flatten` a shared struct into a
/// body that denies unknown fields.
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
            /// System id (see `GET /systems`).
            #[schema(schema_with = $crate::openapi::schemas::system_id)]
            pub system: String,
            /// Preset id; fills params, q, v, step and t_end (default: the system's first
            /// preset).
            #[serde(default)]
            #[schema(schema_with = $crate::openapi::schemas::preset_id)]
            pub preset: Option<String>,
            /// Parameter overrides by name, e.g. `{"epsilon": 0.5}`.
            #[serde(default)]
            #[schema(schema_with = $crate::openapi::schemas::params)]
            pub params: Option<std::collections::BTreeMap<String, f64>>,
            /// Initial configuration (one number per degree of freedom, each at most 1e90 in
            /// magnitude).
            #[serde(default)]
            #[schema(schema_with = $crate::openapi::schemas::state)]
            pub q: Option<Vec<f64>>,
            /// Initial velocity, consistent with the constraints (each component at most
            /// 1e90 in magnitude).
            #[serde(default)]
            #[schema(schema_with = $crate::openapi::schemas::state)]
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
            #[schema(schema_with = $crate::openapi::schemas::integrals)]
            pub integrals: Option<Vec<String>>,
            $($(#[$field_meta])* pub $field: $ty,)*
        }

        impl $name {
            /// The scene, for the core to resolve.
            pub fn scene_request(&self) -> nhlab_core::SceneRequest {
                nhlab_core::SceneRequest {
                    system: self.system.clone(),
                    preset: self.preset.clone(),
                    params: self.params.iter().flatten().map(|(n, v)| (n.clone(), *v)).collect(),
                    q: self.q.clone(),
                    v: self.v.clone(),
                    step: self.step,
                    t_end: self.t_end,
                }
            }

            /// The `/simulate` body of this scene with `methods` and `points`.
            pub fn to_simulate(
                &self,
                methods: Option<Vec<$crate::MethodRequest>>,
                points: Option<i64>,
            ) -> $crate::SimulateRequest {
                $crate::SimulateRequest {
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
    }
}

impl SimulateRequest {
    /// Reads a request body, naming the offending path on failure.
    pub fn from_json(body: &[u8]) -> Result<Self, AppError> {
        read_object(body)
    }
}

/// Reads a request body that must be one JSON object, naming the offending path on failure.
///
/// serde's derived structs also accept an array of the fields in order, so `["cvt"]` would be
/// read as `{"system": "cvt"}` and `[]` as `{}` (all defaults: a whole scorecard); any JSON
/// that is not an object is refused here first.
pub fn read_object<T: de::DeserializeOwned>(body: &[u8]) -> Result<T, AppError> {
    let first = body.iter().find(|b| !matches!(b, b' ' | b'\t' | b'\n' | b'\r'));
    if first.is_some_and(|&b| b != b'{')
        && let Ok(value) = serde_json::from_slice::<serde_json::Value>(body)
    {
        return Err(AppError::not_an_object(&value));
    }
    let de = &mut serde_json::Deserializer::from_slice(body);
    let req: T = serde_path_to_error::deserialize(&mut *de)?;
    // Nothing but whitespace may follow the object (`{…} {` is not one JSON document).
    de.end().map_err(|e| AppError::malformed(&e))?;
    Ok(req)
}

/// Reads a list of objects (a scorecard's `scenes`), refusing an element written as an array
/// of its fields, which serde's derived structs would otherwise accept. The elements are read
/// from the request's own map access, so an error keeps its path (`scenes[0].step`).
pub fn objects<'de, D: de::Deserializer<'de>, T: Deserialize<'de>>(
    d: D,
) -> Result<Option<Vec<T>>, D::Error> {
    struct Object<T>(T);
    impl<'de, T: Deserialize<'de>> Deserialize<'de> for Object<T> {
        fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            struct ObjectVisitor<T>(std::marker::PhantomData<T>);
            impl<'de, T: Deserialize<'de>> Visitor<'de> for ObjectVisitor<T> {
                type Value = T;
                fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                    f.write_str("a JSON object")
                }
                fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<T, A::Error> {
                    T::deserialize(de::value::MapAccessDeserializer::new(map))
                }
            }
            d.deserialize_map(ObjectVisitor(std::marker::PhantomData)).map(Object)
        }
    }
    let list: Option<Vec<Object<T>>> = Deserialize::deserialize(d)?;
    Ok(list.map(|l| l.into_iter().map(|Object(t)| t).collect()))
}

/// One method of a request: its id and parameter overrides, beside the id (`{"id": "dla",
/// "alpha": 0.4}`, as responses echo it) or in a `params` object (`{"id": "dla", "params":
/// {"alpha": 0.4}}`, as a scene's parameters and `GET /systems` put them); a bare string is
/// the method with its defaults.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MethodRequest {
    /// Method id.
    pub id: String,
    /// Parameters, in the order given.
    pub params: Vec<(String, f64)>,
    /// Whether they were given in a `params` object (their errors' paths then go through it).
    pub nested: bool,
}

impl MethodRequest {
    /// The method `id` with these parameters, given beside the id.
    pub fn new(id: &str, params: Vec<(String, f64)>) -> Self {
        Self { id: id.to_owned(), params, nested: false }
    }
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
        f.write_str(
            "a method: an id string, or an object {\"id\": \"dla\", \"alpha\": 0.4} or \
             {\"id\": \"dla\", \"params\": {\"alpha\": 0.4}}",
        )
    }

    fn visit_str<E: de::Error>(self, id: &str) -> Result<MethodRequest, E> {
        Ok(MethodRequest::new(id, Vec::new()))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<MethodRequest, A::Error> {
        let (mut id, mut flat, mut nested) = (None, Vec::new(), None);
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "id" if id.is_some() => return Err(de::Error::duplicate_field("id")),
                "id" => id = Some(map.next_value::<String>()?),
                "params" if nested.is_some() => return Err(de::Error::duplicate_field("params")),
                "params" => nested = Some(map.next_value::<Params>()?.0),
                _ => {
                    let value = map.next_value::<f64>()?;
                    push_param(&mut flat, key, value)?;
                }
            }
        }
        let id = id.ok_or_else(|| de::Error::missing_field("id"))?;
        match nested {
            None => Ok(MethodRequest::new(&id, flat)),
            Some(params) if flat.is_empty() => Ok(MethodRequest { id, params, nested: true }),
            Some(_) => Err(de::Error::custom(format!(
                "give the parameters of method {id} either beside its id or in `params`, not both"
            ))),
        }
    }
}

/// A method's `params` object, name by name in the order given.
struct Params(Vec<(String, f64)>);

impl<'de> Deserialize<'de> for Params {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct ParamsVisitor;
        impl<'de> Visitor<'de> for ParamsVisitor {
            type Value = Params;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an object of parameter values, e.g. {\"alpha\": 0.4}")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Params, A::Error> {
                let mut params = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    let value = map.next_value::<f64>()?;
                    push_param(&mut params, key, value)?;
                }
                Ok(Params(params))
            }
        }
        d.deserialize_map(ParamsVisitor)
    }
}

/// Adds a parameter, refusing a second value for the same name (else the last would win
/// unseen).
fn push_param<E: de::Error>(
    params: &mut Vec<(String, f64)>,
    name: String,
    value: f64,
) -> Result<(), E> {
    if params.iter().any(|(n, _)| *n == name) {
        return Err(E::custom(format!("parameter `{name}` is given twice")));
    }
    params.push((name, value));
    Ok(())
}

scene_body! {
    /// One scene of a `POST /scorecard`: a `/simulate` body without `methods` and `points`.
    pub struct SceneSpec {}
}
