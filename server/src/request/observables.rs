//! [`ObservablesRequest`]: the `observables` object of a request, names and formulas
//! (`{"theta": "theta", "speed": "x_dot*cos(theta) + y_dot*sin(theta)"}`), read in the order
//! given and refusing a name given twice, as every object of the API does.

use serde::Deserialize;
use serde::de::{self, MapAccess, Visitor};
use std::collections::HashSet;
use std::fmt;

/// Observables by name, each a formula, in the order given; no name twice.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ObservablesRequest(pub Vec<(String, String)>);

impl<'de> Deserialize<'de> for ObservablesRequest {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct ObservablesVisitor;
        impl<'de> Visitor<'de> for ObservablesVisitor {
            type Value = ObservablesRequest;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an object of formulas by name, e.g. {\"speed\": \"x_dot\"}")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                let (mut given, mut seen) = (Vec::new(), HashSet::new());
                while let Some(name) = map.next_key::<String>()? {
                    let formula = map.next_value::<String>()?;
                    if !seen.insert(name.clone()) {
                        return Err(de::Error::custom(format!(
                            "observable `{name}` is given twice"
                        )));
                    }
                    given.push((name, formula));
                }
                Ok(ObservablesRequest(given))
            }
        }
        d.deserialize_map(ObservablesVisitor)
    }
}

impl serde::Serialize for ObservablesRequest {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (name, formula) in &self.0 {
            map.serialize_entry(name, formula)?;
        }
        map.end()
    }
}
