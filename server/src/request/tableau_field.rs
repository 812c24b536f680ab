//! A `prk` method's `tableau` as a request gives it: a stored tableau's id, or an object
//! `{"a": [[…]], "b": […], "c": […], "a_hat": [[…]], "b_hat": […]}` (`c`, `a_hat`, `b_hat`
//! optional), read with the path of any error inside it. Its values are checked by the core.

use nhlab_core::methods::TableauChoice;
use nhlab_core::methods::prk::tableau::TableauSpec;
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer};
use serde_json::Value;
use std::fmt;

/// The given form's fields.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Given {
    a: Vec<Vec<f64>>,
    b: Vec<f64>,
    c: Option<Vec<f64>>,
    a_hat: Option<Vec<Vec<f64>>>,
    b_hat: Option<Vec<f64>>,
}

/// A `tableau` field, read.
pub(crate) struct TableauField(pub TableauChoice);

impl<'de> Deserialize<'de> for TableauField {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(TableauVisitor)
    }
}

struct TableauVisitor;

impl<'de> Visitor<'de> for TableauVisitor {
    type Value = TableauField;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(
            "a stored tableau's id (GET /systems lists them under `tableaux`) or a tableau \
             {\"a\": [[..]], \"b\": [..], \"c\": [..], \"a_hat\": [[..]], \"b_hat\": [..]}",
        )
    }

    fn visit_str<E: de::Error>(self, id: &str) -> Result<TableauField, E> {
        Ok(TableauField(TableauChoice::Stored(id.to_owned())))
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<TableauField, A::Error> {
        let g = Given::deserialize(de::value::MapAccessDeserializer::new(map))?;
        Ok(TableauField(TableauChoice::Given(TableauSpec {
            a: g.a,
            b: g.b,
            c: g.c,
            a_hat: g.a_hat,
            b_hat: g.b_hat,
        })))
    }
}

/// A tableau as JSON, as a request gives it (what a sweep's rows echo).
pub fn tableau_value(t: &TableauChoice) -> Value {
    match t {
        TableauChoice::Stored(id) => Value::from(id.clone()),
        TableauChoice::Given(s) => {
            let mut out = serde_json::Map::new();
            out.insert("a".into(), serde_json::json!(s.a));
            out.insert("b".into(), serde_json::json!(s.b));
            for (name, v) in [("c", &s.c), ("b_hat", &s.b_hat)] {
                if let Some(v) = v {
                    out.insert(name.into(), serde_json::json!(v));
                }
            }
            if let Some(a_hat) = &s.a_hat {
                out.insert("a_hat".into(), serde_json::json!(a_hat));
            }
            Value::Object(out)
        }
    }
}
