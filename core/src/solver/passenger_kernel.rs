//! The passenger's kernel direction `k̃(ζ)` of a coupled system, from the entries of A.
//!
//! On a coupled system `A = [A_x(ζ) | 0]`; where the passenger's kernel is one line
//! (`N = R + 2`), the midpoint constraint of DD and DD-AVF says that `q̇₀ + q̇₁` is
//! `w k̃(ζ̄)` plus a driver component, which turns their passenger solves into one unknown
//! (`methods::dd::reduced`, `methods::dd::closed_form`). `k̃` is not normalized, so no square root
//! enters: it is `(−a₂, a₁)` for one constraint, the cross product of the two rows for two (every
//! test system is one of these).

use crate::{Matrix, Vector};

/// Whether [`kernel_and_derivative`] covers systems of these dimensions: a one-dimensional
/// passenger kernel (`N = R + 2`) with one or two constraints.
pub(crate) const fn covers<const N: usize, const R: usize>() -> bool {
    N == R + 2 && (R == 1 || R == 2)
}

/// `(k̃, dk̃/dζ)`: a vector spanning the kernel of `A_x`, with zero driver component, from the
/// entries of `A = [A_x | 0]` and of `dA/dζ` (where it [`covers`] the system).
#[inline]
pub(crate) fn kernel_and_derivative<const N: usize, const R: usize>(
    a: &Matrix<R, N>,
    da: &Matrix<R, N>,
) -> (Vector<N>, Vector<N>) {
    let (mut k, mut dk) = (Vector::<N>::zeros(), Vector::<N>::zeros());
    if R == 1 {
        (k[0], k[1]) = (-a[(0, 1)], a[(0, 0)]);
        (dk[0], dk[1]) = (-da[(0, 1)], da[(0, 0)]);
    } else if R == 2 {
        let cross = |u: [f64; 3], v: [f64; 3]| {
            [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        };
        let row = |m: &Matrix<R, N>, r: usize| [m[(r, 0)], m[(r, 1)], m[(r, 2)]];
        let c = cross(row(a, 0), row(a, 1));
        let (d1, d2) = (cross(row(da, 0), row(a, 1)), cross(row(a, 0), row(da, 1)));
        for i in 0..3 {
            (k[i], dk[i]) = (c[i], d1[i] + d2[i]);
        }
    }
    (k, dk)
}

/// `k̃` alone, from A's entries (see [`kernel_and_derivative`]).
#[inline]
pub(crate) fn kernel<const N: usize, const R: usize>(a: &Matrix<R, N>) -> Vector<N> {
    kernel_and_derivative(a, &Matrix::<R, N>::zeros()).0
}
