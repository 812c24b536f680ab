//! [`MethodRequest`]: one method of a request, as an id string or an object with its
//! parameters beside the id or in a `params` object; a parameter given twice is refused.

use crate::request::TableauField;
use crate::request::params::{Params, push_param};
use nhlab_core::methods::TableauChoice;
use serde::Deserialize;
use serde::de::{self, MapAccess, Visitor};
use std::collections::HashSet;
use std::fmt;

/// One method of a request: its id and parameter overrides, beside the id (`{"id": "dla",
/// "alpha": 0.4}`, as responses echo it) or in a `params` object (`{"id": "dla", "params":
/// {"alpha": 0.4}}`, as a scene's parameters and `GET /systems` put them); a bare string is
/// the method with its defaults. `"composition": "p4s3"` beside the id takes a symmetric
/// method as that composition of its steps. A `prk` method takes `"tableau"` (a stored
/// tableau's id or the tableau) and `"constraint"` beside its id.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MethodRequest {
    /// Method id.
    pub id: String,
    /// Parameters, in the order given.
    pub params: Vec<(String, f64)>,
    /// Whether they were given in a `params` object (their errors' paths then go through it).
    pub nested: bool,
    /// The composition it is taken in (`"p4s3"`, …), if any.
    pub composition: Option<String>,
    /// A `prk` method's tableau, if given.
    pub tableau: Option<TableauChoice>,
    /// A `prk` method's constraint, if given.
    pub constraint: Option<String>,
}

impl MethodRequest {
    /// The method `id` with these parameters, given beside the id.
    pub fn new(id: &str, params: Vec<(String, f64)>) -> Self {
        Self { id: id.to_owned(), params, ..Self::default() }
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
             {\"id\": \"dla\", \"params\": {\"alpha\": 0.4}}, optionally with \
             \"composition\": \"p4s3\" (and for prk \"tableau\" and \"constraint\")",
        )
    }

    fn visit_str<E: de::Error>(self, id: &str) -> Result<MethodRequest, E> {
        Ok(MethodRequest::new(id, Vec::new()))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<MethodRequest, A::Error> {
        let (mut id, mut flat, mut nested, mut composition) = (None, Vec::new(), None, None);
        let (mut tableau, mut constraint) = (None, None);
        let mut seen = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            match key.as_str() {
                "id" if id.is_some() => return Err(de::Error::duplicate_field("id")),
                "id" => id = Some(map.next_value::<String>()?),
                "params" if nested.is_some() => return Err(de::Error::duplicate_field("params")),
                "params" => nested = Some(map.next_value::<Params>()?.0),
                "composition" if composition.is_some() => {
                    return Err(de::Error::duplicate_field("composition"));
                }
                "composition" => composition = Some(map.next_value::<String>()?),
                "tableau" if tableau.is_some() => {
                    return Err(de::Error::duplicate_field("tableau"));
                }
                "tableau" => tableau = Some(map.next_value::<TableauField>()?.0),
                "constraint" if constraint.is_some() => {
                    return Err(de::Error::duplicate_field("constraint"));
                }
                "constraint" => constraint = Some(map.next_value::<String>()?),
                _ => {
                    let value = map.next_value::<f64>()?;
                    push_param(&mut flat, &mut seen, key, value)?;
                }
            }
        }
        let id = id.ok_or_else(|| de::Error::missing_field("id"))?;
        match nested {
            None => Ok(MethodRequest {
                composition,
                tableau,
                constraint,
                ..MethodRequest::new(&id, flat)
            }),
            Some(params) if flat.is_empty() => {
                Ok(MethodRequest { id, params, nested: true, composition, tableau, constraint })
            }
            Some(_) => Err(de::Error::custom(format!(
                "give the parameters of method {id} either beside its id or in `params`, not both"
            ))),
        }
    }
}
