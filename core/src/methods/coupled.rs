//! Where the coupled fast paths of DLA^α and DLA^{0,1} run: the driver solved alone, then
//! the passenger in one linear solve.

use crate::model::system::System;

/// Whether DLA^α's and DLA^{0,1}'s coupled fast paths run on a system. A fast path is kept
/// only where it is at least 2× faster than the general Newton solve (`docs/performance.md`).
/// Where V is quadratic and ζ is not an angle (`cvt`, `particle`) the driver's update is
/// affine, the passenger's one linear solve, and neither needs a sine. Where ζ is an angle,
/// the sines and cosines that both paths evaluate hold the fast paths under 2×, so those
/// systems take the general solve.
pub fn coupled_fast_path<S: System<N, R>, const N: usize, const R: usize>(sys: &S) -> bool {
    sys.quadratic_passenger() && sys.quadratic_driver() && !sys.zeta_is_angle()
}
