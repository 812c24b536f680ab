//! The SPARK step on the general class (`docs/model.md` §3), solved in its reduced form. The
//! stage velocities are explicit in the stage positions and the scaled multipliers Z_j = hΛ_j:
//!
//! ```text
//! V_l = q̇₀ + M⁻¹ Σ_j ā_lj k_j,   k_j = A(Q_j)ᵀ Z_j − h ∇V(Q_j)
//! ```
//!
//! so Newton's unknowns are Q_2 … Q_s and Z_1 … Z_{s−1} (Q_1 = q₀; Z_s enters only q̇₁,
//! as IIIB's last column is zero): (s − 1)(N + R) of them, as many as RATTLE's for s = 2. The
//! equations are the IIIA positions E_i = Q_i − q₀ − h Σ_l a_il V_l and the weighted
//! constraints G_k = Σ_j a_kj A(Q_j) V_j, i, k = 2 … s. The position increments are
//! eliminated with an approximate inverse of their block ([`Pieces`]), which leaves a Schur
//! complement on the multipliers alone, (s − 1)R unknowns, the only system factored; the
//! rest are products of fixed-size blocks. The pieces are those of the first iterate (a
//! second-order Taylor guess), kept while the iteration contracts fast.

#![allow(
    clippy::needless_range_loop,
    reason = "stage indices i, k, l, m run over parts of the stages, as the equations write them"
)]

use super::Spark;
use super::tableau::{LOBATTO2, LOBATTO3, LOBATTO4, LOBATTO5, Lobatto};
use crate::linalg::{Lu, Scratch, lu_in_place, lu_solve_in_place};
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::GeneralStepper;
use crate::model::mechanical::{Derivatives, Forces, Mechanical, acceleration_at};
use crate::solver::newton::{NewtonConfig, counted};
use crate::{Matrix, State, StepFailure, Vector};
use std::cell::RefCell;

/// How an iteration's linear system is solved.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Linear {
    /// Through the Schur complement on the multipliers (`Pieces`).
    Structured,
    /// The whole (s − 1)(N + R) system, dense: where ρ = ‖hP‖ is too large for the series,
    /// or where the structured iteration did not contract.
    Dense,
}

/// The largest ρ = ‖hP‖ the structured solve takes (its rate ρ³/(1 − ρ) is then 0.04).
const RHO_MAX: f64 = 0.3;

std::thread_local! {
    /// Kept per thread, so that a step allocates nothing once the first has sized it.
    static SCRATCH: RefCell<(Scratch, Scratch)> = RefCell::new(Default::default());
}

/// A chord iteration contracting by more than this keeps its Jacobian.
const FAST_CONTRACTION: f64 = 0.05;

impl GeneralStepper for Spark {
    #[inline]
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        match self.stages {
            2 => Stages { spark: self, t: &LOBATTO2, sys, h }.step(st, mem),
            3 => Stages { spark: self, t: &LOBATTO3, sys, h }.step(st, mem),
            4 => Stages { spark: self, t: &LOBATTO4, sys, h }.step(st, mem),
            5 => Stages { spark: self, t: &LOBATTO5, sys, h }.step(st, mem),
            // `from_params` builds 2 … 5 only; a value set by hand has no tableau.
            _ => Err(StepFailure::Singular),
        }
    }
}

/// One step with the `S`-stage pair.
struct Stages<'a, const S: usize, const N: usize, const R: usize, M: Mechanical<N, R>> {
    spark: &'a Spark,
    t: &'a Lobatto<S>,
    sys: &'a M,
    h: f64,
}

/// An iterate: the stage positions and scaled multipliers (Q_1 = q₀, Z_s = 0), and what
/// they give: the forces at the stages, the kicks k_j and the stage velocities V_l.
struct Iterate<const S: usize, const N: usize, const R: usize> {
    q: [Vector<N>; S],
    z: [Vector<R>; S],
    f: [Forces<N, R>; S],
    kick: [Vector<N>; S],
    v: [Vector<N>; S],
}

impl<const S: usize, const N: usize, const R: usize, M: Mechanical<N, R>> Stages<'_, S, N, R, M> {
    fn step(&self, st: &mut State<N, R>, mem: &mut GeneralMemory<N, R>) -> Result<(), StepFailure> {
        let (sys, t, h) = (self.sys, self.t, self.h);
        let mass = sys.mass();
        let start = mem.forces(sys, &st.q);
        // The guess: Q_i by Taylor to second order, Z_j = hλ₀.
        let a0 = mass.solve(&(start.constraint.transpose() * st.lambda - start.gradient));
        let c: [f64; S] = std::array::from_fn(|i| t.a[i].iter().sum());
        let mut it = Iterate {
            q: std::array::from_fn(|i| st.q + (h * c[i]) * (st.v + (0.5 * h * c[i]) * a0)),
            z: std::array::from_fn(|j| if j + 1 < S { h * st.lambda } else { Vector::zeros() }),
            f: [start; S],
            kick: [Vector::zeros(); S],
            v: [st.v; S],
        };
        it.q[0] = st.q;
        SCRATCH.with(|cell| {
            let (schur, dense) = &mut *cell.borrow_mut();
            self.solve((schur, dense), st, &mut it)
        })?;
        // q₁ = q₀ + h Σ b_j V_j; M q̂̇₁ = M q̇₀ + Σ_j b_j k_j, with k_s = −h∇V(Q_s).
        let mut dq = Vector::<N>::zeros();
        let mut p = mass.times(&st.v);
        for j in 0..S {
            dq += (h * t.b[j]) * it.v[j];
            p += t.b[j] * it.kick[j];
        }
        let v_hat = mass.solve(&p);
        st.advance_to(dq, v_hat);
        // The end condition: q̇₁ projected onto A(q₁) q̇ = 0 in the M-norm.
        let (end, d_end) = sys.forces_and_derivatives(&st.q);
        let a = end.constraint;
        let m_inv_at = mass.solve_columns(&a.transpose());
        let mu = Lu::new(a * m_inv_at).ok_or(StepFailure::Singular)?.solve(&(a * v_hat));
        st.v = v_hat - m_inv_at * mu;
        // λ₁: the continuous multiplier at the new state (the next step's guess), else
        // h b_s Λ_s = −μ.
        st.lambda = acceleration_at(mass, &end, &d_end, &st.v).map_or(-mu / (h * t.b[S - 1]), |(_, lambda)| lambda);
        mem.remember(&st.q, end);
        Ok(())
    }

    /// The forces, kicks and stage velocities of the iterate's (Q, Z), from q̇₀ = `v0`.
    /// With `derivatives`, also ∇²V and ∂A/∂q at the stages (one call, where a system
    /// computes both at once).
    fn evaluate(&self, it: &mut Iterate<S, N, R>, v0: &Vector<N>, derivatives: Option<&mut [Derivatives<N, R>; S]>) {
        let (t, h, mass) = (self.t, self.h, self.sys.mass());
        match derivatives {
            Some(dr) => {
                for j in 1..S {
                    (it.f[j], dr[j]) = self.sys.forces_and_derivatives(&it.q[j]);
                }
            }
            None => {
                for j in 1..S {
                    it.f[j] = self.sys.forces(&it.q[j]);
                }
            }
        }
        for j in 0..S {
            it.kick[j] = it.f[j].constraint.transpose() * it.z[j] - h * it.f[j].gradient;
        }
        for l in 0..S {
            // ā's last column is zero: k_s enters q̇₁ alone.
            let mut p = Vector::<N>::zeros();
            for j in 0..S - 1 {
                p += t.abar[l][j] * it.kick[j];
            }
            it.v[l] = v0 + mass.solve(&p);
        }
    }

    /// Newton on (Q_2 … Q_s, Z_1 … Z_{s−1}); leaves the kicks and stage velocities at the solution
    /// (the last increment taken to first order, [`Self::follow`]).
    /// The Jacobian's pieces are those of the first iterate, kept while the iteration
    /// contracts fast and taken afresh where it does not.
    fn solve(
        &self,
        (schur_buf, dense_buf): (&mut Scratch, &mut Scratch),
        st: &State<N, R>,
        it: &mut Iterate<S, N, R>,
    ) -> Result<(), StepFailure> {
        let cfg: &NewtonConfig = &self.spark.newton;
        let mut pieces = Pieces::<S, N, R>::new();
        let mut dr = [Derivatives { hessian: Matrix::zeros(), partials: [Matrix::zeros(); N] }; S];
        let (mut kept, mut previous) = (false, f64::INFINITY);
        let mut linear = if self.spark.fast_path { Linear::Structured } else { Linear::Dense };
        for k in 1..=cfg.max_iter {
            self.evaluate(it, &st.v, (!kept).then_some(&mut dr));
            if !kept {
                self.linearize(&mut pieces, it, &dr);
                if pieces.rho > RHO_MAX {
                    linear = Linear::Dense;
                }
                let factored = match linear {
                    Linear::Structured => {
                        let d = (S - 1) * R;
                        let (a, swaps, _) = schur_buf.sized(d);
                        self.through_t(&mut pieces);
                        self.schur(a, d, &pieces);
                        lu_in_place(a, d, swaps)
                    }
                    Linear::Dense => {
                        let d = (S - 1) * (N + R);
                        let (a, swaps, _) = dense_buf.sized(d);
                        self.jacobian(a, d, &pieces);
                        lu_in_place(a, d, swaps)
                    }
                };
                if factored.is_none() {
                    return counted(k, Err(StepFailure::Singular));
                }
            }
            let (dq, dz) = match linear {
                Linear::Structured => self.increment(&pieces, schur_buf.sized((S - 1) * R), &st.q, it),
                Linear::Dense => self.dense_increment(dense_buf.sized((S - 1) * (N + R)), &st.q, it),
            };
            let (mut increment, mut size) = (0.0f64, 0.0f64);
            for i in 1..S {
                it.q[i] += dq[i];
                increment = increment.max(dq[i].amax());
                size = size.max(it.q[i].amax());
            }
            for m in 0..S - 1 {
                it.z[m] += dz[m];
                increment = increment.max(dz[m].amax());
                size = size.max(it.z[m].amax());
            }
            if !increment.is_finite() {
                return counted(k, Err(StepFailure::NonFinite));
            }
            // The Jacobian is approximate (`Pieces`), so the iteration is linear: the error
            // this update leaves is about δ²/δ' (its rate δ/δ' times δ). After the first
            // update, whose pieces are of this iterate, it is the approximation's rate times
            // δ plus Newton's δ² (as `NewtonConfig::converged` takes it, C = 1).
            let rate = if linear == Linear::Dense { 0.0 } else { pieces.rate() };
            let left = if previous.is_finite() {
                increment * increment / previous
            } else {
                increment * (rate + increment)
            };
            if cfg.converged(increment, (left, increment), previous, 1.0 + size) {
                // The last increment is small: its effect on the kicks and velocities is taken
                // to first order, which leaves an error of the order of `left`.
                self.follow(it, &pieces, &dr, (&dq, &dz));
                return counted(k, Ok(()));
            }
            // Keep the pieces while they contract fast; else take them at the next iterate,
            // and where the structured iteration did not contract at all, solve densely.
            kept = increment <= FAST_CONTRACTION * previous || !previous.is_finite();
            if increment > previous && linear == Linear::Structured {
                (linear, kept) = (Linear::Dense, false);
            }
            previous = increment;
        }
        counted(cfg.max_iter, Err(StepFailure::NewtonDiverged { iterations: cfg.max_iter, increment: previous }))
    }

    /// The Jacobian's pieces at the iterate (`Pieces`).
    fn linearize(&self, p: &mut Pieces<S, N, R>, it: &Iterate<S, N, R>, dr: &[Derivatives<N, R>; S]) {
        let (t, h, mass) = (self.t, self.h, self.sys.mass());
        let mut bend = [Matrix::<R, N>::zeros(); S];
        for m in 1..S {
            bend[m] = dr[m].constraint_jacobian(&it.v[m]);
            if m + 1 < S {
                p.w[m] = mass.solve_columns(&(dr[m].force_jacobian(&it.z[m]) - h * dr[m].hessian));
            }
        }
        // ρ = ‖hP‖∞ (rows of blocks, each block's max row sum).
        p.rho = (1..S)
            .map(|i| (1..S - 1).map(|m| h * t.aa[i][m].abs() * row_sum_norm(&p.w[m])).sum::<f64>())
            .fold(0.0, f64::max);
        for m in 0..S - 1 {
            p.u[m] = mass.solve_columns(&it.f[m].constraint.transpose());
        }
        for k in 1..S {
            for m in 0..S {
                let mut c = Matrix::<R, N>::zeros();
                for j in 0..S {
                    c += (t.a[k][j] * t.abar[j][m]) * it.f[j].constraint;
                }
                p.c[k][m] = c;
                if m >= 1 {
                    p.gq[k][m] = t.a[k][m] * bend[m] + c * p.w[m];
                }
            }
        }
    }

    /// The kicks and stage velocities moved by the increment (δQ, δZ) to first order:
    /// δk_j = ∂k_j/∂Q_j δQ_j + A(Q_j)ᵀ δZ_j, δV_l = M⁻¹ Σ_j ā_lj δk_j.
    fn follow(
        &self,
        it: &mut Iterate<S, N, R>,
        p: &Pieces<S, N, R>,
        dr: &[Derivatives<N, R>; S],
        (dq, dz): (&[Vector<N>; S], &[Vector<R>; S]),
    ) {
        let (t, h, mass) = (self.t, self.h, self.sys.mass());
        let mut dv = [Vector::<N>::zeros(); S];
        for j in 0..S {
            let dk = if j + 1 == S {
                -h * (dr[j].hessian * dq[j])
            } else {
                let moved = if j == 0 { Vector::zeros() } else { mass.times(&(p.w[j] * dq[j])) };
                moved + it.f[j].constraint.transpose() * dz[j]
            };
            it.kick[j] += dk;
            if j + 1 < S {
                for (l, dvl) in dv.iter_mut().enumerate() {
                    *dvl += t.abar[l][j] * dk;
                }
            }
        }
        for (v, dvl) in it.v.iter_mut().zip(&dv) {
            *v += mass.solve(dvl);
        }
    }

    /// hP x: (hP x)_i = h Σ_m (aā)_im W_m x_m.
    fn hp_times(&self, p: &Pieces<S, N, R>, x: &[Vector<N>; S]) -> [Vector<N>; S] {
        let (t, h) = (self.t, self.h);
        std::array::from_fn(|i| {
            let mut y = Vector::<N>::zeros();
            if i >= 1 {
                for m in 1..S - 1 {
                    y += (h * t.aa[i][m]) * (p.w[m] * x[m]);
                }
            }
            y
        })
    }

    /// T x = x + hP x + (hP)² x, the approximate inverse of the position rows' block I − hP.
    fn t_times(&self, p: &Pieces<S, N, R>, x: &[Vector<N>; S]) -> [Vector<N>; S] {
        let once = self.hp_times(p, x);
        let twice = self.hp_times(p, &once);
        std::array::from_fn(|i| x[i] + once[i] + twice[i])
    }

    /// G_Q T = G_Q (I + hP + (hP)²), block by block: (G_Q hP)_km = (Σ_i h (aā)_im G_Q,ki) W_m,
    /// and (hP)² as hP once more. One row of blocks per constraint stage, so that neither the
    /// Schur complement nor the right-hand side applies T to a column at a time.
    fn through_t(&self, p: &mut Pieces<S, N, R>) {
        let once = self.times_hp(&p.gq, p);
        let twice = self.times_hp(&once, p);
        for k in 1..S {
            for i in 1..S {
                p.gt[k][i] = p.gq[k][i] + once[k][i] + twice[k][i];
            }
        }
    }

    /// X hP for a row of blocks per constraint stage: (X hP)_km = (Σ_i h (aā)_im X_ki) W_m.
    fn times_hp(&self, x: &[[Matrix<R, N>; S]; S], p: &Pieces<S, N, R>) -> [[Matrix<R, N>; S]; S] {
        let (t, h) = (self.t, self.h);
        let mut y = [[Matrix::<R, N>::zeros(); S]; S];
        for k in 1..S {
            for m in 1..S - 1 {
                let mut weighted = Matrix::<R, N>::zeros();
                for i in 1..S {
                    weighted += (h * t.aa[i][m]) * x[k][i];
                }
                y[k][m] = weighted * p.w[m];
            }
        }
        y
    }

    /// The Schur complement S = G_Z − G_Q T E_Z on the multipliers into `out` ((s − 1)R
    /// square, row-major): as E_Z's blocks are −h (aā)_im U_m, its (k, m) block is
    /// (C_km + Σ_i h (aā)_im (G_Q T)_ki) U_m.
    fn schur(&self, out: &mut [f64], d: usize, p: &Pieces<S, N, R>) {
        let (t, h) = (self.t, self.h);
        for k in 1..S {
            for m in 0..S - 1 {
                let mut left = p.c[k][m];
                for i in 1..S {
                    left += (h * t.aa[i][m]) * p.gt[k][i];
                }
                let block = left * p.u[m];
                for row in 0..R {
                    let line = ((k - 1) * R + row) * d + m * R;
                    for col in 0..R {
                        out[line + col] = block[(row, col)];
                    }
                }
            }
        }
    }

    /// The residuals: E_i = Q_i − q₀ − h Σ_l a_il V_l and G_k = Σ_j a_kj A(Q_j) V_j,
    /// i, k = 2 … s (entry 0 unused).
    fn residuals(&self, q0: &Vector<N>, it: &Iterate<S, N, R>) -> ([Vector<N>; S], [Vector<R>; S]) {
        let (t, h) = (self.t, self.h);
        let e = std::array::from_fn(|i| {
            let mut e = Vector::<N>::zeros();
            if i >= 1 {
                e = it.q[i] - q0;
                for l in 0..S {
                    e -= (h * t.a[i][l]) * it.v[l];
                }
            }
            e
        });
        let g = std::array::from_fn(|k| {
            let mut g = Vector::<R>::zeros();
            if k >= 1 {
                for j in 0..S {
                    g += t.a[k][j] * (it.f[j].constraint * it.v[j]);
                }
            }
            g
        });
        (e, g)
    }

    /// Newton's increment (δQ, δZ) at the iterate: with T ≈ (I − hP)⁻¹,
    /// S δZ = −r_G + G_Q T r_E and δQ = −T (r_E + E_Z δZ).
    fn increment(
        &self,
        p: &Pieces<S, N, R>,
        (schur, swaps, rhs): (&mut [f64], &mut [usize], &mut [f64]),
        q0: &Vector<N>,
        it: &Iterate<S, N, R>,
    ) -> ([Vector<N>; S], [Vector<R>; S]) {
        let (t, h) = (self.t, self.h);
        let (r_e, r_g) = self.residuals(q0, it);
        for k in 1..S {
            let mut g = -r_g[k];
            for i in 1..S {
                g += p.gt[k][i] * r_e[i];
            }
            rhs[(k - 1) * R..k * R].copy_from_slice(g.as_slice());
        }
        lu_solve_in_place(schur, rhs.len(), swaps, rhs);
        let dz: [Vector<R>; S] = std::array::from_fn(|m| {
            if m + 1 < S { Vector::<R>::from_column_slice(&rhs[m * R..(m + 1) * R]) } else { Vector::zeros() }
        });
        let y: [Vector<N>; S] = std::array::from_fn(|i| {
            let mut y = -r_e[i];
            if i >= 1 {
                for m in 0..S - 1 {
                    y += (h * t.aa[i][m]) * (p.u[m] * dz[m]);
                }
            }
            y
        });
        (self.t_times(p, &y), dz)
    }

    /// Newton's increment from the whole Jacobian ([`Self::jacobian`]), factored densely.
    fn dense_increment(
        &self,
        (jac, swaps, r): (&mut [f64], &mut [usize], &mut [f64]),
        q0: &Vector<N>,
        it: &Iterate<S, N, R>,
    ) -> ([Vector<N>; S], [Vector<R>; S]) {
        let (r_e, r_g) = self.residuals(q0, it);
        let zc = (S - 1) * N;
        for i in 1..S {
            r[(i - 1) * N..i * N].copy_from_slice(r_e[i].as_slice());
            r[zc + (i - 1) * R..zc + i * R].copy_from_slice(r_g[i].as_slice());
        }
        lu_solve_in_place(jac, r.len(), swaps, r);
        let dq = std::array::from_fn(|i| {
            if i == 0 { Vector::zeros() } else { -Vector::<N>::from_column_slice(&r[(i - 1) * N..i * N]) }
        });
        let dz = std::array::from_fn(|m| {
            if m + 1 < S { -Vector::<R>::from_column_slice(&r[zc + m * R..zc + (m + 1) * R]) } else { Vector::zeros() }
        });
        (dq, dz)
    }

    /// The whole Jacobian in (Q_2 … Q_s, Z_1 … Z_{s−1}) from its pieces, row by row into
    /// `jac` (d × d, d = (s − 1)(N + R)).
    fn jacobian(&self, jac: &mut [f64], d: usize, p: &Pieces<S, N, R>) {
        let (t, h) = (self.t, self.h);
        let zc = (S - 1) * N;
        jac.fill(0.0);
        for i in 1..S {
            let row = (i - 1) * N;
            for m in 1..S {
                let mut block = if m == i { Matrix::<N, N>::identity() } else { Matrix::zeros() };
                if m + 1 < S {
                    block -= (h * t.aa[i][m]) * p.w[m];
                }
                put(jac, d, (row, (m - 1) * N), &block);
            }
            for m in 0..S - 1 {
                put(jac, d, (row, zc + m * R), &(-(h * t.aa[i][m]) * p.u[m]));
            }
        }
        for k in 1..S {
            let row = zc + (k - 1) * R;
            for m in 1..S {
                put(jac, d, (row, (m - 1) * N), &p.gq[k][m]);
            }
            for m in 0..S - 1 {
                put(jac, d, (row, zc + m * R), &(p.c[k][m] * p.u[m]));
            }
        }
    }
}

/// Writes `block` into the d × d row-major `jac` with its top left at `(row, col)`.
fn put<const P: usize, const Q: usize>(jac: &mut [f64], d: usize, (row, col): (usize, usize), block: &Matrix<P, Q>) {
    for r in 0..P {
        let line = &mut jac[(row + r) * d + col..(row + r) * d + col + Q];
        for (c, x) in line.iter_mut().enumerate() {
            *x = block[(r, c)];
        }
    }
}

/// The Jacobian of the equations (E_2 … E_s, G_2 … G_s) in (Q_2 … Q_s, Z_1 … Z_{s−1}), in
/// pieces. With W_m = M⁻¹ ∂k_m/∂Q_m, U_m = M⁻¹ A(Q_m)ᵀ, (aā)_im = Σ_l a_il ā_lm and
/// C_km = Σ_j a_kj ā_jm A(Q_j):
///
/// ```text
/// ∂E_i/∂Q_m = δ_im − h (aā)_im W_m =: (I − hP)_im    ∂E_i/∂Z_m = −h (aā)_im U_m =: E_Z
/// ∂G_k/∂Q_m = a_km ∂(A(Q) V_m)/∂Q + C_km W_m =: G_Q  ∂G_k/∂Z_m = C_km U_m =: G_Z
/// ```
///
/// W_m = O(h) (its terms are h∇²V and ∂(AᵀZ)/∂q with Z = hΛ), so hP = O(h²) and
/// T = I + hP + (hP)² inverts I − hP up to O(h⁶) (ρ³/(1 − ρ) with ρ = ‖hP‖): eliminating δQ
/// with T leaves a Schur complement on the multipliers alone, (s − 1)R unknowns, and an
/// iteration whose rate is that beyond Newton's. T enters through G_Q T, formed once per
/// Jacobian (R rows per stage), and once applied to a vector for δQ. Every other product is
/// one of fixed-size blocks. For s = 2, hP = 0 and it is Newton's.
struct Pieces<const S: usize, const N: usize, const R: usize> {
    rho: f64,
    w: [Matrix<N, N>; S],
    u: [Matrix<N, R>; S],
    c: [[Matrix<R, N>; S]; S],
    gq: [[Matrix<R, N>; S]; S],
    /// G_Q T, the structured solve's ([`Stages::through_t`]).
    gt: [[Matrix<R, N>; S]; S],
}

impl<const S: usize, const N: usize, const R: usize> Pieces<S, N, R> {
    fn new() -> Self {
        Self {
            rho: 0.0,
            w: [Matrix::zeros(); S],
            u: [Matrix::zeros(); S],
            c: [[Matrix::zeros(); S]; S],
            gq: [[Matrix::zeros(); S]; S],
            gt: [[Matrix::zeros(); S]; S],
        }
    }
}

impl<const S: usize, const N: usize, const R: usize> Pieces<S, N, R> {
    /// The rate T's approximation leaves to the iteration, ρ³/(1 − ρ) (infinite for ρ ≥ ½,
    /// where the series is not trusted).
    fn rate(&self) -> f64 {
        if self.rho < 0.5 { self.rho.powi(3) / (1.0 - self.rho) } else { f64::INFINITY }
    }
}

/// The max-norm of a matrix: its largest absolute row sum.
fn row_sum_norm<const N: usize>(m: &Matrix<N, N>) -> f64 {
    (0..N).map(|r| m.row(r).iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max)
}
