//! Typed errors: [`InputError`] for a scene or method a user got wrong (each names the
//! offending field, so the API can point at it), [`StepFailure`] for one step that could
//! not be taken, and [`RunError`] for a run that ended early, naming the step and time.

use std::fmt;

use thiserror::Error;

/// A number as an error message echoes it: Rust's `{}` writes `1e300` with 300 digits and
/// `1e-300` with 300 zeros, so magnitudes outside `[1e-4, 1e15)` are written as `1e300`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Short(pub f64);

impl fmt::Display for Short {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if x != 0.0 && x.is_finite() && !(1e-4..1e15).contains(&x.abs()) {
            write!(f, "{x:e}")
        } else {
            write!(f, "{x}")
        }
    }
}

/// Something wrong with what a user asked for. [`InputError::field`] names the field.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum InputError {
    /// No system has this id.
    #[error("unknown system '{id}'; valid systems: {valid}")]
    UnknownSystem {
        /// What was asked for.
        id: String,
        /// The valid ids, comma-separated.
        valid: String,
    },
    /// The system has no parameter of this name.
    #[error("unknown parameter '{name}' for {owner}; valid parameters: {valid}")]
    UnknownParam {
        /// Field path of the parameter, e.g. `params.eps`.
        field: String,
        /// What was asked for.
        name: String,
        /// The system or method it was asked of.
        owner: String,
        /// The valid names, comma-separated (or "none").
        valid: String,
    },
    /// A parameter lies outside its range.
    #[error("{name} = {} is out of range; allowed: {range}", Short(*.value))]
    ParamOutOfRange {
        /// Field path, e.g. `params.epsilon` or `alpha`.
        field: String,
        /// The parameter's name.
        name: String,
        /// The value given.
        value: f64,
        /// The allowed range, written as an interval.
        range: String,
    },
    /// No preset of the system has this id.
    #[error("unknown preset '{id}' for {system}; valid presets: {valid}")]
    UnknownPreset {
        /// What was asked for.
        id: String,
        /// The system.
        system: String,
        /// The valid ids, comma-separated.
        valid: String,
    },
    /// q or v has the wrong number of components.
    #[error("{field} must have {expected} components (the system's dof), got {got}")]
    WrongLength {
        /// `q` or `v`.
        field: String,
        /// The system's dimension.
        expected: usize,
        /// What was given.
        got: usize,
    },
    /// A number is NaN or infinite.
    #[error("{field} must be a finite number, got {value}")]
    NonFinite {
        /// Field path, e.g. `q[2]`.
        field: String,
        /// The value given.
        value: f64,
    },
    /// A component of the initial state is so large that the run would count as diverged
    /// from its first step.
    #[error(
        "{field} = {value:e} is too large: the initial q and v must be at most {limit:e} in \
         magnitude (a run whose state exceeds 1e100 has diverged)"
    )]
    TooLarge {
        /// Field path, e.g. `q[0]`.
        field: String,
        /// The value given.
        value: f64,
        /// The largest magnitude allowed.
        limit: f64,
    },
    /// The initial velocity violates the constraints.
    #[error(
        "inconsistent initial velocity: |A(q) v| = {residual:.3e} exceeds 1e-9; v must satisfy the \
         constraints A(q) v = 0 (the nearest v that does, in the metric of M: [{}])",
        nearest.iter().map(|x| format!("{}", Short(*x))).collect::<Vec<_>>().join(", ")
    )]
    InconsistentVelocity {
        /// The residual |A(q) v|.
        residual: f64,
        /// The admissible velocity nearest to v in the metric of M:
        /// `v − M⁻¹Aᵀ(A M⁻¹Aᵀ)⁻¹ A v`.
        nearest: Vec<f64>,
    },
    /// A method that has no step for the system asked for.
    #[error("{message}")]
    NotApplicable {
        /// Field path, e.g. `methods[1]` at the API, `id` in core.
        field: String,
        /// Why, in words.
        message: String,
    },
    /// The step is zero or negative.
    #[error("step must be positive, got {}", Short(*.step))]
    NonPositiveStep {
        /// The step given.
        step: f64,
    },
    /// t_end is shorter than one step.
    #[error("t_end = {} must be at least one step ({})", Short(*.t_end), Short(*.step))]
    TEndTooShort {
        /// The t_end given.
        t_end: f64,
        /// The step given.
        step: f64,
    },
    /// No method has this id.
    #[error("unknown method '{id}'; valid methods: {valid}")]
    UnknownMethod {
        /// Field path, e.g. `methods[1].id` at the API, `id` in core.
        field: String,
        /// What was asked for.
        id: String,
        /// The valid ids, comma-separated.
        valid: String,
    },
    /// No integral has this name.
    #[error("unknown integral '{name}'; valid integrals: {valid}")]
    UnknownIntegral {
        /// What was asked for.
        name: String,
        /// The valid names, comma-separated.
        valid: String,
    },
    /// The system does not have this integral.
    #[error("{system} has no integral '{integral}'; it has: {available}")]
    IntegralUnavailable {
        /// The integral asked for.
        integral: String,
        /// The system.
        system: String,
        /// What the system has, comma-separated.
        available: String,
    },
    /// The latitude is undefined for this initial state.
    #[error("the latitude is undefined here: {reason}")]
    LatitudeUndefined {
        /// Why.
        reason: String,
    },
    /// A formula of a system given as formulas does not parse or names what it may not.
    #[error("{error}")]
    Formula {
        /// Field path, e.g. `system.constraints[0][1]`.
        field: String,
        /// What is wrong, and where in the formula.
        error: crate::formula::FormulaError,
    },
    /// A composition that is unknown or asked of a method that is not symmetric.
    #[error("{message}")]
    Composition {
        /// Field path, e.g. `methods[1].composition`.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A `prk` method's tableau or constraint that no step can be built from, or given to
    /// another method.
    #[error("{message}")]
    Tableau {
        /// Field path, e.g. `methods[0].tableau.b`.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A system given as formulas is malformed or leaves the class of `docs/model.md` §1
    /// (sizes, names, a constraint matrix without full rank at the start).
    #[error("{message}")]
    CustomSystem {
        /// Field path, e.g. `system.passenger[1]`.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

impl InputError {
    /// The path of the offending field in a `/simulate` request, e.g. `params.epsilon`.
    pub fn field(&self) -> String {
        match self {
            Self::UnknownSystem { .. } => "system".into(),
            Self::UnknownParam { field, .. }
            | Self::ParamOutOfRange { field, .. }
            | Self::WrongLength { field, .. }
            | Self::NonFinite { field, .. }
            | Self::TooLarge { field, .. }
            | Self::UnknownMethod { field, .. }
            | Self::Formula { field, .. }
            | Self::Composition { field, .. }
            | Self::Tableau { field, .. }
            | Self::NotApplicable { field, .. }
            | Self::CustomSystem { field, .. } => field.clone(),
            Self::UnknownPreset { .. } => "preset".into(),
            Self::InconsistentVelocity { .. } => "v".into(),
            Self::NonPositiveStep { .. } => "step".into(),
            Self::TEndTooShort { .. } => "t_end".into(),
            Self::UnknownIntegral { .. } | Self::IntegralUnavailable { .. } => "integrals".into(),
            Self::LatitudeUndefined { .. } => "integrals".into(),
        }
    }

    /// The same error with its field path put under `prefix` (e.g. `methods[1]`).
    pub fn within(mut self, prefix: &str) -> Self {
        match &mut self {
            Self::UnknownParam { field, .. }
            | Self::ParamOutOfRange { field, .. }
            | Self::NonFinite { field, .. }
            | Self::Composition { field, .. }
            | Self::Tableau { field, .. }
            | Self::UnknownMethod { field, .. } => *field = format!("{prefix}.{field}"),
            Self::NotApplicable { field, .. } => *field = prefix.to_string(),
            _ => {}
        }
        self
    }
}

/// Why one step could not be taken.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
pub enum StepFailure {
    /// Newton's method did not reach its tolerance within its iteration budget.
    #[error("Newton did not converge in {iterations} iterations (last increment {increment:.3e})")]
    NewtonDiverged {
        /// Iterations taken.
        iterations: u32,
        /// Size of the last increment.
        increment: f64,
    },
    /// A linear system in the step was singular.
    #[error("singular linear system in the step")]
    Singular,
    /// The step produced NaN or infinity.
    #[error("the solution became non-finite (the run diverged)")]
    NonFinite,
    /// The state grew beyond any meaningful size.
    #[error("the solution exceeded {limit:e} in magnitude (the run diverged; try a smaller step)")]
    Diverged {
        /// The bound on |q|, |q̇| and |λ| that was crossed.
        limit: f64,
    },
    /// The constraint matrix lost rank: its rows are no longer independent, and the
    /// multiplier is no longer determined.
    #[error(
        "the constraint matrix A(q) lost rank at or within this step (its smallest singular \
         value is {smallest:.3e} here, {initial:.3e} at the start): its rows are no longer \
         independent"
    )]
    RankLost {
        /// The smallest singular value of A(q) at the state reached.
        smallest: f64,
        /// The smallest singular value of A(q₀).
        initial: f64,
    },
    /// The method has no step for this system's class (the planner refuses such a run
    /// before it starts; this is the step's own guard).
    #[error("the method does not apply to this system")]
    NotApplicable,
    /// The adaptive solve inside a step of the `reference` method failed (why, in words).
    #[error("the adaptive solve (Dop853) inside the step failed: {0}")]
    AdaptiveSolve(&'static str),
    /// The step of a method written outside nhlab (in Python) raised an error or returned
    /// what is not a state: its words.
    #[error("the method's step failed: {0}")]
    External(&'static str),
    /// The caller asked a measurement of steps to stop (its client went away).
    #[error("stopped: the measurement was cancelled")]
    Stopped,
}

/// Why a run ended before t_end.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RunError {
    /// A step failed.
    #[error("step {step} (t = {t:.6}) failed: {failure}")]
    Step {
        /// Index of the step that failed (1-based: step 1 goes from t = 0 to t = h).
        step: u64,
        /// Time at the start of that step.
        t: f64,
        /// What went wrong.
        failure: StepFailure,
    },
    /// The observer asked to stop.
    #[error("cancelled at step {step} (t = {t:.6})")]
    Cancelled {
        /// Steps completed.
        step: u64,
        /// Time reached.
        t: f64,
    },
    /// The run took longer than its time limit ([`RunConfig::time_limit`](crate::RunConfig)).
    #[error(
        "time limit: the run took longer than {} s of wall-clock time and was stopped at step \
         {step} (t = {t:.6}); shorten t_end or lengthen the step",
        Short(*limit)
    )]
    TimeLimit {
        /// Steps completed.
        step: u64,
        /// Time reached.
        t: f64,
        /// The limit, in seconds.
        limit: f64,
    },
}

#[cfg(test)]
mod tests {
    use super::Short;

    #[test]
    fn short_numbers_stay_plain_and_extreme_ones_take_an_exponent() {
        let cases = [
            (0.1, "0.1"),
            (-7.0, "-7"),
            (0.0, "0"),
            (1e14, "100000000000000"),
            (1e15, "1e15"),
            (1e-4, "0.0001"),
            (-1e-300, "-1e-300"),
            (1e308, "1e308"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
        ];
        for (x, written) in cases {
            assert_eq!(Short(x).to_string(), written);
        }
    }
}
