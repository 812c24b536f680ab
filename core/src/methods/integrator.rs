//! The [`Integrator`] trait: one step `(q₀, q̇₀, λ₀) ↦ (q₁, q̇₁, λ₁)` of a method of
//! `docs/model.md` §3, with the method's own [`Memory`] beside the state.

use super::general_memory::GeneralMemory;
use super::memory::Memory;
use super::prk::tableau::TableauChoice;
use crate::model::mechanical::Mechanical;
use crate::model::system::{ParamSpec, System};
use crate::{InputError, State, StepFailure};

/// What a method is, for listings (the method's own parameters live in the config struct).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodInfo {
    /// Id, as in the API.
    pub id: &'static str,
    /// Human name.
    pub name: &'static str,
    /// Parameters, in the order `from_params` takes them.
    pub params: &'static [ParamSpec],
    /// Order with default parameters.
    pub order: u32,
    /// Where the method comes from.
    pub reference: &'static str,
    /// Whether the step solves a nonlinear system (Newton).
    pub implicit: bool,
    /// The order its symmetric compositions reach where it is below the scheme's (measured,
    /// `docs/high-order.md`): LF carries λ and the DD family's q̇ leaves the constraint
    /// manifold between steps, so their compositions stop at 4 (DD's q̇ itself at 2).
    pub composed_order_limit: Option<u32>,
    /// Why the method has no step for the general class (`docs/model.md` §3), if it has none:
    /// it then runs only on systems of the paper's class.
    pub class_only: Option<&'static str>,
    /// Whether it is a measuring instrument rather than a method under study (the
    /// reference solve): asked for by its id only, never among the defaults,
    /// [`Method::all`](crate::Method::all) or the cross-product tests.
    pub instrument: bool,
    /// Where the step is symmetric only at one value of a parameter (DLA^α at α = ½): that
    /// value, and the order elsewhere; `None` where symmetry does not depend on the parameters.
    /// What a client offers compositions by, for the method as configured.
    pub symmetric_at: Option<SymmetricAt>,
    /// Whether its step is code outside nhlab registered in the process (a method written
    /// in Python, [`External`](super::External)): only the nhlab Python package has any, a
    /// server none; never among the defaults or the cross-product tests, and not offered
    /// by the page.
    pub external: bool,
    /// Whether it is a family whose members are given by their tableaux
    /// ([`Prk`](super::Prk)): asked for with a tableau, and not among
    /// [`Method::all`](crate::Method::all), the scorecard's and benchmarks' methods (SPARK is
    /// its fast member on the Lobatto pairs); the cross-product tests take it with its
    /// default tableau.
    pub by_tableau: bool,
}

/// The one parameter value at which a method's step is symmetric ([`MethodInfo::symmetric_at`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SymmetricAt {
    /// The parameter.
    pub param: &'static str,
    /// Its value there.
    pub value: f64,
    /// The method's order at any other value.
    pub order_elsewhere: u32,
}

/// What a run steps: a method of the list ([`Integrator`]) or one composed of its steps
/// ([`Composed`](super::composition::Composed)). The step is pure in `self`, so one value can
/// serve many runs at once; what it carries from step to step besides the state is its
/// [`Stepper::Memory`], owned by the run.
pub trait Stepper: Copy + Send + Sync + 'static {
    /// What the method remembers from one step to the next (see [`Memory`]).
    type Memory<const N: usize, const R: usize>: Memory<N, R>;
    /// Advances `state` by one step `h`, reading and updating the method's `memory`.
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        state: &mut State<N, R>,
        memory: &mut Self::Memory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure>;
}

/// A method's step on the general class (`docs/model.md` §1: any M, V(q), A(q)), with its
/// [`GeneralMemory`]. A system of the paper's class runs the method's class step
/// ([`Stepper`]); this one runs on every other, and on a class system seen through
/// [`General`](crate::model::mechanical::General) (its general path).
pub trait GeneralStepper: Copy + Send + Sync + 'static {
    /// Advances `state` by one step `h`.
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        state: &mut State<N, R>,
        memory: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure>;
}

/// A one-step nonholonomic integrator of the list: a small config struct with its
/// description, on top of its [`Stepper`] step.
pub trait Integrator: Stepper + GeneralStepper {
    /// Its description.
    fn info() -> &'static MethodInfo;
    /// Builds it from parameter values in the order of `info().params`, already range-checked.
    fn from_params(params: &[f64]) -> Result<Self, InputError>;
    /// Builds it from parameter values and what a request gives beside them, a tableau and a
    /// constraint, which only [`Prk`](super::Prk) takes: the others refuse them.
    fn from_parts(
        params: &[f64],
        tableau: Option<&TableauChoice>,
        constraint: Option<&str>,
    ) -> Result<Self, InputError> {
        let field = match (tableau, constraint) {
            (None, None) => return Self::from_params(params),
            (Some(_), _) => "tableau",
            (None, Some(_)) => "constraint",
        };
        Err(InputError::Tableau {
            field: field.into(),
            message: format!(
                "method {} takes no {field}: only prk is given a tableau and a constraint",
                Self::info().id
            ),
        })
    }
    /// Its parameter values, in the order of `info().params`.
    fn params(&self) -> Vec<f64> {
        Vec::new()
    }
    /// Order of convergence with these parameters.
    fn order(&self) -> u32 {
        Self::info().order
    }
    /// Short label, e.g. `DLA^0.4`.
    fn label(&self) -> String;
    /// The same method on its general path, for a method that has faster ones (fast paths
    /// are tested against it and benchmarked beside it); `None` for the others.
    fn general_path(&self) -> Option<Self> {
        None
    }
    /// Whether the step is symmetric, `Φ_{−h} ∘ Φ_h = id` (reversible in the sense of
    /// `docs/model.md` §11): only then does a symmetric [`Composition`] raise its order.
    ///
    /// [`Composition`]: super::composition::Composition
    fn symmetric(&self) -> bool {
        false
    }
}
