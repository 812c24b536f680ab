//! OpenAPI schemas built from the core's registry, for the request bodies'
//! `#[schema(schema_with = …)]`: ids (systems, presets, methods, integrals) as enums and
//! parameter bounds as minimum/maximum, so that a client (or a fuzzer) generates meaningful
//! bodies.

use crate::config::Config;
use nhlab_core::methods::prk::Constraint;
use nhlab_core::methods::prk::stored::stored;
use nhlab_core::methods::prk::tableau::MAX_STAGES;
use nhlab_core::{Composition, Integral, ParamSpec, SYSTEMS, method_infos};
use utoipa::openapi::RefOr;
use utoipa::openapi::schema::{
    AdditionalProperties, ArrayBuilder, ObjectBuilder, OneOfBuilder, Schema, Type,
};

fn strings(values: Vec<&'static str>) -> ObjectBuilder {
    ObjectBuilder::new().schema_type(Type::String).enum_values(Some(values))
}

fn number() -> ObjectBuilder {
    ObjectBuilder::new().schema_type(Type::Number)
}

fn bounded(p: &ParamSpec) -> ObjectBuilder {
    let mut n = number().description(Some(p.description)).default(Some(p.default.into()));
    if p.min.is_finite() {
        n = if p.min_open { n.exclusive_minimum(Some(p.min)) } else { n.minimum(Some(p.min)) };
    }
    if p.max.is_finite() {
        n = if p.max_open { n.exclusive_maximum(Some(p.max)) } else { n.maximum(Some(p.max)) };
    }
    n
}

/// `system`: one of the registry's ids.
pub(crate) fn system_id() -> ObjectBuilder {
    strings(SYSTEMS.iter().map(|s| s.info().id).collect())
        .description(Some("System id (see GET /systems)"))
}

/// `system`: a system id, or a system given as formulas.
pub(crate) fn system() -> OneOfBuilder {
    OneOfBuilder::new()
        .item(system_id())
        .item(<crate::request::FormulaSystem as utoipa::PartialSchema>::schema())
        .item(<crate::request::GeneralSystem as utoipa::PartialSchema>::schema())
}

/// `preset`: one of the presets of any system (each system has its own; see GET /systems).
pub(crate) fn preset_id() -> ObjectBuilder {
    let mut ids: Vec<&'static str> =
        SYSTEMS.iter().flat_map(|s| s.info().presets.iter().map(|p| p.id)).collect();
    ids.sort_unstable();
    ids.dedup();
    strings(ids).description(Some(
        "Preset id of the system (see GET /systems); fills params, q, v, step and t_end",
    ))
}

/// `observables`: formulas by name.
pub(crate) fn observables() -> ObjectBuilder {
    ObjectBuilder::new()
        .schema_type(Type::Object)
        .additional_properties(Some(AdditionalProperties::RefOr(RefOr::T(Schema::Object(
            ObjectBuilder::new().schema_type(Type::String).build(),
        )))))
        .description(Some(
            "Observables by name, each a formula in the coordinates, their velocities \
             (x_dot), t and the parameters, e.g. {\"speed\": \"x_dot*cos(theta)\"}",
        ))
}

/// `params`: numbers by name.
pub(crate) fn params() -> ObjectBuilder {
    ObjectBuilder::new()
        .schema_type(Type::Object)
        .additional_properties(Some(AdditionalProperties::RefOr(RefOr::T(Schema::Object(
            number().build(),
        )))))
        .description(Some("Parameter overrides by name, e.g. {\"epsilon\": 0.5}"))
}

/// `q`, `v`: the initial state's components, each at most `MAX_INITIAL` in magnitude.
pub(crate) fn state() -> ArrayBuilder {
    let limit = nhlab_core::MAX_INITIAL;
    ArrayBuilder::new().items(number().minimum(Some(-limit)).maximum(Some(limit)))
}

/// `integrals`: a non-empty list of integral ids, or the names of the system's invariants.
pub(crate) fn integrals() -> ArrayBuilder {
    let ids = Integral::ALL.map(Integral::id).join(", ");
    ArrayBuilder::new()
        .items(ObjectBuilder::new().schema_type(Type::String).description(Some(format!(
            "an integral id ({ids}) or the name of one of the system's invariants"
        ))))
        .min_items(Some(1))
}

/// A `prk` method's `tableau`: a stored tableau's id, or the tableau.
fn tableau() -> OneOfBuilder {
    let stored = stored().iter().map(|t| t.id).collect();
    let vector =
        || ArrayBuilder::new().items(number()).min_items(Some(1)).max_items(Some(MAX_STAGES));
    let matrix =
        || ArrayBuilder::new().items(vector()).min_items(Some(1)).max_items(Some(MAX_STAGES));
    let given = ObjectBuilder::new()
        .schema_type(Type::Object)
        .additional_properties(Some(AdditionalProperties::FreeForm(false)))
        .property("a", matrix())
        .property("b", vector())
        .property("c", vector())
        .property("a_hat", matrix())
        .property("b_hat", vector())
        .required("a")
        .required("b");
    OneOfBuilder::new().item(strings(stored)).item(given)
}

/// A `prk` method's `constraint`.
fn constraints() -> ObjectBuilder {
    strings(Constraint::ALL.map(Constraint::id).to_vec())
}

/// `methods`: a non-empty list of method ids, `{"id": …, param: value}` objects or
/// `{"id": …, "params": {param: value}}` objects, with a `composition` for the symmetric ones.
pub(crate) fn methods() -> ArrayBuilder {
    let infos = method_infos();
    let mut one_of = OneOfBuilder::new().item(strings(infos.iter().map(|m| m.id).collect()));
    let closed = || {
        ObjectBuilder::new()
            .schema_type(Type::Object)
            .additional_properties(Some(AdditionalProperties::FreeForm(false)))
    };
    let composable = nhlab_core::methods::composable();
    let compositions = || strings(Composition::ALL.map(Composition::id).to_vec());
    for m in &infos {
        let (mut flat, mut params) =
            (closed().property("id", strings(vec![m.id])).required("id"), closed());
        let mut nested = closed();
        // A method given by tableaux composes where its tableau and constraint are symmetric.
        if composable.contains(&m.id) || m.by_tableau {
            flat = flat.property("composition", compositions());
            nested = nested.property("composition", compositions());
        }
        if m.by_tableau {
            flat = flat.property("tableau", tableau()).property("constraint", constraints());
            nested = nested.property("tableau", tableau()).property("constraint", constraints());
        }
        for p in m.params {
            flat = flat.property(p.name, bounded(p));
            params = params.property(p.name, bounded(p));
        }
        let nested = nested
            .property("id", strings(vec![m.id]))
            .property("params", params)
            .required("id")
            .required("params");
        one_of = one_of.item(flat).item(nested);
    }
    ArrayBuilder::new()
        .items(one_of)
        .min_items(Some(1))
        .max_items(Some(Config::default().max_methods))
}
