//! Systems given as formulas (`docs/model.md` §10), in two forms. The general form
//! ([`GeneralSpec`]: coordinates, M, V(q), A(q), invariants) is compiled into a
//! [`Formulated`] system: the paper's class where nhlab finds it ([`detect`]), run as a
//! [`Custom`] system with the driver last, or the general class ([`GeneralCompiled`], run as a
//! [`GeneralCustom`]). The paper's own form ([`FormulaSpec`]: passenger potential U(x), driver
//! potential V_d(ζ), the passenger columns of A(ζ)) is compiled into the class directly
//! ([`Compiled`]). Either is checked, differentiated exactly and made into tapes once per
//! request.

mod compile;
mod detect;
mod driver_cache;
mod general;
mod general_spec;
mod general_system;
mod invariants;
mod spec;
mod system;

pub(crate) use compile::parameter_values;
pub use compile::{Compiled, Parameters, Passenger};
pub use general::{Formulated, GeneralCompiled, Structure};
pub use general_spec::{GeneralSpec, MAX_COORDINATES, MassEntry, MassSpec};
pub use general_system::GeneralCustom;
pub use invariants::Invariants;
pub use spec::{CustomLimits, FormulaSpec, MAX_PASSENGERS};
pub use system::Custom;
