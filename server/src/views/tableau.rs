//! A `prk` method's tableau as answers show it ([`TableauEcho`]: a stored one's id, a given one
//! in full) and the stored tableaux as `GET /systems` lists them ([`StoredTableauView`]).

use nhlab_core::methods::TableauChoice;
use nhlab_core::methods::prk::stored::StoredTableau;
use nhlab_core::methods::prk::tableau::{Tableau, TableauSpec};
use nhlab_core::methods::prk::{Constraint, Prk};
use serde::Serialize;
use utoipa::ToSchema;

/// A partitioned Runge–Kutta tableau: `a`, `b`, `c` for the positions, `a_hat`, `b_hat` for
/// the velocities and forces.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct TableauView {
    /// s rows of s.
    pub a: Vec<Vec<f64>>,
    /// s weights.
    pub b: Vec<f64>,
    /// s nodes, the row sums of `a` (absent only in the echo of a request that did not
    /// resolve, where it was not given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub c: Option<Vec<f64>>,
    /// s rows of s (absent as `c`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a_hat: Option<Vec<Vec<f64>>>,
    /// s weights (absent as `c`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub b_hat: Option<Vec<f64>>,
}

impl TableauView {
    /// The view of a tableau.
    pub fn of(t: &Tableau) -> Self {
        Self::given(t.spec())
    }

    /// A tableau as a request gave it.
    fn given(spec: TableauSpec) -> Self {
        Self { a: spec.a, b: spec.b, c: spec.c, a_hat: spec.a_hat, b_hat: spec.b_hat }
    }
}

/// A `prk` method's tableau as an answer echoes it: the stored tableau's id, or the tableau.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
#[serde(untagged)]
pub enum TableauEcho {
    /// A stored tableau's id.
    Stored(String),
    /// A tableau given in the request.
    Given(TableauView),
}

impl TableauEcho {
    /// The echo of a method's tableau.
    pub fn of(m: &Prk) -> Self {
        match m.stored {
            Some(id) => Self::Stored(id.into()),
            None => Self::Given(TableauView::of(&m.tableau)),
        }
    }

    /// The echo of a tableau as a request gave it (a method that did not resolve).
    pub fn requested(t: &TableauChoice) -> Self {
        match t {
            TableauChoice::Stored(id) => Self::Stored(id.clone()),
            TableauChoice::Given(spec) => Self::Given(TableauView::given(spec.clone())),
        }
    }

    /// The same as a request gives it.
    pub fn choice(m: &Prk) -> TableauChoice {
        match m.stored {
            Some(id) => TableauChoice::Stored(id.into()),
            None => TableauChoice::Given(m.tableau.spec()),
        }
    }
}

/// A stored tableau, for `{"id": "prk", "tableau": id}`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct StoredTableauView {
    /// Id.
    pub id: String,
    /// Human name.
    pub name: String,
    /// Stages s.
    pub stages: usize,
    /// Classical order, from the order conditions of `q̇ = v, v̇ = g(q, v)`.
    pub order: u32,
    /// Whether the tableau is symmetric.
    pub symmetric: bool,
    /// The constraints it takes (`stage` only where as many stages carry multipliers as
    /// carry conditions), each with the order and symmetry of the method it makes.
    pub constraints: Vec<ConstraintView>,
    /// Where it comes from.
    pub reference: String,
    /// The tableau.
    pub tableau: TableauView,
}

/// A stored tableau with one constraint: the method `{"id": "prk", "tableau": …,
/// "constraint": …}`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ConstraintView {
    /// `stage`, `end` or `midpoint`.
    pub id: String,
    /// The method's order.
    pub order: u32,
    /// Whether the method's step is symmetric (it may then be composed).
    pub symmetric: bool,
    /// Its label.
    pub label: String,
}

impl StoredTableauView {
    /// The view of a stored tableau.
    pub fn of(t: &StoredTableau) -> Self {
        use nhlab_core::Integrator;
        let choice = TableauChoice::Stored(t.id.into());
        Self {
            id: t.id.into(),
            name: t.name.into(),
            stages: t.tableau.stages,
            order: t.order,
            symmetric: t.tableau.symmetric(),
            constraints: Constraint::ALL
                .into_iter()
                .filter_map(|c| Prk::new(Some(&choice), Some(c.id())).ok())
                .map(|m| ConstraintView {
                    id: m.constraint.id().into(),
                    order: m.order(),
                    symmetric: m.symmetric(),
                    label: m.label(),
                })
                .collect(),
            reference: t.reference.into(),
            tableau: TableauView::of(&t.tableau),
        }
    }
}
