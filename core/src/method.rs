//! The [`Integrator`] trait: one step `(q₀, q̇₀, λ₀) ↦ (q₁, q̇₁, λ₁)` of a method of MATH.md §3.

use crate::system::{ParamSpec, System};
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
}

/// A one-step nonholonomic integrator. A method is a small config struct; the step is pure
/// in `self`, so one method value can serve many runs at once.
pub trait Integrator: Copy + Send + Sync + 'static {
    /// Its description.
    fn info() -> &'static MethodInfo;
    /// Builds it from parameter values in the order of `info().params`, already range-checked.
    fn from_params(params: &[f64]) -> Result<Self, InputError>;
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
    /// Advances `state` by one step `h`.
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        state: &mut State<N, R>,
        h: f64,
    ) -> Result<(), StepFailure>;
}
