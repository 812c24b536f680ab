//! Small dense LU with partial pivoting on fixed-size matrices.
//!
//! nalgebra's own `lu()` needs `DimMin` bounds that would leak into every generic
//! signature of the integrators; this one works for any `const N` and stays on the stack.

use crate::Matrix;

/// LU factors of an N×N matrix (row permutation kept as indices).
pub(crate) struct Lu<const N: usize> {
    lu: Matrix<N, N>,
    perm: [usize; N],
}

impl<const N: usize> Lu<N> {
    /// Factorizes `a`; `None` when a pivot is zero or not finite (singular matrix).
    #[inline]
    pub(crate) fn new(mut a: Matrix<N, N>) -> Option<Self> {
        let mut perm = [0; N];
        for (i, p) in perm.iter_mut().enumerate() {
            *p = i;
        }
        for k in 0..N {
            let mut piv = k;
            for i in k + 1..N {
                if a[(i, k)].abs() > a[(piv, k)].abs() {
                    piv = i;
                }
            }
            let pivot = a[(piv, k)];
            if pivot == 0.0 || !pivot.is_finite() {
                return None;
            }
            if piv != k {
                a.swap_rows(piv, k);
                perm.swap(piv, k);
            }
            for i in k + 1..N {
                let m = a[(i, k)] / a[(k, k)];
                a[(i, k)] = m;
                for j in k + 1..N {
                    a[(i, j)] -= m * a[(k, j)];
                }
            }
        }
        Some(Self { lu: a, perm })
    }

    /// Solves `A X = B` for every column of `b`.
    #[inline]
    pub(crate) fn solve<const K: usize>(&self, b: &Matrix<N, K>) -> Matrix<N, K> {
        let mut x = Matrix::<N, K>::zeros();
        for (i, &p) in self.perm.iter().enumerate() {
            x.set_row(i, &b.row(p));
        }
        for c in 0..K {
            for i in 0..N {
                let mut s = x[(i, c)];
                for j in 0..i {
                    s -= self.lu[(i, j)] * x[(j, c)];
                }
                x[(i, c)] = s;
            }
            for i in (0..N).rev() {
                let mut s = x[(i, c)];
                for j in i + 1..N {
                    s -= self.lu[(i, j)] * x[(j, c)];
                }
                x[(i, c)] = s / self.lu[(i, i)];
            }
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_pivoting_system() {
        let a = Matrix::<3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
        let x = Matrix::<3, 1>::new(1.0, -2.0, 0.5);
        let b = a * x;
        let got = Lu::new(a).expect("regular").solve(&b);
        assert!((got - x).amax() < 1e-14, "{got}");
    }

    #[test]
    fn singular_is_none() {
        let a = Matrix::<2, 2>::new(1.0, 2.0, 2.0, 4.0);
        assert!(Lu::new(a).is_none());
    }
}
