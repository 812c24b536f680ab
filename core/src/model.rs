//! The model: mechanical systems with linear velocity constraints, the general class of
//! `docs/model.md` §1 ([`mechanical::Mechanical`]), and within it the paper's class of
//! nonholonomically coupled systems ([`system::System`]); the built-in systems ([`systems`]),
//! systems given as formulas ([`custom`]), and the state a one-step method moves
//! ([`state::State`]: q, q̇, λ and their compensated sums).

pub mod custom;
pub mod integral;
pub mod mechanical;
pub mod params;
pub mod state;
pub mod system;
pub mod systems;
