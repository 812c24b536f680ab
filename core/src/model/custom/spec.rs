//! [`FormulaSpec`]: a system as a user writes it, and [`CustomLimits`], the bounds on it.

use crate::formula::Limits;

/// Most passenger coordinates a system given as formulas may have.
pub const MAX_PASSENGERS: usize = 6;

/// A system given as formulas: names, parameters with their default values, and the three
/// kinds of formulas (`docs/model.md` §7).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FormulaSpec {
    /// A label for listings and plots.
    pub name: String,
    /// The passenger coordinates' names, x₁ … xₙ.
    pub passenger: Vec<String>,
    /// The driver's name, ζ.
    pub driver: String,
    /// Parameters with their default values, in order.
    pub parameters: Vec<(String, f64)>,
    /// `U(x)`: passenger coordinates and parameters only.
    pub passenger_potential: String,
    /// `V_d(ζ)`: the driver and parameters only.
    pub driver_potential: String,
    /// The passenger columns of `A(ζ)`, row by row: the driver and parameters only.
    pub constraints: Vec<Vec<String>>,
}

/// Bounds on a system given as formulas.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CustomLimits {
    /// Bounds on each formula.
    pub formula: Limits,
    /// Most parameters.
    pub max_parameters: usize,
    /// Whether formulas are compiled to machine code where the JIT is built in (cargo
    /// feature `jit`) and works on the host (else only their tapes are interpreted: the
    /// general path, for tests).
    pub native: bool,
}

impl Default for CustomLimits {
    fn default() -> Self {
        Self { formula: Limits::default(), max_parameters: 16, native: true }
    }
}
