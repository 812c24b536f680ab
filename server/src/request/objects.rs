//! [`objects`]: reads a list of JSON objects (a scorecard's `scenes`) for serde's
//! `deserialize_with`, refusing an element that is not an object.

use serde::Deserialize;
use serde::de::{self, MapAccess, Visitor};
use std::fmt;

/// Reads a list of objects (a scorecard's `scenes`), refusing an element written as an array
/// of its fields, which serde's derived structs would otherwise accept. The elements are read
/// from the request's own map access, so an error keeps its path (`scenes[0].step`).
pub(crate) fn objects<'de, D: de::Deserializer<'de>, T: Deserialize<'de>>(
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
