//! The [`Prk`] step on the general class, solved by Newton on the whole system. The unknowns
//! are the stage velocities V_1 … V_s and the scaled multipliers Z = hΛ (one per forced stage
//! for `stage`, one for the step otherwise); the stage positions are explicit in the
//! velocities, `Q_i = q₀ + h Σ_j a_ij V_j`. With `k_j = A(Q_j)ᵀ Z_j − h∇V(Q_j)` and
//! `K_j = ∂k_j/∂Q_j = ∂(A(Q_j)ᵀ Z_j)/∂q − h∇²V(Q_j)`, the equations and their derivatives
//! are
//!
//! ```text
//! E_i = M(V_i − q̇₀) − Σ_j â_ij k_j        ∂E_i/∂V_l = M δ_il − h Σ_j â_ij a_jl K_j
//!                                          ∂E_i/∂Z   = −Σ_j â_ij A(Q_j)ᵀ   (j of that Z)
//! stage:    G_i = Σ_j a_ij A(Q_j) V_j     ∂G_i/∂V_l = a_il A(Q_l) + h Σ_j a_ij a_jl C_j(V_j)
//! end:      G = A(q₁) q̇₁                  through q₁ = q₀ + hΣ b_j V_j, q̇₁ = q̇₀ + M⁻¹Σ b̂_j k_j
//! midpoint: G = A(q_m) u, u = Σ b_j V_j,  q_m = q₀ + (h/2) u
//! ```
//!
//! with `C_j(u) = ∂(A u)/∂q` at Q_j. The Jacobian is exact and taken afresh at every
//! iterate; its size d = sN + (multipliers)·R stays small (s ≤ 5), and its storage is kept per
//! thread, so a step allocates nothing once the first has sized it.

#![allow(
    clippy::needless_range_loop,
    reason = "stage indices i, j, l run over the tableau's stages, as the equations write them"
)]

use super::tableau::MAX_STAGES;
use super::{Constraint, Prk};
use crate::linalg::{Lu, Scratch, lu_in_place, lu_solve_in_place};
use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::GeneralStepper;
use crate::model::mechanical::{Derivatives, Forces, Mechanical, acceleration_at};
use crate::solver::newton::counted;
use crate::{Matrix, State, StepFailure, Vector};
use std::cell::RefCell;

std::thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

impl GeneralStepper for Prk {
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        SCRATCH.with(|cell| Solve::new(self, sys, h).step(&mut cell.borrow_mut(), st, mem))
    }
}

/// One step's layout: which multiplier each stage takes and which rows carry conditions.
struct Solve<'a, const N: usize, const R: usize, M: Mechanical<N, R>> {
    prk: &'a Prk,
    sys: &'a M,
    h: f64,
    /// The multiplier of stage j, if it has one.
    multiplier: [Option<usize>; MAX_STAGES],
    /// Multipliers.
    count: usize,
    /// For `stage`: the row of a each condition takes.
    rows: [usize; MAX_STAGES],
}

/// The stages at an iterate.
struct Stages<const N: usize, const R: usize> {
    v: [Vector<N>; MAX_STAGES],
    z: [Vector<R>; MAX_STAGES],
    q: [Vector<N>; MAX_STAGES],
    f: [Forces<N, R>; MAX_STAGES],
    d: [Derivatives<N, R>; MAX_STAGES],
    kick: [Vector<N>; MAX_STAGES],
}

impl<'a, const N: usize, const R: usize, M: Mechanical<N, R>> Solve<'a, N, R, M> {
    fn new(prk: &'a Prk, sys: &'a M, h: f64) -> Self {
        let t = &prk.tableau;
        let (mut multiplier, mut rows, mut count) = ([None; MAX_STAGES], [0; MAX_STAGES], 0);
        match prk.constraint {
            Constraint::Stage => {
                for (g, j) in t.forced_stages().enumerate() {
                    multiplier[j] = Some(g);
                    count = g + 1;
                }
                for (g, i) in t.constrained_stages().enumerate() {
                    rows[g] = i;
                }
            }
            Constraint::End | Constraint::Midpoint => {
                for j in 0..t.stages {
                    multiplier[j] = Some(0);
                }
                count = 1;
            }
        }
        Self { prk, sys, h, multiplier, count, rows }
    }

    fn step(&self, scratch: &mut Scratch, st: &mut State<N, R>, mem: &mut GeneralMemory<N, R>) -> Result<(), StepFailure> {
        let (t, h, mass) = (&self.prk.tableau, self.h, self.sys.mass());
        let s = t.stages;
        let start = mem.forces(self.sys, &st.q);
        let a0 = mass.solve(&(start.constraint.transpose() * st.lambda - start.gradient));
        let zero_d = Derivatives { hessian: Matrix::zeros(), partials: [Matrix::zeros(); N] };
        let mut x = Stages {
            v: std::array::from_fn(|i| st.v + (h * t.c[i]) * a0),
            z: [h * st.lambda; MAX_STAGES],
            q: [st.q; MAX_STAGES],
            f: [start; MAX_STAGES],
            d: [zero_d; MAX_STAGES],
            kick: [Vector::zeros(); MAX_STAGES],
        };
        let d = s * N + self.count * R;
        let (jac, swaps, res) = scratch.sized(d);
        let cfg = &self.prk.newton;
        let (mut done, mut iterations, mut previous) = (false, 0, f64::INFINITY);
        loop {
            self.evaluate(&mut x, &st.q);
            if done {
                break;
            }
            if iterations == cfg.max_iter {
                return counted(iterations, Err(StepFailure::NewtonDiverged { iterations, increment: f64::NAN }));
            }
            iterations += 1;
            self.assemble(&x, st, jac, res);
            if lu_in_place(jac, d, swaps).is_none() {
                return counted(iterations, Err(StepFailure::Singular));
            }
            lu_solve_in_place(jac, d, swaps, res);
            let (mut step, mut size) = (0.0_f64, 0.0_f64);
            for i in 0..s {
                for n in 0..N {
                    x.v[i][n] -= res[i * N + n];
                    size = size.max(x.v[i][n].abs());
                }
            }
            for g in 0..self.count {
                for r in 0..R {
                    x.z[g][r] -= res[s * N + g * R + r];
                    size = size.max(x.z[g][r].abs());
                }
            }
            for &d in res.iter() {
                step = step.max(d.abs());
            }
            if !res.iter().all(|d| d.is_finite()) {
                return counted(iterations, Err(StepFailure::NonFinite));
            }
            // Exact Newton: the error this update leaves is about δ²/δ' (C = 1).
            let left = if previous.is_finite() { step * step / previous } else { f64::INFINITY };
            done = cfg.converged(step, (left, step), previous, 1.0 + size);
            if iterations == cfg.max_iter && !done {
                return counted(iterations, Err(StepFailure::NewtonDiverged { iterations, increment: step }));
            }
            previous = step;
        }
        counted(iterations, Ok(()))?;
        let (dq, v1) = self.end(&x, &st.v);
        st.advance_to(dq, v1);
        let (end, d_end) = self.sys.forces_and_derivatives(&st.q);
        let mut z_mean = Vector::<R>::zeros();
        for g in 0..self.count {
            z_mean += x.z[g] / self.count as f64;
        }
        if self.prk.constraint == Constraint::Stage {
            // q̇₁ projected onto A(q₁) q̇ = 0 in the M-norm.
            let a = end.constraint;
            let m_inv_at = mass.solve_columns(&a.transpose());
            let mu = Lu::new(a * m_inv_at).ok_or(StepFailure::Singular)?.solve(&(a * st.v));
            st.v -= m_inv_at * mu;
        }
        st.lambda = acceleration_at(mass, &end, &d_end, &st.v).map_or(z_mean / h, |(_, lambda)| lambda);
        mem.remember(&st.q, end);
        if st.is_finite() { Ok(()) } else { Err(StepFailure::NonFinite) }
    }

    /// The stage positions, forces, derivatives and kicks of the iterate's (V, Z).
    fn evaluate(&self, x: &mut Stages<N, R>, q0: &Vector<N>) {
        let (t, h) = (&self.prk.tableau, self.h);
        for i in 0..t.stages {
            let mut q = *q0;
            for j in 0..t.stages {
                q += (h * t.a[i][j]) * x.v[j];
            }
            x.q[i] = q;
            (x.f[i], x.d[i]) = self.sys.forces_and_derivatives(&q);
            x.kick[i] = -h * x.f[i].gradient;
            if let Some(g) = self.multiplier[i] {
                x.kick[i] += x.f[i].constraint.transpose() * x.z[g];
            }
        }
    }

    /// `(q₁ − q₀, q̇₁)` before any projection.
    fn end(&self, x: &Stages<N, R>, v0: &Vector<N>) -> (Vector<N>, Vector<N>) {
        let t = &self.prk.tableau;
        let (mut dq, mut p) = (Vector::<N>::zeros(), Vector::<N>::zeros());
        for j in 0..t.stages {
            dq += (self.h * t.b[j]) * x.v[j];
            p += t.b_hat[j] * x.kick[j];
        }
        (dq, v0 + self.sys.mass().solve(&p))
    }

    /// The residual into `res` (Newton solves J δ = res and takes x − δ) and the Jacobian.
    fn assemble(&self, x: &Stages<N, R>, st: &State<N, R>, jac: &mut [f64], res: &mut [f64]) {
        let (t, h, mass) = (&self.prk.tableau, self.h, self.sys.mass());
        let s = t.stages;
        let d = s * N + self.count * R;
        jac.fill(0.0);
        let m = mass.matrix();
        let mut put = |row: usize, col: usize, block: &dyn Fn(usize, usize) -> f64, rows: usize, cols: usize| {
            for r in 0..rows {
                for c in 0..cols {
                    jac[(row + r) * d + col + c] += block(r, c);
                }
            }
        };
        // K_j = ∂k_j/∂Q_j.
        let k: [Matrix<N, N>; MAX_STAGES] = std::array::from_fn(|j| {
            let mut kj = -h * x.d[j].hessian;
            if let (true, Some(g)) = (j < s, self.multiplier[j]) {
                kj += x.d[j].force_jacobian(&x.z[g]);
            }
            kj
        });
        for i in 0..s {
            let mut e = m * (x.v[i] - st.v);
            for j in 0..s {
                e -= t.a_hat[i][j] * x.kick[j];
            }
            res[i * N..(i + 1) * N].copy_from_slice(e.as_slice());
            for l in 0..s {
                let mut block = if i == l { m } else { Matrix::zeros() };
                for j in 0..s {
                    block -= (h * t.a_hat[i][j] * t.a[j][l]) * k[j];
                }
                put(i * N, l * N, &|r, c| block[(r, c)], N, N);
            }
            for j in 0..s {
                if let Some(g) = self.multiplier[j] {
                    let at = t.a_hat[i][j] * x.f[j].constraint.transpose();
                    put(i * N, s * N + g * R, &|r, c| -at[(r, c)], N, R);
                }
            }
        }
        let base = s * N;
        match self.prk.constraint {
            Constraint::Stage => {
                for g in 0..self.count {
                    let i = self.rows[g];
                    let mut gi = Vector::<R>::zeros();
                    for j in 0..s {
                        gi += t.a[i][j] * (x.f[j].constraint * x.v[j]);
                    }
                    res[base + g * R..base + (g + 1) * R].copy_from_slice(gi.as_slice());
                    for l in 0..s {
                        let mut block = t.a[i][l] * x.f[l].constraint;
                        for j in 0..s {
                            block += (h * t.a[i][j] * t.a[j][l]) * x.d[j].constraint_jacobian(&x.v[j]);
                        }
                        put(base + g * R, l * N, &|r, c| block[(r, c)], R, N);
                    }
                }
            }
            Constraint::End => {
                let (dq, v1) = self.end(x, &st.v);
                let q1 = st.q + dq;
                let (f1, d1) = self.sys.forces_and_derivatives(&q1);
                let a1 = f1.constraint;
                res[base..base + R].copy_from_slice((a1 * v1).as_slice());
                let c1 = d1.constraint_jacobian(&v1);
                let a1_m_inv: Matrix<R, N> = mass.solve_columns(&a1.transpose()).transpose();
                for l in 0..s {
                    let mut block = (h * t.b[l]) * c1;
                    for j in 0..s {
                        block += (h * t.b_hat[j] * t.a[j][l]) * (a1_m_inv * k[j]);
                    }
                    put(base, l * N, &|r, c| block[(r, c)], R, N);
                }
                let mut block = Matrix::<R, R>::zeros();
                for j in 0..s {
                    block += t.b_hat[j] * (a1_m_inv * x.f[j].constraint.transpose());
                }
                put(base, base, &|r, c| block[(r, c)], R, R);
            }
            Constraint::Midpoint => {
                let mut u = Vector::<N>::zeros();
                for j in 0..s {
                    u += t.b[j] * x.v[j];
                }
                let (fm, dm) = self.sys.forces_and_derivatives(&(st.q + (0.5 * h) * u));
                res[base..base + R].copy_from_slice((fm.constraint * u).as_slice());
                let block = fm.constraint + (0.5 * h) * dm.constraint_jacobian(&u);
                for l in 0..s {
                    put(base, l * N, &|r, c| t.b[l] * block[(r, c)], R, N);
                }
            }
        }
    }
}
