//! [`Params`]: an object of named numbers (a scene's `params`, a method's `params`), read in
//! the order given and refusing a name given twice: serde's maps keep the last value of a
//! repeated key unseen, while every other object of the API refuses duplicate fields.

use serde::Deserialize;
use serde::de::{self, MapAccess, Visitor};
use std::collections::HashSet;
use std::fmt;

/// Parameter values by name, in the order given; no name twice.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Params(pub Vec<(String, f64)>);

impl<'de> Deserialize<'de> for Params {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct ParamsVisitor;
        impl<'de> Visitor<'de> for ParamsVisitor {
            type Value = Params;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an object of parameter values, e.g. {\"alpha\": 0.4}")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Params, A::Error> {
                let (mut params, mut seen) = (Vec::new(), HashSet::new());
                while let Some(key) = map.next_key::<String>()? {
                    let value = map.next_value::<f64>()?;
                    push_param(&mut params, &mut seen, key, value)?;
                }
                Ok(Params(params))
            }
        }
        d.deserialize_map(ParamsVisitor)
    }
}

impl serde::Serialize for Params {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (name, value) in &self.0 {
            map.serialize_entry(name, value)?;
        }
        map.end()
    }
}

impl FromIterator<(String, f64)> for Params {
    fn from_iter<I: IntoIterator<Item = (String, f64)>>(iter: I) -> Self {
        Self(iter.into_iter().collect())
    }
}

/// The error of a parameter given twice (else the last value would win unseen).
fn twice<E: de::Error>(name: &str) -> E {
    E::custom(format!("parameter `{name}` is given twice"))
}

/// Adds a parameter, refusing a second value for the same name; `seen` holds the names so
/// far (a body may hold thousands of them).
pub(crate) fn push_param<E: de::Error>(
    params: &mut Vec<(String, f64)>,
    seen: &mut HashSet<String>,
    name: String,
    value: f64,
) -> Result<(), E> {
    if !seen.insert(name.clone()) {
        return Err(twice(&name));
    }
    params.push((name, value));
    Ok(())
}
