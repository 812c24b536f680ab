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

/// nalgebra's closed-form inverse of the concrete `M×M` type, for a generic `N×N` that is
/// known to have `N == M`.
#[inline]
fn closed_form<const N: usize, const M: usize>(a: &Matrix<N, N>) -> Option<Matrix<N, N>> {
    let inv = nalgebra::SMatrix::<f64, M, M>::from_fn(|i, j| a[(i, j)]).try_inverse()?;
    Some(Matrix::<N, N>::from_fn(|i, j| inv[(i, j)]))
}

/// `A⁻¹`: nalgebra's closed forms for N ≤ 4 (the matrices here are `I + O(h²)` and
/// `h A Aᵀ`-like, well conditioned, and closed forms are several times cheaper than the loops
/// of a pivoted LU), the LU above otherwise. `None` when `A` is singular.
#[inline]
pub(crate) fn inverse<const N: usize>(a: &Matrix<N, N>) -> Option<Matrix<N, N>> {
    // N is a constant, so all but one arm compile away (and the conversions with them).
    let m = match N {
        1 => Some(Matrix::<N, N>::from_element(1.0 / a[(0, 0)])),
        2 => closed_form::<N, 2>(a),
        3 => closed_form::<N, 3>(a),
        4 => closed_form::<N, 4>(a),
        _ => Lu::new(*a).map(|lu| lu.solve(&Matrix::<N, N>::identity())),
    }?;
    m.iter().all(|v| v.is_finite()).then_some(m)
}

/// `(adj A, det A)` of a 3×3 matrix (`None` for other sizes), so that `A⁻¹ = adj A / det A`
/// can be applied without waiting on the reciprocal: the saddle solve of Newton's iteration
/// (`newton::saddle_increment`) multiplies by adj A while det A's reciprocal is computed, and
/// its Schur equation needs no reciprocal of det A at all.
#[inline]
pub(crate) fn adjugate3<const N: usize>(a: &Matrix<N, N>) -> Option<(Matrix<N, N>, f64)> {
    if N != 3 {
        return None;
    }
    // adj A (i, j) is the cofactor (j, i): the 2×2 determinant of the rows and columns left
    // when row j and column i are taken out, signed.
    let minor = |(r0, r1): (usize, usize), (c0, c1): (usize, usize)| {
        a[(r0, c0)] * a[(r1, c1)] - a[(r0, c1)] * a[(r1, c0)]
    };
    let others = [(1, 2), (0, 2), (0, 1)];
    let adj = Matrix::<N, N>::from_fn(|i, j| {
        let m = minor(others[j], others[i]);
        if (i + j) % 2 == 0 { m } else { -m }
    });
    let det = a[(0, 0)] * adj[(0, 0)] + a[(0, 1)] * adj[(1, 0)] + a[(0, 2)] * adj[(2, 0)];
    Some((adj, det))
}

/// `A⁻¹`, with a shortcut for `A` diagonal but for its last column, whose inverse has the
/// same shape: N divisions, where a 4×4 closed form costs hundreds of flops. Newton's matrix
/// `I + h ∂(∇̄V − A(q̄)ᵀλ)/∂q̇₁` has that shape wherever the discrete gradient's Jacobian is
/// diagonal (as on every test system, unless DD's Gonzalez correction is not round-off),
/// since q̇₁ moves A(q̄) through ζ̄ alone; so does DLA's `I + c∇²V` (with a zero last column).
/// At 3×3 the shortcut costs more instructions than the closed form but is a shorter chain
/// (independent divisions instead of determinant, reciprocal, products), which is what a
/// Newton iteration waits on: DD's step on the knife edge is markedly faster for it.
#[inline(always)] // else left out of line on the 4×4 paths, a call per solve
pub(crate) fn inverse_maybe_bordered<const N: usize>(a: &Matrix<N, N>) -> Option<Matrix<N, N>> {
    let bordered = (0..N - 1).all(|j| (0..N).all(|i| i == j || a[(i, j)] == 0.0));
    if !bordered {
        return inverse(a);
    }
    let d = a.diagonal().map(|x| 1.0 / x);
    let mut inv = Matrix::<N, N>::from_diagonal(&d);
    for i in 0..N - 1 {
        inv[(i, N - 1)] = -a[(i, N - 1)] * d[i] * d[N - 1];
    }
    inv.iter().all(|v| v.is_finite()).then_some(inv)
}

/// Solves `A X = B` (see [`inverse`]).
#[inline]
pub(crate) fn solve<const N: usize, const K: usize>(
    a: &Matrix<N, N>,
    b: &Matrix<N, K>,
) -> Option<Matrix<N, K>> {
    inverse(a).map(|inv| inv * b)
}

/// `det a` by LU with partial pivoting (0 where a pivot is 0).
#[inline]
pub(crate) fn determinant<const N: usize>(a: &Matrix<N, N>) -> f64 {
    let mut m = *a;
    let mut det = 1.0;
    for k in 0..N {
        let p = (k..N).max_by(|&i, &j| m[(i, k)].abs().total_cmp(&m[(j, k)].abs())).unwrap_or(k);
        if m[(p, k)] == 0.0 {
            return 0.0;
        }
        if p != k {
            m.swap_rows(p, k);
            det = -det;
        }
        det *= m[(k, k)];
        for i in k + 1..N {
            let f = m[(i, k)] / m[(k, k)];
            for j in k..N {
                m[(i, j)] -= f * m[(k, j)];
            }
        }
    }
    det
}

/// The smallest pivot `dᵢ` of the Cholesky factor of a symmetric positive semi-definite `g`
/// (`g = L Lᵀ`, `dᵢ = Lᵢᵢ`): 0 where g is singular (or not positive definite), and never above
/// `√λ_max`; with `g = A Aᵀ` it falls to 0 with A's smallest singular value, a bound cheap enough
/// to look at every step.
#[inline]
pub(crate) fn smallest_cholesky_pivot<const R: usize>(g: &Matrix<R, R>) -> f64 {
    let mut l = Matrix::<R, R>::zeros();
    let mut smallest = f64::INFINITY;
    for j in 0..R {
        let mut d = g[(j, j)];
        for k in 0..j {
            d -= l[(j, k)] * l[(j, k)];
        }
        // Not positive, or NaN: singular, or not positive definite.
        if d.is_nan() || d <= 0.0 {
            return 0.0;
        }
        let d = d.sqrt();
        smallest = smallest.min(d);
        l[(j, j)] = d;
        for i in j + 1..R {
            let mut x = g[(i, j)];
            for k in 0..j {
                x -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = x / d;
        }
    }
    smallest
}

/// Calls `$body` with `$d` a constant for the sizes up to 8 (the SPARK Schur complements of
/// small systems): the loops of [`lu_rows`] and [`substitute`], inlined at a known size, lose
/// their bounds checks and unroll. One algorithm, specialized by the compiler, not a second
/// one by hand; larger sizes take it as written.
macro_rules! by_size {
    ($d:expr, |$n:ident| $body:expr) => {
        match $d {
            1 => {
                let $n = 1;
                $body
            }
            2 => {
                let $n = 2;
                $body
            }
            3 => {
                let $n = 3;
                $body
            }
            4 => {
                let $n = 4;
                $body
            }
            5 => {
                let $n = 5;
                $body
            }
            6 => {
                let $n = 6;
                $body
            }
            7 => {
                let $n = 7;
                $body
            }
            8 => {
                let $n = 8;
                $body
            }
            $n => $body,
        }
    };
}

/// LU with partial pivoting, in place, of the d×d matrix stored row by row in `a[..d·d]`, for
/// systems whose size const generics cannot state (a SPARK step's s·N + (s − 1)·R unknowns).
/// The rows are swapped where they lie; `swaps[k]` is the row swapped with row k. `None` when
/// a pivot is zero or not finite (singular matrix).
pub(crate) fn lu_in_place(a: &mut [f64], d: usize, swaps: &mut [usize]) -> Option<()> {
    by_size!(d, |d| lu_rows(&mut a[..d * d], d, &mut swaps[..d]))
}

/// [`lu_in_place`]'s elimination on `a` of exactly d·d entries.
#[inline(always)]
fn lu_rows(a: &mut [f64], d: usize, swaps: &mut [usize]) -> Option<()> {
    for k in 0..d {
        let (mut piv, mut largest) = (k, a[k * d + k].abs());
        for i in k + 1..d {
            let x = a[i * d + k].abs();
            if x > largest {
                (piv, largest) = (i, x);
            }
        }
        // Also false for NaN: a pivot that is zero or not finite leaves the matrix singular.
        if !(largest > 0.0 && largest.is_finite()) {
            return None;
        }
        swaps[k] = piv;
        if piv != k {
            let (upper, lower) = a.split_at_mut(piv * d);
            upper[k * d..(k + 1) * d].swap_with_slice(&mut lower[..d]);
        }
        // Row k, then the rows below it, each reduced by a multiple of row k's tail.
        let (done, below) = a.split_at_mut((k + 1) * d);
        let pivot_row = &done[k * d + k..(k + 1) * d];
        let pivot = pivot_row[0];
        for row in below.chunks_exact_mut(d) {
            let l = row[k] / pivot;
            row[k] = l;
            if l != 0.0 {
                for (x, &p) in row[k + 1..].iter_mut().zip(&pivot_row[1..]) {
                    *x -= l * p;
                }
            }
        }
    }
    Some(())
}

/// Solves `A x = b` in place (`b` becomes x) with the factors of [`lu_in_place`].
pub(crate) fn lu_solve_in_place(a: &[f64], d: usize, swaps: &[usize], b: &mut [f64]) {
    by_size!(d, |d| substitute(&a[..d * d], d, &swaps[..d], &mut b[..d]))
}

/// [`lu_solve_in_place`]'s two substitutions, on exactly d·d, d and d entries.
#[inline(always)]
fn substitute(a: &[f64], d: usize, swaps: &[usize], b: &mut [f64]) {
    for (k, &swap) in swaps[..d].iter().enumerate() {
        b.swap(k, swap);
    }
    for i in 1..d {
        let row = &a[i * d..i * d + i];
        let mut sum = 0.0;
        for (x, y) in row.iter().zip(&b[..i]) {
            sum += x * y;
        }
        b[i] -= sum;
    }
    for i in (0..d).rev() {
        let row = &a[i * d + i..(i + 1) * d];
        let mut sum = 0.0;
        for (x, y) in row[1..].iter().zip(&b[i + 1..d]) {
            sum += x * y;
        }
        b[i] = (b[i] - sum) / row[0];
    }
}

/// A dense Newton system of any size d, kept per thread by the steps that
/// need one: the Jacobian (row by row), its row swaps, the residual.
#[derive(Default)]
pub(crate) struct Scratch {
    jacobian: Vec<f64>,
    swaps: Vec<usize>,
    residual: Vec<f64>,
}

impl Scratch {
    /// The first `d·d`, `d` and `d` entries, grown to them if need be.
    pub(crate) fn sized(&mut self, d: usize) -> (&mut [f64], &mut [usize], &mut [f64]) {
        if self.residual.len() < d {
            self.jacobian.resize(d * d, 0.0);
            self.swaps.resize(d, 0);
            self.residual.resize(d, 0.0);
        }
        (&mut self.jacobian[..d * d], &mut self.swaps[..d], &mut self.residual[..d])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_adjugate_over_the_determinant_is_the_inverse() {
        let a = Matrix::<3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
        let (adj, det) = adjugate3(&a).expect("3×3");
        assert_eq!(det, -5.0);
        assert!((adj * a - Matrix::<3, 3>::identity() * det).amax() < 1e-14, "{adj}");
        assert!(adjugate3(&Matrix::<2, 2>::identity()).is_none());
    }

    #[test]
    fn the_in_place_lu_solves_as_the_fixed_size_one() {
        let a = Matrix::<4, 4>::from_fn(|i, j| if i == j { 0.1 } else { 1.0 + (i * j) as f64 });
        let b = Matrix::<4, 1>::new(1.0, -2.0, 0.5, 3.0);
        let mut flat: Vec<f64> = (0..16).map(|k| a[(k / 4, k % 4)]).collect();
        let (mut swaps, mut x) = ([0; 4], b.as_slice().to_vec());
        lu_in_place(&mut flat, 4, &mut swaps).expect("regular");
        lu_solve_in_place(&flat, 4, &swaps, &mut x);
        let fixed = Lu::new(a).expect("regular").solve(&b);
        assert!(x.iter().zip(fixed.iter()).all(|(u, v)| (u - v).abs() < 1e-13), "{x:?}");
        assert!(lu_in_place(&mut [1.0, 2.0, 2.0, 4.0], 2, &mut [0; 2]).is_none(), "singular");
    }

    /// The sizes `by_size` takes as constants give the factors and solutions of the loops at a
    /// size known only when they run, bit for bit; every size solves its system.
    #[test]
    fn the_lu_at_a_constant_size_is_the_lu_as_written() {
        for d in 1..=10 {
            // Off-diagonal entries larger than the diagonal: every column pivots.
            let a: Vec<f64> = (0..d * d)
                .map(
                    |k| if k / d == k % d { 0.1 } else { 1.0 + ((k / d) * (k % d) + k % 3) as f64 },
                )
                .collect();
            let b: Vec<f64> = (0..d).map(|i| 1.0 - 0.3 * i as f64).collect();
            let (mut fast, mut fast_swaps, mut x) = (a.clone(), vec![0; d], b.clone());
            lu_in_place(&mut fast, d, &mut fast_swaps).expect("regular");
            lu_solve_in_place(&fast, d, &fast_swaps, &mut x);
            let (mut written, mut swaps, mut y) = (a.clone(), vec![0; d], b.clone());
            let at_run_time = std::hint::black_box(d);
            lu_rows(&mut written, at_run_time, &mut swaps).expect("regular");
            substitute(&written, at_run_time, &swaps, &mut y);
            assert_eq!((&fast, &fast_swaps, &x), (&written, &swaps, &y), "d = {d}");
            for i in 0..d {
                let ax: f64 = (0..d).map(|j| a[i * d + j] * x[j]).sum();
                assert!((ax - b[i]).abs() < 1e-10, "d = {d}, row {i}: {ax} against {}", b[i]);
            }
        }
    }

    #[test]
    fn solves_a_pivoting_system() {
        let a = Matrix::<3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
        let x = Matrix::<3, 1>::new(1.0, -2.0, 0.5);
        let b = a * x;
        let got = Lu::new(a).expect("regular").solve(&b);
        assert!((got - x).amax() < 1e-14, "{got}");
    }

    #[test]
    fn closed_forms_agree_with_lu() {
        let a3 = Matrix::<3, 3>::new(1.1, 0.2, -0.3, 0.05, 0.9, 0.1, -0.2, 0.3, 1.3);
        let b3 = Matrix::<3, 2>::new(1.0, 2.0, -1.0, 0.5, 0.25, 3.0);
        let lu = Lu::new(a3).unwrap().solve(&b3);
        assert!((solve(&a3, &b3).unwrap() - lu).amax() < 1e-14);
        let a2 = Matrix::<2, 2>::new(2.0, 1.0, 0.5, 3.0);
        let b2 = Matrix::<2, 1>::new(1.0, -1.0);
        assert!((a2 * solve(&a2, &b2).unwrap() - b2).amax() < 1e-15);
        let a4 =
            Matrix::<4, 4>::from_fn(|i, j| if i == j { 2.0 } else { 0.1 * (i + 2 * j) as f64 });
        let b4 = Matrix::<4, 1>::new(1.0, -2.0, 0.5, 3.0);
        assert!((solve(&a4, &b4).unwrap() - Lu::new(a4).unwrap().solve(&b4)).amax() < 1e-14);
        let a5 = Matrix::<5, 5>::identity() * 2.0;
        assert_eq!(solve(&a5, &Matrix::<5, 1>::repeat(1.0)).unwrap(), Matrix::<5, 1>::repeat(0.5));
        assert!(solve(&Matrix::<1, 1>::zeros(), &Matrix::<1, 1>::repeat(1.0)).is_none());
    }

    #[test]
    fn bordered_inverse_is_the_inverse() {
        let mut a = Matrix::<4, 4>::from_diagonal(&Matrix::<4, 1>::new(1.5, 0.5, 2.0, 4.0));
        a.set_column(3, &Matrix::<4, 1>::new(0.3, -0.7, 0.2, 4.0));
        let inv = inverse_maybe_bordered(&a).unwrap();
        assert!((inv * a - Matrix::<4, 4>::identity()).amax() < 1e-15, "{inv}");
        assert!((inv - inverse(&a).unwrap()).amax() < 1e-15);
        // Not bordered: the closed form.
        a[(1, 0)] = 0.25;
        let inv = inverse_maybe_bordered(&a).unwrap();
        assert!((inv * a - Matrix::<4, 4>::identity()).amax() < 1e-15, "{inv}");
        a[(3, 3)] = 0.0;
        a[(1, 0)] = 0.0;
        assert!(inverse_maybe_bordered(&a).is_none());
    }

    #[test]
    fn singular_is_none() {
        let a = Matrix::<2, 2>::new(1.0, 2.0, 2.0, 4.0);
        assert!(Lu::new(a).is_none());
    }
}
