//! How each coordinate of the passenger passes kicks on in SPARK's class step
//! (`spark/class.rs`, `docs/model.md` §3). With K = ∇²U diagonal, a coordinate with K's entry κ
//! and the raw kicks u_m = A(ζ_m)ᵀ Z_m − h ∇U(q₀) (m < s) has stage displacements
//! D_i = Q_i − q₀ that solve D_i + h²κ Σ_j (aā)_ij D_j = h c_i q̇₀ + h Σ_m (aā)_im u_m
//! (i, j = 2 … s − 1), and kicks k_j = u_j − hκ D_j = Σ_m Φ_jm u_m − ψ_j q̇₀; the stage
//! velocities V_l = q̇₀ + Σ_j ā_lj k_j then move by Ω = ā Φ, and the weighted constraints
//! Σ_l a_kl A(ζ_l) V_l by a_kl Ω_lm. For κ = 0: Φ = I, ψ = 0. These depend on the tableau, h and
//! κ alone, so a run computes them once ([`Responses::prepare`] keeps them while those stay).

#![allow(
    clippy::needless_range_loop,
    reason = "stage indices i, j, k, l, m run over parts of the stages, as the equations write them"
)]

use super::tableau::Lobatto;
use crate::Vector;
use crate::linalg::{lu_in_place, lu_solve_in_place};

/// The most stages a SPARK method has: the responses are stored at this size.
pub(super) const MAX_STAGES: usize = 5;
const M: usize = MAX_STAGES;

/// One entry κ of K's diagonal: see the module's doc. Indices as the stages' (from 0).
#[derive(Debug, Clone, Copy)]
pub(super) struct Response {
    /// κ.
    pub kappa: f64,
    /// Φ: the kicks k_j (j < s) from the raw kicks u_m.
    pub phi: [[f64; M]; M],
    /// ψ: the kicks' part in q̇₀.
    pub psi: [f64; M],
    /// a_kl Ω_lm, as `weight[k][m][l]`: constraint k's response to u_m through stage l.
    pub weight: [[[f64; M]; M]; M],
}

impl Response {
    fn new<const S: usize>(t: &Lobatto<S>, h: f64, kappa: f64) -> Option<Self> {
        let mut phi = [[0.0; M]; M];
        for (j, row) in phi.iter_mut().enumerate().take(S) {
            row[j] = 1.0;
        }
        let mut psi = [0.0; M];
        let d = S - 2;
        if kappa != 0.0 && d > 0 {
            // β = (I + h²κ P)⁻¹, P the (aā) block of stages 2 … s − 1, applied column by column.
            let (mut b, mut swaps) = ([0.0; 9], [0usize; 3]);
            for i in 0..d {
                for j in 0..d {
                    let identity = f64::from(u8::from(i == j));
                    b[i * d + j] = identity + h * h * kappa * t.aa[i + 1][j + 1];
                }
            }
            lu_in_place(&mut b[..d * d], d, &mut swaps[..d])?;
            let hk = h * kappa;
            // Θ_·m = h β (aā)_·m, Φ_jm = δ_jm − hκ Θ_jm; then ψ = hκ · h β c.
            for m in 0..S {
                let mut col = [0.0; 3];
                for i in 0..d {
                    col[i] = h * if m + 1 < S { t.aa[i + 1][m] } else { t.c[i + 1] };
                }
                lu_solve_in_place(&b[..d * d], d, &swaps[..d], &mut col[..d]);
                for i in 0..d {
                    if m + 1 < S {
                        phi[i + 1][m] -= hk * col[i];
                    } else {
                        psi[i + 1] = hk * col[i];
                    }
                }
            }
        }
        let mut weight = [[[0.0; M]; M]; M];
        for l in 0..S {
            for m in 0..S - 1 {
                let omega: f64 = (0..S - 1).map(|j| t.abar[l][j] * phi[j][m]).sum();
                for k in 1..S {
                    weight[k][m][l] = t.a[k][l] * omega;
                }
            }
        }
        Some(Self { kappa, phi, psi, weight })
    }
}

/// The responses of K's distinct entries and which one each coordinate takes (the
/// driver's: κ = 0, its kicks being its own), kept for the tableau, h and K they were made for.
#[derive(Debug, Default)]
pub(super) struct Responses {
    key: Vec<u64>,
    of: Vec<Response>,
    coordinate: Vec<usize>,
}

impl Responses {
    /// Made for the `S`-stage tableau, h and K's diagonal `kappa`, unless they are already;
    /// `None` where a coordinate's system in the displacements is singular.
    pub(super) fn prepare<const S: usize, const N: usize>(
        &mut self,
        t: &Lobatto<S>,
        h: f64,
        kappa: &Vector<N>,
    ) -> Option<()> {
        let key = [S as u64, h.to_bits()].into_iter().chain(kappa.iter().map(|k| k.to_bits()));
        if self.key.len() == N + 2 && key.clone().eq(self.key.iter().copied()) {
            return Some(());
        }
        self.key.clear();
        self.of.clear();
        self.coordinate.clear();
        self.of.push(Response::new(t, h, 0.0)?);
        for r in 0..N {
            let k = if r + 1 < N { kappa[r] } else { 0.0 };
            let group = match self.of.iter().position(|g| g.kappa == k) {
                Some(g) => g,
                None => {
                    self.of.push(Response::new(t, h, k)?);
                    self.of.len() - 1
                }
            };
            self.coordinate.push(group);
        }
        self.key.extend(key);
        Some(())
    }

    /// The distinct entries' responses (the first is κ = 0's).
    #[inline]
    pub(super) fn groups(&self) -> &[Response] {
        &self.of
    }

    /// Which of [`Responses::groups`] coordinate r takes.
    #[inline]
    pub(super) fn group(&self, r: usize) -> usize {
        self.coordinate[r]
    }
}
