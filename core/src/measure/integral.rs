//! [`Integral`]: the quantities whose error series nhlab reports.

use std::fmt;

/// A first integral (or the constraint diagnostic), named as in the paper and the API.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Integral {
    /// Total energy `H`.
    Energy,
    /// Passenger energy `E`.
    PassengerEnergy,
    /// Driver energy `h`.
    DriverEnergy,
    /// The latitude `ℓ` of `docs/model.md` §5, sampled at the section crossings.
    Latitude,
    /// Constraint residual `|A(q) q̇|` (a diagnostic, reported as is).
    Constraint,
}

impl Integral {
    /// Every integral, in the API's order.
    pub const ALL: [Integral; 5] =
        [Self::Energy, Self::PassengerEnergy, Self::DriverEnergy, Self::Latitude, Self::Constraint];

    /// The API name.
    pub const fn id(self) -> &'static str {
        match self {
            Self::Energy => "energy",
            Self::PassengerEnergy => "passenger_energy",
            Self::DriverEnergy => "driver_energy",
            Self::Latitude => "latitude",
            Self::Constraint => "constraint",
        }
    }

    /// Parses an API name.
    pub fn from_id(id: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|i| i.id() == id)
    }

    /// Every valid API name, comma-separated (for error messages).
    pub fn valid_ids() -> String {
        Self::ALL.map(Self::id).join(", ")
    }
}

impl fmt::Display for Integral {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}
