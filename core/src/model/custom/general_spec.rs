//! [`GeneralSpec`]: a system of the general class (`docs/model.md` §1) as a user writes it:
//! coordinates, parameters, the mass matrix, the potential, the constraint rows and the
//! invariants it conserves, each a formula.

/// Most coordinates of a system given in the general form.
pub const MAX_COORDINATES: usize = 12;

/// One entry of the mass matrix: a number, or a formula in the parameters.
#[derive(Debug, Clone, PartialEq)]
pub enum MassEntry {
    /// A number.
    Number(f64),
    /// A formula in the parameters.
    Formula(String),
}

/// The mass matrix M as given.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum MassSpec {
    /// Not given: M = I.
    #[default]
    Identity,
    /// `diag(m₁ … m_N)`.
    Diagonal(Vec<MassEntry>),
    /// The full N×N matrix, row by row (symmetric).
    Full(Vec<Vec<MassEntry>>),
}

/// A system of the general class given as formulas; see the module's doc.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralSpec {
    /// A label for listings and plots.
    pub name: String,
    /// The coordinates' names, q₁ … q_N (their velocities are `name_dot`).
    pub coordinates: Vec<String>,
    /// Parameters with their default values, in order.
    pub parameters: Vec<(String, f64)>,
    /// M (constant: numbers or formulas in the parameters).
    pub mass: MassSpec,
    /// `V(q)`: coordinates and parameters.
    pub potential: String,
    /// The rows of `A(q)`, N entries each: coordinates and parameters.
    pub constraints: Vec<Vec<String>>,
    /// Named invariants: formulas in the coordinates, their velocities and the parameters
    /// that the system conserves, each measured like the energy.
    pub invariants: Vec<(String, String)>,
    /// Whether nhlab looks for the paper's class in it (`docs/model.md` §10); `false` runs
    /// even a class system on the general steps.
    pub detect_class: bool,
}

impl Default for GeneralSpec {
    fn default() -> Self {
        Self {
            name: "custom".into(),
            coordinates: Vec::new(),
            parameters: Vec::new(),
            mass: MassSpec::Identity,
            potential: "0".into(),
            constraints: Vec::new(),
            invariants: Vec::new(),
            detect_class: true,
        }
    }
}

impl GeneralSpec {
    /// A spec with unit masses and no invariant: what a built-in writes, its parameters
    /// named `names` at `values`.
    pub fn of(
        name: &str,
        coordinates: &[&str],
        (names, values): (&[&str], &[f64]),
        potential: &str,
        constraints: &[&[&str]],
    ) -> Self {
        let strings = |s: &[&str]| s.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        Self {
            name: name.into(),
            coordinates: strings(coordinates),
            parameters: strings(names).into_iter().zip(values.iter().copied()).collect(),
            mass: MassSpec::Identity,
            potential: potential.into(),
            constraints: constraints.iter().map(|row| strings(row)).collect(),
            invariants: Vec::new(),
            detect_class: true,
        }
    }

    /// With a diagonal mass of these formulas.
    pub fn with_diagonal_mass(mut self, diagonal: &[&str]) -> Self {
        self.mass = MassSpec::Diagonal(
            diagonal.iter().map(|s| MassEntry::Formula(s.to_string())).collect(),
        );
        self
    }

    /// With an invariant.
    pub fn with_invariant(mut self, name: &str, formula: &str) -> Self {
        self.invariants.push((name.into(), formula.into()));
        self
    }
}
