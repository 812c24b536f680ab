//! [`SystemField`]: a scene's `system`, either a built-in's id or a system given as formulas
//! ([`FormulaSystem`], `docs/model.md` §7). Read by hand rather than as an untagged enum, so
//! that an error inside the object keeps its path (`system.constraints[0][1]`) and its
//! message; written back the same way in the answer's `scene`.

use crate::request::Params;
use nhlab_core::{FormulaSpec, SystemRequest};
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use std::fmt;

/// A system given as formulas, as the API reads and writes it.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize, utoipa::ToSchema)]
#[serde(deny_unknown_fields)]
pub struct FormulaSystem {
    /// A label for listings and plots (default `custom`).
    #[serde(default = "custom_name")]
    pub name: String,
    /// Passenger coordinate names x₁ … xₙ (1 to 6; q and v list them first, then the driver).
    pub passenger: Vec<String>,
    /// The driver's name ζ.
    pub driver: String,
    /// Parameters with their default values (a request's `params` overrides them).
    #[serde(default)]
    #[schema(value_type = Object)]
    pub parameters: Params,
    /// U(x): passenger coordinates and parameters only.
    pub passenger_potential: String,
    /// V_d(ζ): the driver and parameters only.
    pub driver_potential: String,
    /// The passenger columns of A(ζ), 1 to n − 1 rows of n entries: the driver and
    /// parameters only.
    pub constraints: Vec<Vec<String>>,
}

fn custom_name() -> String {
    "custom".into()
}

impl FormulaSystem {
    /// As the core takes it.
    pub fn spec(&self) -> FormulaSpec {
        FormulaSpec {
            name: self.name.clone(),
            passenger: self.passenger.clone(),
            driver: self.driver.clone(),
            parameters: self.parameters.0.clone(),
            passenger_potential: self.passenger_potential.clone(),
            driver_potential: self.driver_potential.clone(),
            constraints: self.constraints.clone(),
        }
    }

    /// As the API writes it.
    pub fn of(spec: &FormulaSpec) -> Self {
        Self {
            name: spec.name.clone(),
            passenger: spec.passenger.clone(),
            driver: spec.driver.clone(),
            parameters: Params(spec.parameters.clone()),
            passenger_potential: spec.passenger_potential.clone(),
            driver_potential: spec.driver_potential.clone(),
            constraints: spec.constraints.clone(),
        }
    }
}

/// A scene's `system`.
#[derive(Debug, Clone, PartialEq)]
pub enum SystemField {
    /// A built-in's id.
    Id(String),
    /// A system given as formulas.
    Formulas(Box<FormulaSystem>),
}

impl Default for SystemField {
    fn default() -> Self {
        Self::Id(String::new())
    }
}

impl From<&str> for SystemField {
    fn from(id: &str) -> Self {
        Self::Id(id.into())
    }
}

impl SystemField {
    /// As the core takes it.
    pub fn request(&self) -> SystemRequest {
        match self {
            Self::Id(id) => SystemRequest::Id(id.clone()),
            Self::Formulas(f) => SystemRequest::Formulas(f.spec()),
        }
    }
}

/// The id, or the name of a system given as formulas: for logs and labels.
impl fmt::Display for SystemField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Id(id) => f.write_str(id),
            Self::Formulas(s) => write!(f, "{} (formulas)", s.name),
        }
    }
}

impl<'de> Deserialize<'de> for SystemField {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct SystemVisitor;
        impl<'de> Visitor<'de> for SystemVisitor {
            type Value = SystemField;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a string (a system id, see GET /systems) or an object (a system given as \
                     formulas)",
                )
            }
            fn visit_str<E: de::Error>(self, id: &str) -> Result<SystemField, E> {
                Ok(SystemField::Id(id.into()))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<SystemField, A::Error> {
                let f = FormulaSystem::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(SystemField::Formulas(Box::new(f)))
            }
        }
        d.deserialize_any(SystemVisitor)
    }
}

impl Serialize for SystemField {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Id(id) => s.serialize_str(id),
            Self::Formulas(f) => f.serialize(s),
        }
    }
}
