//! [`Custom`]: a compiled system given as formulas, as a [`System`] of fixed sizes.
//!
//! Where U is quadratic it is evaluated as `u₀ + b·x + ½ xᵀH x` with fixed-size vectors, as
//! a built-in's; otherwise through its compiled formulas. The driver's terms come from one
//! evaluation per ζ ([`driver_cache`](super::driver_cache)); where ζ is an angle, from
//! `sin ζ` and `cos ζ` as the methods carry them, as for the built-in angle systems.

use super::compile::{Compiled, Passenger};
use super::driver_cache::{MAX_OUTPUTS, with_driver_terms};
use super::invariants::Invariants;
use crate::model::system::{DriverTerms, System};
use crate::{Matrix, Vector};
use std::mem::MaybeUninit;
use std::sync::Arc;

/// A system given as formulas with `N − 1` passengers and `R` constraints.
#[derive(Debug, Clone)]
pub struct Custom<const N: usize, const R: usize> {
    compiled: Arc<Compiled>,
    /// `(u₀, b, H)` where U is quadratic (driver row and column zero).
    quadratic: Option<(f64, Vector<N>, Matrix<N, N>)>,
    /// The invariants of its spec, on its `(q, q̇)` ([`with_invariants`](Self::with_invariants)).
    invariants: Option<Arc<Invariants>>,
}

impl<const N: usize, const R: usize> Custom<N, R> {
    /// The system of `compiled`, which must have `N − 1` passengers and `R` constraints.
    pub fn new(compiled: Arc<Compiled>) -> Self {
        debug_assert!(compiled.n + 1 == N && compiled.r == R);
        let quadratic = match &compiled.passenger {
            Passenger::Quadratic { u0, b, h } => {
                let n = N - 1;
                let mut bv = Vector::<N>::zeros();
                let mut hm = Matrix::<N, N>::zeros();
                for i in 0..n {
                    bv[i] = b[i];
                    for j in 0..n {
                        hm[(i, j)] = h[i * n + j];
                    }
                }
                Some((*u0, bv, hm))
            }
            Passenger::General { .. } => None,
        };
        Self { compiled, quadratic, invariants: None }
    }

    /// The same system carrying `invariants`, compiled on its `(q, q̇)` (those of the spec it
    /// was compiled from: `Formulated::invariants`).
    pub fn with_invariants(self, invariants: Option<Arc<Invariants>>) -> Self {
        Self { invariants, ..self }
    }

    fn x(q: &Vector<N>) -> &[f64] {
        &q.as_slice()[..N - 1]
    }

    /// U through its compiled formulas (where it is not quadratic). This and the two below are
    /// out of line so that the quadratic case inlines into the steps.
    #[inline(never)]
    fn general_potential(&self, q: &Vector<N>) -> f64 {
        let mut out = [f64::NAN];
        if let Passenger::General(g) = &self.compiled.passenger {
            g.u.eval(Self::x(q), &mut out);
        }
        out[0]
    }
    /// ∇U through its compiled formulas.
    #[inline(never)]
    fn general_gradient(&self, q: &Vector<N>) -> Vector<N> {
        let mut g = Vector::<N>::zeros();
        match &self.compiled.passenger {
            Passenger::General(p) => p.gradient.eval(Self::x(q), &mut g.as_mut_slice()[..N - 1]),
            Passenger::Quadratic { .. } => g.fill(f64::NAN),
        }
        g
    }
    /// ∇²U through its compiled formulas.
    #[inline(never)]
    fn general_hessian(&self, q: &Vector<N>) -> Matrix<N, N> {
        let Passenger::General(g) = &self.compiled.passenger else {
            return Matrix::<N, N>::repeat(f64::NAN);
        };
        // The upper triangle of at most 6 × 6.
        let mut upper = [0.0; 21];
        g.hessian.eval(Self::x(q), &mut upper[..(N - 1) * N / 2]);
        let mut h = Matrix::<N, N>::zeros();
        let mut k = 0;
        for i in 0..N - 1 {
            for j in i..N - 1 {
                (h[(i, j)], h[(j, i)]) = (upper[k], upper[k]);
                k += 1;
            }
        }
        h
    }

    /// The driver's terms from the outputs of its code, each read by `read`.
    #[inline]
    fn terms_from(values: &[f64], read: impl Fn(&f64) -> f64) -> DriverTerms<N, R> {
        let values = &values[..3 + 2 * R * (N - 1)];
        let (n, r) = (N - 1, R);
        let mut constraint = Matrix::<R, N>::zeros();
        let mut constraint_d = Matrix::<R, N>::zeros();
        for i in 0..r {
            for j in 0..n {
                constraint[(i, j)] = read(&values[3 + i * n + j]);
                constraint_d[(i, j)] = read(&values[3 + r * n + i * n + j]);
            }
        }
        DriverTerms {
            constraint,
            constraint_d,
            potential: read(&values[0]),
            potential_d1: read(&values[1]),
            potential_d2: read(&values[2]),
        }
    }

    /// [`terms_from`](Self::terms_from) the remembered outputs.
    fn terms_of(values: &[f64]) -> DriverTerms<N, R> {
        Self::terms_from(values, |v| *v)
    }
}

impl<const N: usize, const R: usize> System<N, R> for Custom<N, R> {
    fn quadratic_passenger(&self) -> bool {
        self.compiled.quadratic_passenger
    }
    fn quadratic_driver(&self) -> bool {
        self.compiled.quadratic_driver
    }
    fn free_passenger(&self) -> bool {
        self.compiled.free_passenger
    }
    fn driver_is_periodic(&self) -> bool {
        self.compiled.periodic
    }
    fn zeta_is_angle(&self) -> bool {
        self.compiled.angle
    }
    fn invariants(&self) -> Option<&Invariants> {
        self.invariants.as_deref()
    }

    #[inline]
    fn passenger_potential(&self, q: &Vector<N>) -> f64 {
        match &self.quadratic {
            Some((u0, b, h)) => u0 + b.dot(q) + 0.5 * q.dot(&(h * q)),
            None => self.general_potential(q),
        }
    }
    #[inline]
    fn passenger_gradient(&self, q: &Vector<N>) -> Vector<N> {
        match &self.quadratic {
            Some((_, b, h)) => b + h * q,
            None => self.general_gradient(q),
        }
    }
    #[inline]
    fn passenger_hessian(&self, q: &Vector<N>) -> Matrix<N, N> {
        match &self.quadratic {
            Some((_, _, h)) => *h,
            None => self.general_hessian(q),
        }
    }
    fn driver_potential(&self, zeta: f64) -> f64 {
        with_driver_terms(&self.compiled, zeta, |v| v[0])
    }
    fn driver_potential_d1(&self, zeta: f64) -> f64 {
        with_driver_terms(&self.compiled, zeta, |v| v[1])
    }
    fn driver_potential_d2(&self, zeta: f64) -> f64 {
        with_driver_terms(&self.compiled, zeta, |v| v[2])
    }
    fn constraint(&self, zeta: f64) -> Matrix<R, N> {
        with_driver_terms(&self.compiled, zeta, Self::terms_of).constraint
    }
    fn constraint_d(&self, zeta: f64) -> Matrix<R, N> {
        with_driver_terms(&self.compiled, zeta, Self::terms_of).constraint_d
    }
    fn driver_terms(&self, zeta: f64) -> DriverTerms<N, R> {
        with_driver_terms(&self.compiled, zeta, Self::terms_of)
    }
    #[inline]
    fn driver_terms_trig(&self, zeta: f64, sin: f64, cos: f64) -> DriverTerms<N, R> {
        if self.compiled.angle {
            // A Newton iteration's inputs are new each time: evaluated here, not kept.
            let mut values = [MaybeUninit::uninit(); MAX_OUTPUTS];
            let values = self.compiled.driver.eval_uninit(&[zeta, sin, cos], &mut values);
            // One load per output: the code has just stored them one by one, and a wider load
            // across two of those stores waits for them to reach the cache (on the Newton
            // chain, where it made DD's step slower; a remembered output is read long after).
            // SAFETY: a reference to an `f64`.
            Self::terms_from(values, |v| unsafe { std::ptr::read_volatile(v) })
        } else {
            self.driver_terms(zeta)
        }
    }
    /// `(−a₂, a₁)/|a|` for one constraint on two passengers (the latitude's only use, signed as
    /// the CVTs'); zero for other sizes, where nhlab does not offer the latitude.
    fn kernel(&self, zeta: f64) -> Vector<N> {
        let mut k = Vector::<N>::zeros();
        if N == 3 && R == 1 {
            let a = self.constraint(zeta);
            let norm = (a[(0, 0)] * a[(0, 0)] + a[(0, 1)] * a[(0, 1)]).sqrt();
            k[0] = -a[(0, 1)] / norm;
            k[1] = a[(0, 0)] / norm;
        }
        k
    }
}
