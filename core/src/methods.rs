//! The integrators of MATH.md §3, one file each. Register a new one in [`crate::registry`].

mod dd;
mod dla;
mod dla01;
mod leapfrog;

pub use dd::Dd;
pub use dla::Dla;
pub use dla01::Dla01;
pub use leapfrog::Leapfrog;
