//! Systems given as formulas (`docs/model.md` §7): a user's own member of the class of §1,
//! described by its passenger potential U(x), driver potential V_d(ζ) and the passenger
//! columns of A(ζ) ([`FormulaSpec`]), compiled once per request ([`Compiled`]: checked,
//! differentiated exactly, made into tapes) and run as a [`Custom`] system like any other.

mod compile;
mod driver_cache;
mod spec;
mod system;

pub use compile::{Compiled, Passenger};
pub use spec::{CustomLimits, FormulaSpec, MAX_PASSENGERS};
pub use system::Custom;
