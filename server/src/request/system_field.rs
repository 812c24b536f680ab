//! [`SystemField`]: a scene's `system`, a built-in's id or a system given as formulas, in
//! the paper's form ([`FormulaSystem`]: passenger, driver, U, V_d, A's passenger columns) or
//! the general one ([`GeneralSystem`]: coordinates, M, V, A, invariants; `docs/model.md`
//! §10). Read by hand rather than as an untagged enum, so that an error inside the object
//! keeps its path (`system.constraints[0][1]`) and its message; the form is told by its
//! fields (`coordinates` is the general one's). Written back the same way in the answer's
//! `scene`.

use crate::request::Params;
use nhlab_core::model::custom::{MassEntry, MassSpec};
use nhlab_core::{FormulaSpec, GeneralSpec, SystemRequest};
use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use std::collections::HashSet;
use std::fmt;

/// A system of the paper's class given as formulas, as the API reads and writes it.
#[derive(Debug, Clone, Default, PartialEq, Serialize, utoipa::ToSchema)]
pub struct FormulaSystem {
    /// A label for listings and plots (default `custom`).
    pub name: String,
    /// Passenger coordinate names x₁ … xₙ (1 to 6; q and v list them first, then the driver).
    pub passenger: Vec<String>,
    /// The driver's name ζ.
    pub driver: String,
    /// Parameters with their default values (a request's `params` overrides them).
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

/// A system given in the general form, as the API reads and writes it.
#[derive(Debug, Clone, Default, PartialEq, Serialize, utoipa::ToSchema)]
pub struct GeneralSystem {
    /// A label for listings and plots (default `custom`).
    pub name: String,
    /// Coordinate names q₁ … q_N (1 to 12; q and v list them in this order; their velocities
    /// are named `q_dot`).
    pub coordinates: Vec<String>,
    /// Parameters with their default values (a request's `params` overrides them).
    #[schema(value_type = Object)]
    pub parameters: Params,
    /// M: a diagonal list or an N×N symmetric matrix of numbers or formulas in the
    /// parameters; the identity when absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Vec<serde_json::Value>>)]
    pub mass: Option<MassField>,
    /// V(q): coordinates and parameters.
    pub potential: String,
    /// The rows of A(q), 1 to N − 1 of N entries: coordinates and parameters.
    pub constraints: Vec<Vec<String>>,
    /// Named invariants the system conserves: formulas in the coordinates, their velocities
    /// and the parameters, each measured like the energy.
    #[serde(skip_serializing_if = "Formulas::is_empty")]
    #[schema(value_type = Object)]
    pub invariants: Formulas,
    /// Whether nhlab looks for the paper's class in it (default true); false runs it on the
    /// general steps even where the class holds.
    pub detect_class: bool,
}

/// M as the API reads it: a diagonal list or a full matrix of numbers and formulas.
#[derive(Debug, Clone, PartialEq)]
pub enum MassField {
    /// `[m₁, …, m_N]`.
    Diagonal(Vec<MassEntry>),
    /// `[[…], …]`, row by row.
    Full(Vec<Vec<MassEntry>>),
}

/// Named formulas in the order given, no name twice (the invariants).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Formulas(pub Vec<(String, String)>);

impl Formulas {
    fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
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

impl GeneralSystem {
    /// As the core takes it.
    pub fn spec(&self) -> GeneralSpec {
        GeneralSpec {
            name: self.name.clone(),
            coordinates: self.coordinates.clone(),
            parameters: self.parameters.0.clone(),
            mass: match &self.mass {
                None => MassSpec::Identity,
                Some(MassField::Diagonal(d)) => MassSpec::Diagonal(d.clone()),
                Some(MassField::Full(m)) => MassSpec::Full(m.clone()),
            },
            potential: self.potential.clone(),
            constraints: self.constraints.clone(),
            invariants: self.invariants.0.clone(),
            detect_class: self.detect_class,
        }
    }

    /// As the API writes it.
    pub fn of(spec: &GeneralSpec) -> Self {
        Self {
            name: spec.name.clone(),
            coordinates: spec.coordinates.clone(),
            parameters: Params(spec.parameters.clone()),
            mass: match &spec.mass {
                MassSpec::Identity => None,
                MassSpec::Diagonal(d) => Some(MassField::Diagonal(d.clone())),
                MassSpec::Full(m) => Some(MassField::Full(m.clone())),
            },
            potential: spec.potential.clone(),
            constraints: spec.constraints.clone(),
            invariants: Formulas(spec.invariants.clone()),
            detect_class: spec.detect_class,
        }
    }
}

/// A scene's `system`.
#[derive(Debug, Clone, PartialEq)]
pub enum SystemField {
    /// A built-in's id.
    Id(String),
    /// A system of the paper's class given in its form.
    Formulas(Box<FormulaSystem>),
    /// A system given in the general form.
    General(Box<GeneralSystem>),
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
            Self::General(g) => SystemRequest::General(g.spec()),
        }
    }

    /// A system given as formulas, as the API writes it.
    pub fn of(spec: &nhlab_core::catalogue::custom::SystemSpec) -> Self {
        use nhlab_core::catalogue::custom::SystemSpec;
        match spec {
            SystemSpec::Coupled(s) => Self::Formulas(Box::new(FormulaSystem::of(s))),
            SystemSpec::General(s) => Self::General(Box::new(GeneralSystem::of(s))),
        }
    }
}

/// The id, or the name of a system given as formulas: for logs and labels.
impl fmt::Display for SystemField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Id(id) => f.write_str(id),
            Self::Formulas(s) => write!(f, "{} (formulas)", s.name),
            Self::General(s) => write!(f, "{} (formulas)", s.name),
        }
    }
}

/// Either form's fields, read at once and then told apart.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AnyForm {
    #[serde(default = "custom_name")]
    name: String,
    #[serde(default)]
    parameters: Params,
    constraints: Vec<Vec<String>>,
    passenger: Option<Vec<String>>,
    driver: Option<String>,
    passenger_potential: Option<String>,
    driver_potential: Option<String>,
    coordinates: Option<Vec<String>>,
    mass: Option<MassField>,
    potential: Option<String>,
    #[serde(default)]
    invariants: Formulas,
    detect_class: Option<bool>,
}

impl AnyForm {
    /// The form its fields make, or why they make neither.
    fn into_field(self) -> Result<SystemField, String> {
        let paper = [
            ("passenger", self.passenger.is_some()),
            ("driver", self.driver.is_some()),
            ("passenger_potential", self.passenger_potential.is_some()),
            ("driver_potential", self.driver_potential.is_some()),
        ];
        let general = [
            ("coordinates", self.coordinates.is_some()),
            ("mass", self.mass.is_some()),
            ("potential", self.potential.is_some()),
            ("invariants", !self.invariants.is_empty()),
            ("detect_class", self.detect_class.is_some()),
        ];
        let given = |fields: &[(&'static str, bool)]| -> Vec<&'static str> {
            fields.iter().filter(|f| f.1).map(|f| f.0).collect()
        };
        let (paper_given, general_given) = (given(&paper), given(&general));
        if let Some(coordinates) = self.coordinates {
            if !paper_given.is_empty() {
                return Err(format!(
                    "{} belong to the paper's form (passenger, driver, passenger_potential, \
                     driver_potential), not to the general form that `coordinates` starts",
                    paper_given.join(", ")
                ));
            }
            return Ok(SystemField::General(Box::new(GeneralSystem {
                name: self.name,
                coordinates,
                parameters: self.parameters,
                mass: self.mass,
                potential: self
                    .potential
                    .ok_or("missing field `potential` (V(q); \"0\" for none)")?,
                constraints: self.constraints,
                invariants: self.invariants,
                detect_class: self.detect_class.unwrap_or(true),
            })));
        }
        if !general_given.is_empty() {
            return Err(format!(
                "{} belong to the general form, which names its coordinates (`coordinates`)",
                general_given.join(", ")
            ));
        }
        let missing = |field: &str| format!("missing field `{field}`");
        Ok(SystemField::Formulas(Box::new(FormulaSystem {
            name: self.name,
            passenger: self.passenger.ok_or_else(|| {
                "a system given as formulas names its `coordinates` (the general form) or its \
                 `passenger` and `driver` (the paper's form)"
                    .to_string()
            })?,
            driver: self.driver.ok_or_else(|| missing("driver"))?,
            parameters: self.parameters,
            passenger_potential: self
                .passenger_potential
                .ok_or_else(|| missing("passenger_potential"))?,
            driver_potential: self.driver_potential.ok_or_else(|| missing("driver_potential"))?,
            constraints: self.constraints,
        })))
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
                let any = AnyForm::deserialize(de::value::MapAccessDeserializer::new(map))?;
                any.into_field().map_err(de::Error::custom)
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
            Self::General(g) => g.serialize(s),
        }
    }
}

/// A mass entry as JSON writes it: a number or a formula.
fn entry<E: de::Error>(value: &serde_json::Value) -> Result<MassEntry, E> {
    match value {
        serde_json::Value::Number(n) => n
            .as_f64()
            .map(MassEntry::Number)
            .ok_or_else(|| E::custom("a mass entry is a number or a formula")),
        serde_json::Value::String(s) => Ok(MassEntry::Formula(s.clone())),
        _ => Err(E::custom(format!(
            "a mass entry is a number or a formula in the parameters, got {value}"
        ))),
    }
}

impl<'de> Deserialize<'de> for MassField {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let value = serde_json::Value::deserialize(d)?;
        let shape = "`mass` is a list (the diagonal of M) or a list of rows (M)";
        let serde_json::Value::Array(items) = &value else { return Err(de::Error::custom(shape)) };
        if items.iter().all(|x| x.is_array()) && !items.is_empty() {
            let rows = items
                .iter()
                .map(|row| row.as_array().into_iter().flatten().map(entry).collect())
                .collect::<Result<_, _>>()?;
            Ok(Self::Full(rows))
        } else {
            Ok(Self::Diagonal(items.iter().map(entry).collect::<Result<_, _>>()?))
        }
    }
}

impl Serialize for MassField {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let one = |e: &MassEntry| match e {
            MassEntry::Number(x) => serde_json::json!(x),
            MassEntry::Formula(f) => serde_json::json!(f),
        };
        match self {
            Self::Diagonal(d) => d.iter().map(one).collect::<Vec<_>>().serialize(s),
            Self::Full(m) => m
                .iter()
                .map(|row| row.iter().map(one).collect::<Vec<_>>())
                .collect::<Vec<_>>()
                .serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Formulas {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct FormulasVisitor;
        impl<'de> Visitor<'de> for FormulasVisitor {
            type Value = Formulas;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an object of named formulas, e.g. {\"momentum\": \"x_dot + y_dot\"}")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Formulas, A::Error> {
                let (mut out, mut seen) = (Vec::new(), HashSet::new());
                while let Some(key) = map.next_key::<String>()? {
                    let value = map.next_value::<String>()?;
                    if !seen.insert(key.clone()) {
                        return Err(de::Error::custom(format!("`{key}` is given twice")));
                    }
                    out.push((key, value));
                }
                Ok(Formulas(out))
            }
        }
        d.deserialize_map(FormulasVisitor)
    }
}

impl Serialize for Formulas {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (name, formula) in &self.0 {
            map.serialize_entry(name, formula)?;
        }
        map.end()
    }
}
