//! The model: the class of nonholonomically coupled systems of `docs/model.md` §1
//! ([`system::System`]), the test systems of §2 ([`systems`]), and the state a one-step
//! method moves ([`state::State`]: q, q̇, λ and their compensated sums).

pub mod custom;
pub mod state;
pub mod system;
pub mod systems;
mod whole_turns;
