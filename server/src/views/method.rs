//! [`MethodView`]: a configured method as every answer reports it: its id, its parameters
//! inline, its composition if any, a `prk` method's tableau and constraint, and its label.

use crate::views::TableauEcho;
use nhlab_core::{BaseMethod, Method};
use serde::Serialize;
use std::collections::BTreeMap;
use utoipa::ToSchema;

/// A configured method: its id, its parameters (e.g. `alpha`) and its label.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct MethodView {
    /// Method id.
    pub id: String,
    /// Parameter values by name, inline (e.g. `"alpha": 0.4`).
    #[serde(flatten)]
    pub params: BTreeMap<String, f64>,
    /// The composition it is taken in (`p4s3`, …), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub composition: Option<String>,
    /// A `prk` method's tableau: a stored one's id, or the tableau given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tableau: Option<TableauEcho>,
    /// A `prk` method's constraint (`stage`, `end`, `midpoint`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub constraint: Option<String>,
    /// Short label, e.g. `DLA^0.4` or `LF∘p4s3`.
    pub label: String,
}

impl MethodView {
    /// The view of a method.
    pub fn of(method: &Method) -> Self {
        Self {
            id: method.info().id.to_owned(),
            params: method.params().into_iter().map(|(n, v)| (n.to_owned(), v)).collect(),
            composition: method.composition.map(|c| c.id().to_owned()),
            tableau: match &method.base {
                BaseMethod::Prk(m) => Some(TableauEcho::of(m)),
                _ => None,
            },
            constraint: match &method.base {
                BaseMethod::Prk(m) => Some(m.constraint.id().to_owned()),
                _ => None,
            },
            label: method.label(),
        }
    }
}
