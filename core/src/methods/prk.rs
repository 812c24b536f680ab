//! `prk`: a partitioned Runge–Kutta method given as its tableau, with the constraint imposed
//! one of three ways (`docs/model.md` §3, "methods given as tableaux"), so that a researcher
//! can try a new tableau without code. With stage multipliers Λ_j and `k_j = hA(Q_j)ᵀΛ_j −
//! h∇V(Q_j)`:
//!
//! ```text
//! Q_i = q₀ + h Σ_j a_ij V_j,    M V_i = M q̇₀ + Σ_j â_ij k_j
//! q₁  = q₀ + h Σ_j b_j V_j,     M q̇₁ = M q̇₀ + Σ_j b̂_j k_j
//! ```
//!
//! - `stage`: a multiplier for every stage whose column of â is nonzero, fixed by the
//!   conditions `Σ_j a_ij A(Q_j) V_j = 0` for every nonzero row i of a (as many, or the
//!   request is refused); q̇₁ is then projected onto the constraint at q₁ in the M-norm. On
//!   the Lobatto IIIA–IIIB pairs this is the SPARK method, which it is tested against.
//! - `end`: one multiplier for all stages, fixed by `A(q₁) q̇₁ = 0`.
//! - `midpoint`: one multiplier for all stages, fixed by `A((q₀ + q₁)/2)(q₁ − q₀) = 0`, as
//!   the discrete gradients impose it; q̇₁ is left where the step puts it.
//!
//! The tableau is checked ([`Tableau::checked`]), its classical order computed from the order
//! conditions ([`order::classical_order`]); the step is declared symmetric where the tableau
//! is and the constraint keeps it (`end` and `midpoint` on states on the constraint, `stage`
//! where the end projection is a stage's own, as in the Lobatto pairs). Newton solves the whole system densely: this is the
//! family to try tableaux in, and the SPARK methods are its fast members.

mod general;
pub mod order;
pub mod stored;
pub mod tableau;

use self::stored::stored_tableau;
pub use self::tableau::TableauChoice;
use self::tableau::Tableau;
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::{GeneralStepper, Integrator, MethodInfo, Stepper};
use crate::model::mechanical::General;
use crate::model::system::System;
use crate::solver::newton::NewtonConfig;
use crate::{InputError, State, StepFailure};

/// How a [`Prk`] imposes the constraint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Constraint {
    /// Stage multipliers, conditions weighted by a's rows, the end velocity projected.
    Stage,
    /// One multiplier, the constraint at the step's end.
    End,
    /// One multiplier, the constraint at the midpoint of the step's chord.
    Midpoint,
}

impl Constraint {
    /// Every way, as the API names them.
    pub const ALL: [Constraint; 3] = [Constraint::Stage, Constraint::End, Constraint::Midpoint];

    /// Its name in the API.
    pub fn id(self) -> &'static str {
        match self {
            Constraint::Stage => "stage",
            Constraint::End => "end",
            Constraint::Midpoint => "midpoint",
        }
    }
}

/// A partitioned Runge–Kutta method given as its tableau.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prk {
    /// The tableau.
    pub tableau: Tableau,
    /// The stored tableau's id, if it is one.
    pub stored: Option<&'static str>,
    /// How the constraint is imposed.
    pub constraint: Constraint,
    /// The tableau's classical order ([`order::classical_order`]).
    pub classical_order: u32,
    /// Newton's settings.
    pub newton: NewtonConfig,
}

/// The stored tableau a `prk` without one takes.
pub const DEFAULT_TABLEAU: &str = "gauss2";

impl Default for Prk {
    fn default() -> Self {
        let t = stored_tableau(DEFAULT_TABLEAU).expect("the default tableau is stored");
        Self {
            tableau: t.tableau,
            stored: Some(t.id),
            constraint: Constraint::Stage,
            classical_order: t.order,
            newton: NewtonConfig::default(),
        }
    }
}

static INFO: MethodInfo = MethodInfo {
    id: "prk",
    name: "Partitioned Runge–Kutta given as its tableau",
    params: &[],
    order: 4,
    reference: "Hairer, Lubich & Wanner, GNI II.2 and VII.1; L. Jay, BIT 43 (2003)",
    implicit: true,
    composed_order_limit: None,
    class_only: None,
    instrument: false,
    symmetric_at: None,
    external: false,
    by_tableau: true,
};

impl Prk {
    /// The method of `tableau` with `constraint` (both as a request gives them; `None`: the
    /// defaults, [`DEFAULT_TABLEAU`] and `stage`), checked.
    pub fn new(tableau: Option<&TableauChoice>, constraint: Option<&str>) -> Result<Self, InputError> {
        let (tableau, stored, classical_order) = match tableau {
            None => {
                let d = Prk::default();
                (d.tableau, d.stored, d.classical_order)
            }
            Some(TableauChoice::Stored(id)) => {
                let t = stored_tableau(id).ok_or_else(|| InputError::Tableau {
                    field: "tableau".into(),
                    message: format!(
                        "unknown tableau '{id}'; stored tableaux: {}",
                        stored::stored().iter().map(|t| t.id).collect::<Vec<_>>().join(", ")
                    ),
                })?;
                (t.tableau, Some(t.id), t.order)
            }
            Some(TableauChoice::Given(spec)) => {
                let t = Tableau::checked(spec)?;
                (t, None, order::classical_order(&t))
            }
        };
        let constraint = match constraint {
            None => Constraint::Stage,
            Some(name) => Constraint::ALL.into_iter().find(|c| c.id() == name).ok_or_else(|| {
                InputError::Tableau {
                    field: "constraint".into(),
                    message: format!("unknown constraint '{name}'; valid: stage, end, midpoint"),
                }
            })?,
        };
        let refused = |message: String| InputError::Tableau { field: "constraint".into(), message };
        match constraint {
            Constraint::Stage => {
                let (rows, columns) = (tableau.constrained_stages().count(), tableau.forced_stages().count());
                if rows != columns {
                    return Err(refused(format!(
                        "constraint 'stage' needs as many multipliers (nonzero columns of \
                         a_hat: {columns}) as weighted conditions (nonzero rows of a: {rows}); \
                         this tableau can take 'end' or 'midpoint'"
                    )));
                }
                if !tableau.stage_conditions_fix_multipliers() {
                    return Err(refused(
                        "constraint 'stage' cannot fix this tableau's multipliers: the product \
                         a·a_hat, on the rows of a that carry conditions and the columns of \
                         a_hat that carry multipliers, is singular; try 'end' or 'midpoint'"
                            .into(),
                    ));
                }
            }
            Constraint::Midpoint if !tableau.midpoint_condition_fixes_its_multiplier() => {
                return Err(refused(
                    "constraint 'midpoint' cannot fix this tableau's multiplier: Σ_j b_j Σ_l \
                     a_hat_jl is 0; try 'end'"
                        .into(),
                ));
            }
            Constraint::Midpoint | Constraint::End => {}
        }
        Ok(Self { tableau, stored, constraint, classical_order, newton: NewtonConfig::default() })
    }

    /// Why the step is not symmetric, if it is not.
    pub fn asymmetry(&self) -> Option<&'static str> {
        if !self.tableau.symmetric() {
            return Some("its tableau is not symmetric");
        }
        match self.constraint {
            // One multiplier for the whole step: the step back from the end meets the
            // condition at the start, which a state on the constraint satisfies.
            Constraint::Midpoint | Constraint::End => None,
            Constraint::Stage if self.tableau.ends_on_a_stage() => None,
            Constraint::Stage => Some("the end projection of constraint 'stage' is not a stage's own"),
        }
    }
}

impl Integrator for Prk {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(_: &[f64]) -> Result<Self, InputError> {
        Ok(Self::default())
    }
    fn from_parts(
        _: &[f64],
        tableau: Option<&TableauChoice>,
        constraint: Option<&str>,
    ) -> Result<Self, InputError> {
        Self::new(tableau, constraint)
    }
    fn order(&self) -> u32 {
        match self.constraint {
            Constraint::Stage => self.classical_order,
            // One multiplier for the whole step: measured order 2 at most (docs/high-order.md).
            Constraint::End | Constraint::Midpoint => self.classical_order.min(2),
        }
    }
    fn label(&self) -> String {
        let tableau = match self.stored {
            Some(id) => id.to_owned(),
            None => format!("{}-stage p{}", self.tableau.stages, self.classical_order),
        };
        match self.constraint {
            Constraint::Stage => format!("PRK[{tableau}]"),
            c => format!("PRK[{tableau}, {}]", c.id()),
        }
    }
    fn symmetric(&self) -> bool {
        self.asymmetry().is_none()
    }
}

impl Stepper for Prk {
    type Memory<const N: usize, const R: usize> = GeneralMemory<N, R>;
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        self.step_general(&General(sys), st, mem, h)
    }
}
