//! The integrators of MATH.md §3, one file each. Register a new one in [`crate::registry`].

mod dd;
mod dd_avf;
mod dd_reduced;
mod dla;
mod dla01;
mod exact_energy;
mod leapfrog;
mod rk4;

pub use dd::Dd;
pub use dd_avf::DdAvf;
pub use dla::Dla;
pub use dla01::Dla01;
pub use leapfrog::Leapfrog;
pub use rk4::Rk4;
