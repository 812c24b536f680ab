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

use crate::system::System;

/// Whether DLA^α's and DLA^{0,1}'s coupled fast paths run on a system. Issue 4 keeps a fast
/// path only where it is at least 2× faster than the general Newton solve. Where V is
/// quadratic and ζ is not an angle (`cvt`, `particle`) the driver's update is affine, the
/// passenger's one linear solve, and neither needs a sine: 2.05–2.56× the general paths in
/// criterion, 2.2–2.4× in a steady loop, 3.5–3.7× in instructions (2026-11-25,
/// `docs/benchmarks.md`; `particle`'s DLA^α is the closest). Where ζ is an angle, the sines and
/// cosines that both paths evaluate held the fast paths to 1.56–2.00× (knife edge,
/// `cvt_pendulum`, both disks; 2026-11-25, `docs/benchmarks.md`), so those systems take the
/// general solve.
pub const fn coupled_fast_path<S: System<N, R>, const N: usize, const R: usize>() -> bool {
    S::QUADRATIC_PASSENGER && S::QUADRATIC_DRIVER && !S::ZETA_IS_ANGLE
}
