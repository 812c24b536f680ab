//! [`Integral`]: the quantities whose error series nhlab reports.

use std::fmt;

/// Most invariants a system may declare (`docs/model.md` §4).
pub const MAX_INVARIANTS: usize = 8;

/// A first integral (or the constraint diagnostic), named as in the paper and the API.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Integral {
    /// Total energy `H`.
    Energy,
    /// Passenger energy `E` (the paper's class only).
    PassengerEnergy,
    /// Driver energy `h` (the paper's class only).
    DriverEnergy,
    /// The latitude `ℓ` of `docs/model.md` §5, sampled at the section crossings.
    Latitude,
    /// Constraint residual `|A(q) q̇|` (a diagnostic, reported as is).
    Constraint,
    /// The system's invariant of this index: a formula in q and q̇ that the system declares
    /// conserved (its name is the system's, `PreparedScene::integral_name`).
    Invariant(u8),
}

impl Integral {
    /// Every integral with a fixed name, in the API's order.
    pub const ALL: [Integral; 5] =
        [Self::Energy, Self::PassengerEnergy, Self::DriverEnergy, Self::Latitude, Self::Constraint];

    /// How many integrals a run can have: the fixed ones and the invariants.
    pub const COUNT: usize = Self::ALL.len() + MAX_INVARIANTS;

    /// A dense index below [`Integral::COUNT`], for tables of every integral.
    pub const fn index(self) -> usize {
        match self {
            Self::Energy => 0,
            Self::PassengerEnergy => 1,
            Self::DriverEnergy => 2,
            Self::Latitude => 3,
            Self::Constraint => 4,
            Self::Invariant(k) => 5 + k as usize,
        }
    }

    /// The integral of a dense index ([`Integral::index`]).
    pub fn of_index(index: usize) -> Option<Self> {
        match index {
            0..5 => Some(Self::ALL[index]),
            i if i < Self::COUNT => Some(Self::Invariant((i - 5) as u8)),
            _ => None,
        }
    }

    /// The API name of a fixed integral; `invariant` for an invariant, whose own name is its
    /// system's.
    pub const fn id(self) -> &'static str {
        match self {
            Self::Energy => "energy",
            Self::PassengerEnergy => "passenger_energy",
            Self::DriverEnergy => "driver_energy",
            Self::Latitude => "latitude",
            Self::Constraint => "constraint",
            Self::Invariant(_) => "invariant",
        }
    }

    /// Parses an API name of a fixed integral.
    pub fn from_id(id: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|i| i.id() == id)
    }

    /// Every valid API name of a fixed integral, comma-separated (for error messages).
    pub fn valid_ids() -> String {
        Self::ALL.map(Self::id).join(", ")
    }
}

impl fmt::Display for Integral {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Invariant(k) => write!(f, "invariant {k}"),
            _ => f.write_str(self.id()),
        }
    }
}
