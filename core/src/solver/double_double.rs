//! Double-double numbers: a value held as the unevaluated sum `hi + lo` of two doubles
//! (about 106 bits), and the error-free transformations they are built from.
//!
//! The state already holds q and q̇ this way: compensated summation keeps what each addition
//! rounded away (`State::q_compensation`, `v_compensation`), so `q + q_compensation` is the
//! configuration to ~10⁻³². Where a step must be exact beyond double precision (the end of
//! DD's step on quadratic potentials, `methods::dd::closed_form`; whole turns taken off an angle,
//! `whole_turns`) it computes in these. Only sums and products by doubles are needed, so
//! only those are here: Knuth's two-sum, the two-product ([`Products`]: one fused
//! multiply–add where the CPU has it, Dekker's splitting otherwise), and sloppy sums
//! accurate to ~10⁻³² of the operands, which is what a residual needs.

use std::marker::PhantomData;
use std::ops::{Add, Mul, Neg};

/// How the exact product of two doubles is computed.
pub(crate) trait Products: Copy {
    /// `a · b` rounded, and what the rounding lost, exactly.
    fn two_prod(a: f64, b: f64) -> (f64, f64);
}

/// One fused multiply–add. Only where the CPU has FMA and the code calling it is compiled
/// for it (`#[target_feature]`): elsewhere `mul_add` is a library call that spills every
/// live register.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fused;

/// Dekker's product: both factors split in halves of 26 bits, whose products are exact.
/// Exact for factors below 2⁹⁹⁶ in magnitude (larger ones overflow the split to a
/// non-finite result, which ends a run as non-finite; no state of a run comes near).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dekker;

impl Products for Fused {
    #[inline]
    fn two_prod(a: f64, b: f64) -> (f64, f64) {
        let p = a * b;
        (p, a.mul_add(b, -p))
    }
}

impl Products for Dekker {
    #[inline]
    fn two_prod(a: f64, b: f64) -> (f64, f64) {
        let p = a * b;
        let (a_hi, a_lo) = split(a);
        let (b_hi, b_lo) = split(b);
        (p, ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo)
    }
}

/// Veltkamp's split of `a` into two halves of 26 bits that sum to it exactly.
#[inline]
fn split(a: f64) -> (f64, f64) {
    let c = 134_217_729.0 * a; // 2²⁷ + 1
    let hi = c - (c - a);
    (hi, a - hi)
}

/// Knuth's two-sum: `a + b` rounded, and what the rounding lost, exactly.
#[inline]
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a + b` rounded and its rounding error, for `|a| ≥ |b|` (or a zero): three operations.
#[inline]
fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// `hi + lo`, unevaluated, with `|lo|` at most about an ulp of `hi`; products through `P`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DoubleDouble<P: Products> {
    /// The leading double.
    pub(crate) hi: f64,
    /// What `hi` leaves out.
    pub(crate) lo: f64,
    products: PhantomData<P>,
}

impl<P: Products> DoubleDouble<P> {
    /// The number `hi + lo` (need not be normalized).
    #[inline]
    pub(crate) fn new(hi: f64, lo: f64) -> Self {
        Self { hi, lo, products: PhantomData }
    }

    /// The exact product of two doubles.
    #[inline]
    pub(crate) fn product(a: f64, b: f64) -> Self {
        let (hi, lo) = P::two_prod(a, b);
        Self::new(hi, lo)
    }

    /// `self · c` for a power of two `c`: exact, without the product's transformation.
    #[inline]
    pub(crate) fn scaled(self, c: f64) -> Self {
        debug_assert!(c.abs().log2().fract() == 0.0, "{c} is not a power of two");
        Self::new(self.hi * c, self.lo * c)
    }

    #[inline]
    fn normalized(hi: f64, lo: f64) -> Self {
        let (hi, lo) = fast_two_sum(hi, lo);
        Self::new(hi, lo)
    }
}

impl<P: Products> From<f64> for DoubleDouble<P> {
    #[inline]
    fn from(x: f64) -> Self {
        Self::new(x, 0.0)
    }
}

impl<P: Products> Add for DoubleDouble<P> {
    type Output = Self;
    #[inline]
    fn add(self, b: Self) -> Self {
        let (s, e) = two_sum(self.hi, b.hi);
        Self::normalized(s, e + (self.lo + b.lo))
    }
}

impl<P: Products> Add<f64> for DoubleDouble<P> {
    type Output = Self;
    #[inline]
    fn add(self, b: f64) -> Self {
        let (s, e) = two_sum(self.hi, b);
        Self::normalized(s, e + self.lo)
    }
}

impl<P: Products> Neg for DoubleDouble<P> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self::new(-self.hi, -self.lo)
    }
}

impl<P: Products> Mul<f64> for DoubleDouble<P> {
    type Output = Self;
    #[inline]
    fn mul(self, b: f64) -> Self {
        let (p, e) = P::two_prod(self.hi, b);
        Self::normalized(p, e + self.lo * b)
    }
}

/// A sum of doubles and double-double products, kept as its rounded value and the running
/// total of what the roundings lost (Ogita, Rump & Oishi's Sum2 and Dot2): as accurate as
/// double-double arithmetic, without renormalizing after every term.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sum2<P: Products> {
    sum: f64,
    err: f64,
    products: PhantomData<P>,
}

impl<P: Products> Sum2<P> {
    /// The sum of `x` alone.
    #[inline]
    pub(crate) fn new(x: f64) -> Self {
        Self { sum: x, err: 0.0, products: PhantomData }
    }

    /// Adds `x`.
    #[inline]
    pub(crate) fn add(&mut self, x: f64) {
        let (s, e) = two_sum(self.sum, x);
        self.sum = s;
        self.err += e;
    }

    /// Adds `x`.
    #[inline]
    pub(crate) fn add_dd(&mut self, x: DoubleDouble<P>) {
        self.add(x.hi);
        self.err += x.lo;
    }

    /// Adds `a · b` (to ~10⁻³² of it: the low parts' product is left out).
    #[inline]
    pub(crate) fn add_product(&mut self, a: DoubleDouble<P>, b: DoubleDouble<P>) {
        let (p, e) = P::two_prod(a.hi, b.hi);
        self.add(p);
        self.err += e + (a.hi * b.lo + a.lo * b.hi);
    }

    /// The sum, as a double-double (not normalized).
    #[inline]
    pub(crate) fn to_dd(self) -> DoubleDouble<P> {
        DoubleDouble::new(self.sum, self.err)
    }

    /// The sum, rounded.
    #[inline]
    pub(crate) fn to_f64(self) -> f64 {
        self.sum + self.err
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type D = DoubleDouble<Dekker>;

    fn value<P: Products>(x: DoubleDouble<P>) -> f64 {
        x.hi + x.lo
    }

    #[test]
    fn error_free_transformations_are_exact() {
        // 1 + 2⁻⁶⁰ is not a double; two_sum keeps the 2⁻⁶⁰.
        let tiny = 2f64.powi(-60);
        assert_eq!(two_sum(1.0, tiny), (1.0, tiny));
        assert_eq!(two_sum(tiny, 1.0), (1.0, tiny));
        // (1 + 2⁻³⁰)² = 1 + 2⁻²⁹ + 2⁻⁶⁰, by either product.
        let a = 1.0 + 2f64.powi(-30);
        assert_eq!(Dekker::two_prod(a, a), (1.0 + 2f64.powi(-29), tiny));
        assert_eq!(Fused::two_prod(a, a), (1.0 + 2f64.powi(-29), tiny));
        // Both agree on products whose error has all 53 bits.
        for (x, y) in [(0.1, 3.0), (std::f64::consts::PI, -std::f64::consts::E), (1e150, 7e-3)] {
            assert_eq!(Dekker::two_prod(x, y), Fused::two_prod(x, y), "{x} · {y}");
        }
    }

    #[test]
    fn sums_and_products_keep_about_106_bits() {
        // 0.1 · 3 − 0.3 for the doubles 0.1 and 0.3 (which are not tenths), exactly: from
        // their mantissas as integers. It is 2⁻⁵⁵; double arithmetic gives 2⁻⁵⁴.
        let exact = {
            // 0.1 = m₁·2⁻⁵⁶, 0.3 = m₃·2⁻⁵⁴ (both normal, 53-bit mantissas).
            let m1 = (0.1f64 * 2f64.powi(56)) as i128;
            let m3 = (0.3f64 * 2f64.powi(54)) as i128;
            (3 * m1 - 4 * m3) as f64 * 2f64.powi(-56)
        };
        assert_eq!(value(D::from(0.1) * 3.0 + -0.3), exact);
        assert_ne!(0.1 * 3.0 - 0.3, exact, "double arithmetic alone loses it");
        let mut sum = Sum2::<Dekker>::new(-0.3);
        sum.add_product(D::from(0.1), D::from(3.0));
        assert_eq!(sum.to_f64(), exact);
        // A sum whose double parts cancel leaves the low parts, exactly.
        let x = D::new(1.0, 2f64.powi(-70));
        let y = D::new(-1.0, 2f64.powi(-71));
        assert_eq!(value(x + y), 3.0 * 2f64.powi(-71));
        assert_eq!(value(x + -x), 0.0);
        assert_eq!(value(x.scaled(-2.0) + 2.0), -2f64.powi(-69));
    }
}
