//! Symmetric compositions (`docs/model.md` §11): a symmetric method Φ_h of order 2 taken as
//! `Φ_{γ_s h} ∘ … ∘ Φ_{γ_1 h}` with coefficients that sum to 1 and read the same backwards is
//! a symmetric method of higher order (Hairer, Lubich & Wanner, *Geometric Numerical
//! Integration*, II.4 and V.3). Every sub-step is a step of the method, so the composition
//! keeps what each step keeps: reversibility, the fibration, and for DD and DD-AVF the energy.
//!
//! [`SCHEMES`] lists the schemes with their coefficients, one row each; a [`Composition`]
//! names one of them, and [`Composed`] is a method taken so. The method's memory is carried across the sub-steps (each is keyed by what it depends
//! on, so a sub-step reads only what holds at its start), and so is the multiplier λ.

use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::{GeneralStepper, Integrator, Stepper};
use crate::model::mechanical::Mechanical;
use crate::model::system::System;
use crate::{State, StepFailure};

/// Yoshida's triple jump: γ₁ = γ₃ = 1/(2 − 2^{1/3}), γ₂ = 1 − 2γ₁.
const P4S3: [f64; 3] = {
    // 2^{1/3} to the last digit (const fns cannot take cube roots).
    let cbrt2 = 1.259_921_049_894_873_2;
    let g = 1.0 / (2.0 - cbrt2);
    [g, 1.0 - 2.0 * g, g]
};

/// Suzuki's fractal: γ₁ = γ₂ = γ₄ = γ₅ = 1/(4 − 4^{1/3}), γ₃ = 1 − 4γ₁.
const P4S5: [f64; 5] = {
    let cbrt4 = 1.587_401_051_968_199_5;
    let g = 1.0 / (4.0 - cbrt4);
    [g, g, 1.0 - 4.0 * g, g, g]
};

/// Kahan & Li's s9odr6a, as printed in Hairer, Lubich & Wanner, V.3 (3.11); the middle
/// coefficient is 1 − 2(γ₁ + … + γ₄).
#[allow(clippy::excessive_precision, reason = "the digits as printed, to check by eye")]
const P6S9: [f64; 9] = symmetric([
    0.392_161_444_007_314_139_279_250_56,
    0.332_599_136_789_359_438_599_748_64,
    -0.706_246_172_557_639_359_809_964_82,
    0.082_213_596_293_550_800_231_490_45,
]);

/// Kahan & Li's s15odr8, as printed in Hairer, Lubich & Wanner, V.3 (3.12); the middle
/// coefficient is 1 − 2(γ₁ + … + γ₇).
#[allow(clippy::excessive_precision, reason = "the digits as printed, to check by eye")]
const P8S15: [f64; 15] = symmetric([
    0.741_670_364_350_612_953_448_227_80,
    -0.409_100_825_800_031_593_997_300_10,
    0.190_754_710_296_238_379_953_876_26,
    -0.573_862_471_116_082_266_656_387_73,
    0.299_064_181_303_655_923_844_463_54,
    0.334_624_918_245_298_183_784_957_98,
    0.315_293_092_396_766_596_632_056_66,
]);

/// The symmetric coefficients `γ₁ … γ_K, 1 − 2Σγ, γ_K … γ₁` (S = 2K + 1).
const fn symmetric<const K: usize, const S: usize>(half: [f64; K]) -> [f64; S] {
    assert!(S == 2 * K + 1);
    let mut out = [0.0; S];
    let (mut sum, mut i) = (0.0, 0);
    while i < K {
        out[i] = half[i];
        out[S - 1 - i] = half[i];
        sum += half[i];
        i += 1;
    }
    out[K] = 1.0 - 2.0 * sum;
    out
}

/// A symmetric composition scheme as data: what the API, `GET /systems`, the docs and the
/// tests read of it. Adding a scheme is its coefficients and one row of [`SCHEMES`].
#[derive(Debug)]
pub struct Scheme {
    /// Id, as in the API (`p4s3`: order 4, 3 stages).
    pub id: &'static str,
    /// Order of the composition of a symmetric method of order 2.
    pub order: u32,
    /// The sub-step coefficients γ₁ … γ_s, in the order the sub-steps are taken.
    pub coefficients: &'static [f64],
    /// Human name.
    pub name: &'static str,
    /// Where the coefficients come from.
    pub reference: &'static str,
}

/// Every scheme, by order: the one list of them.
pub const SCHEMES: [Scheme; 4] = [
    Scheme {
        id: "p4s3",
        order: 4,
        coefficients: &P4S3,
        name: "Yoshida's triple jump",
        reference: "Yoshida, Phys. Lett. A 150 (1990); Suzuki, Phys. Lett. A 146 (1990); HLW II.4",
    },
    Scheme {
        id: "p4s5",
        order: 4,
        coefficients: &P4S5,
        name: "Suzuki's fractal",
        reference: "Suzuki, Phys. Lett. A 146 (1990); McLachlan, SISC 16 (1995); HLW II.4",
    },
    Scheme {
        id: "p6s9",
        order: 6,
        coefficients: &P6S9,
        name: "Kahan & Li, 9 stages",
        reference: "Kahan & Li, Math. Comp. 66 (1997); Hairer, Lubich & Wanner, GNI V.3",
    },
    Scheme {
        id: "p8s15",
        order: 8,
        coefficients: &P8S15,
        name: "Kahan & Li, 15 stages",
        reference: "Kahan & Li, Math. Comp. 66 (1997); Hairer, Lubich & Wanner, GNI V.3",
    },
];

/// A symmetric composition scheme: a row of [`SCHEMES`], small and `Copy` so that a composed
/// method stays a small config value.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Composition(u8);

impl std::fmt::Debug for Composition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.id())
    }
}

impl Composition {
    /// Every scheme, in the order of [`SCHEMES`].
    pub const ALL: [Composition; SCHEMES.len()] = {
        let mut all = [Composition(0); SCHEMES.len()];
        let mut i = 0;
        while i < all.len() {
            all[i] = Composition(i as u8);
            i += 1;
        }
        all
    };

    /// The scheme's row.
    pub fn scheme(self) -> &'static Scheme {
        &SCHEMES[usize::from(self.0)]
    }

    /// Id, as in the API (`p4s3`: order 4, 3 stages).
    pub fn id(self) -> &'static str {
        self.scheme().id
    }

    /// The scheme with this id.
    pub fn from_id(id: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|c| c.id() == id)
    }

    /// Order of the composition of a symmetric method of order 2.
    pub fn order(self) -> u32 {
        self.scheme().order
    }

    /// The sub-step coefficients γ₁ … γ_s, in the order the sub-steps are taken.
    pub fn coefficients(self) -> &'static [f64] {
        self.scheme().coefficients
    }

    /// Sub-steps per step.
    pub fn stages(self) -> usize {
        self.coefficients().len()
    }

    /// Human name.
    pub fn name(self) -> &'static str {
        self.scheme().name
    }

    /// Where the coefficients come from.
    pub fn reference(self) -> &'static str {
        self.scheme().reference
    }
}

/// A method taken as a symmetric composition of its steps: `step` stays the full step h, the
/// sub-steps are `γ_i h`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Composed<M> {
    /// The symmetric method composed.
    pub base: M,
    /// The scheme.
    pub composition: Composition,
}

impl<M: Integrator> Stepper for Composed<M> {
    type Memory<const N: usize, const R: usize> = M::Memory<N, R>;

    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        state: &mut State<N, R>,
        memory: &mut Self::Memory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        for &gamma in self.composition.coefficients() {
            self.base.step(sys, state, memory, gamma * h)?;
        }
        Ok(())
    }
}

impl<M: Integrator> GeneralStepper for Composed<M> {
    #[inline]
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        state: &mut State<N, R>,
        memory: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        for &gamma in self.composition.coefficients() {
            self.base.step_general(sys, state, memory, gamma * h)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficients_sum_to_one_and_read_the_same_backwards() {
        for c in Composition::ALL {
            let g = c.coefficients();
            assert_eq!(g.len(), c.stages());
            assert!((g.iter().sum::<f64>() - 1.0).abs() < 4e-16, "{}: Σγ ≠ 1", c.id());
            assert!(g.iter().eq(g.iter().rev()), "{} is not symmetric", c.id());
            // Order p needs Σγᵏ = 0 for odd 3 ≤ k < p: necessary conditions, the rest is
            // checked by the orders measured in tests/it/compositions.rs.
            for k in (3..c.order()).step_by(2) {
                let power: f64 = g.iter().map(|x| x.powi(k as i32)).sum();
                assert!(power.abs() < 1e-14, "{}: Σγ^{k} = {power}", c.id());
            }
            assert_eq!(Composition::from_id(c.id()), Some(c));
            assert_eq!(c.id(), format!("p{}s{}", c.order(), c.stages()), "the id says both");
        }
        assert_eq!(Composition::from_id("p4s4"), None);
    }

    #[test]
    fn the_triple_jump_is_yoshidas() {
        let g = Composition::from_id("p4s3").expect("listed").coefficients();
        let cbrt2 = 2f64.powf(1.0 / 3.0);
        assert!((g[0] - 1.0 / (2.0 - cbrt2)).abs() < 1e-15);
        assert!((g[1] + cbrt2 / (2.0 - cbrt2)).abs() < 1e-15);
        let g = Composition::from_id("p4s5").expect("listed").coefficients();
        assert!((g[2] + 4f64.powf(1.0 / 3.0) / (4.0 - 4f64.powf(1.0 / 3.0))).abs() < 1e-15);
    }
}
