//! The SPARK step on the paper's class where U is quadratic with a diagonal Hessian K
//! (`docs/model.md` §3, "SPARK on the paper's class"): the same equations as the general
//! step's, solved with what the class gives. A has no driver column and V splits, so the
//! driver's stages ζ_2 … ζ_s are those of the Lobatto IIIA–IIIB pair on ζ̈ = −V_d'(ζ) alone
//! (a Newton solve in s − 2 unknowns, explicit for s = 2); with them A(ζ_j) is known at every
//! stage, ∇U(Q_j) = ∇U(q₀) + K (Q_j − q₀) exactly, and the passenger's equations are linear in
//! the scaled multipliers Z_1 … Z_{s−1}: one solve of (s − 1)R unknowns, no iteration. The
//! coupling of the stage positions through K is eliminated coordinate by coordinate (K is
//! diagonal), once per run for each distinct entry of K (`spark/response.rs`).

#![allow(
    clippy::needless_range_loop,
    reason = "stage indices i, j, l, m run over parts of the stages, as the equations write them"
)]

use super::Spark;
use super::response::{Response, Responses};
use super::tableau::{LOBATTO2, LOBATTO3, LOBATTO4, LOBATTO5, Lobatto};
use crate::linalg::{Lu, Scratch, lu_in_place, lu_solve_in_place};
use crate::methods::general_memory::GeneralMemory;
use crate::model::mechanical::{Forces, General};
use crate::model::system::{DriverTerms, System, constraint_force};
use crate::solver::angle_tracker::AngleTracker;
use crate::solver::newton::counted;
use crate::{Matrix, State, StepFailure, Vector};
use std::cell::RefCell;

std::thread_local! {
    /// The multipliers' system and the responses, kept per thread so that a step allocates
    /// nothing and a run computes its responses once.
    static WORK: RefCell<(Scratch, Responses)> = RefCell::new(Default::default());
}

/// K's diagonal where the class step runs on `sys` at q: U quadratic and ∇²U diagonal.
#[inline]
pub(super) fn diagonal_hessian<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    q: &Vector<N>,
) -> Option<Vector<N>> {
    if !sys.quadratic_passenger() {
        return None;
    }
    let k = sys.passenger_hessian(q);
    let diagonal = k.diagonal();
    (k == Matrix::from_diagonal(&diagonal)).then_some(diagonal)
}

impl Spark {
    /// One step on the class, K's diagonal `kappa` ([`diagonal_hessian`]).
    #[inline]
    pub(super) fn step_class<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
        kappa: &Vector<N>,
    ) -> Result<(), StepFailure> {
        match self.stages {
            2 => Class { spark: self, t: &LOBATTO2, sys, h }.step(st, mem, kappa),
            3 => Class { spark: self, t: &LOBATTO3, sys, h }.step(st, mem, kappa),
            4 => Class { spark: self, t: &LOBATTO4, sys, h }.step(st, mem, kappa),
            5 => Class { spark: self, t: &LOBATTO5, sys, h }.step(st, mem, kappa),
            _ => Err(StepFailure::Singular),
        }
    }
}

/// One step with the `S`-stage pair.
struct Class<'a, const S: usize, const N: usize, const R: usize, Sys: System<N, R>> {
    spark: &'a Spark,
    t: &'a Lobatto<S>,
    sys: &'a Sys,
    h: f64,
}

/// The driver's stages: ζ_j with A, V_d and their derivatives there, and the trackers that
/// evaluated them (the step's end is a rotation away from ζ_s).
struct Driver<const S: usize, const N: usize, const R: usize> {
    zeta: [f64; S],
    terms: [DriverTerms<N, R>; S],
    trackers: [AngleTracker; S],
    iterations: u32,
}

impl<const S: usize, const N: usize, const R: usize, Sys: System<N, R>> Class<'_, S, N, R, Sys> {
    fn step(
        &self,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        kappa: &Vector<N>,
    ) -> Result<(), StepFailure> {
        let (sys, t, h) = (self.sys, self.t, self.h);
        let start = mem.forces(&General(sys), &st.q);
        let mut driver = self.driver(st, &start)?;
        let iterations = driver.iterations;
        let g0 = start.gradient;
        let terms = &driver.terms;
        let (kick, v) = WORK
            .with(|cell| {
                let (scratch, responses) = &mut *cell.borrow_mut();
                responses.prepare(t, h, kappa).ok_or(StepFailure::Singular)?;
                let z = self.multipliers(scratch, st, &g0, terms, responses)?;
                Ok(self.motion(st, &g0, terms, responses, &z))
            })
            .or_else(|e| counted(iterations, Err(e)))?;
        // q₁ = Q_s = q₀ + h Σ b_j V_j; q̂̇₁ = q̇₀ + Σ_j b_j k_j with k_s = −h ∇V(Q_s), exact for
        // the quadratic U.
        let mut dq = Vector::<N>::zeros();
        let mut v_hat = st.v;
        for j in 0..S {
            dq += (h * t.b[j]) * v[j];
            if j + 1 < S {
                v_hat += t.b[j] * kick[j];
            }
        }
        let mut end_gradient = sys.passenger_gradient(&(st.q + dq));
        end_gradient[N - 1] = terms[S - 1].potential_d1;
        v_hat -= (h * t.b[S - 1]) * end_gradient;
        if !v_hat.iter().chain(dq.iter()).all(|x| x.is_finite()) {
            return counted(iterations, Err(StepFailure::NonFinite));
        }
        st.advance_to(dq, v_hat);
        // The end condition: q̇₁ projected onto A(ζ₁) q̇ = 0, at ζ₁ as the state holds it (ζ_s
        // to round-off: a rotation of ζ_s's sine and cosine, where ζ is an angle).
        let zeta1 = st.q[N - 1];
        let end = if zeta1 == driver.zeta[S - 1] {
            driver.terms[S - 1]
        } else {
            driver.trackers[S - 1].terms(sys, zeta1)
        };
        let a = end.constraint;
        let Some(mu) = Lu::new(a * a.transpose()).map(|lu| lu.solve(&(a * v_hat))) else {
            return counted(iterations, Err(StepFailure::Singular));
        };
        st.v = v_hat - constraint_force(&a, &mu);
        // λ₁: the continuous multiplier at the new state (the next step's guess), else
        // h b_s Λ_s = −μ, as on the general step.
        let gradient = end.gradient(sys, &st.q);
        st.lambda = end.continuous_multiplier(&gradient, &st.v).unwrap_or(-mu / (h * t.b[S - 1]));
        mem.remember(&st.q, Forces { gradient, constraint: a });
        counted(iterations, Ok(()))
    }

    /// The driver's stages: ζ_i = ζ₀ + h c_i ζ̇₀ − h² Σ_{j<s} (aā)_ij V_d'(ζ_j), by Newton in
    /// ζ_2 … ζ_{s−1} (one iteration where V_d is quadratic: the equations are then affine), then
    /// ζ_s explicitly; the terms are those at the solution.
    fn driver(&self, st: &State<N, R>, start: &Forces<N, R>) -> Result<Driver<S, N, R>, StepFailure> {
        let (sys, t, h) = (self.sys, self.t, self.h);
        let (z0, w0, d1_0) = (st.q[N - 1], st.v[N - 1], start.gradient[N - 1]);
        let first = DriverTerms {
            constraint: start.constraint,
            constraint_d: Matrix::zeros(),
            potential: 0.0,
            potential_d1: d1_0,
            potential_d2: 0.0,
        };
        let mut out = Driver {
            // The guess: Taylor to second order.
            zeta: std::array::from_fn(|i| z0 + h * t.c[i] * (w0 - 0.5 * h * t.c[i] * d1_0)),
            terms: [first; S],
            trackers: [AngleTracker::new(); S],
            iterations: 0,
        };
        out.zeta[0] = z0;
        self.driver_newton(&mut out, (z0, w0))?;
        let hh = h * h;
        let mut last = z0 + h * t.c[S - 1] * w0;
        for i in 1..S - 1 {
            out.terms[i] = out.trackers[i].terms(sys, out.zeta[i]);
        }
        for j in 0..S - 1 {
            last -= hh * t.aa[S - 1][j] * out.terms[j].potential_d1;
        }
        out.zeta[S - 1] = last;
        out.terms[S - 1] = out.trackers[S - 1].terms(sys, last);
        Ok(out)
    }

    /// Newton on the driver's stages ζ_2 … ζ_{s−1} from the guess in `out` (none for s = 2,
    /// where ζ_2 is explicit), from ζ₀ and ζ̇₀; `out.terms` holds stage 1's V_d'.
    fn driver_newton(&self, out: &mut Driver<S, N, R>, (z0, w0): (f64, f64)) -> Result<(), StepFailure> {
        let (sys, t, h, cfg) = (self.sys, self.t, self.h, &self.spark.newton);
        let d = S - 2;
        if d == 0 {
            return Ok(());
        }
        let hh = h * h;
        let mut previous = f64::INFINITY;
        loop {
            out.iterations += 1;
            for i in 1..S - 1 {
                out.terms[i] = out.trackers[i].terms(sys, out.zeta[i]);
            }
            let (mut jac, mut swaps, mut e) = ([0.0; 9], [0usize; 3], [0.0; 3]);
            for i in 1..S - 1 {
                let mut r = out.zeta[i] - z0 - h * t.c[i] * w0;
                for j in 0..S - 1 {
                    let weight = hh * t.aa[i][j];
                    r += weight * out.terms[j].potential_d1;
                    if j >= 1 {
                        let identity = f64::from(u8::from(i == j));
                        jac[(i - 1) * d + j - 1] = identity + weight * out.terms[j].potential_d2;
                    }
                }
                e[i - 1] = r;
            }
            if lu_in_place(&mut jac[..d * d], d, &mut swaps[..d]).is_none() {
                return counted(out.iterations, Err(StepFailure::Singular));
            }
            lu_solve_in_place(&jac[..d * d], d, &swaps[..d], &mut e[..d]);
            let (mut increment, mut size) = (0.0f64, 0.0f64);
            for i in 1..S - 1 {
                out.zeta[i] -= e[i - 1];
                increment = increment.max(e[i - 1].abs());
                size = size.max(out.zeta[i].abs());
            }
            if !increment.is_finite() {
                return counted(out.iterations, Err(StepFailure::NonFinite));
            }
            // One iteration solves the affine equations of a quadratic V_d.
            let left = increment * increment / if previous.is_finite() { previous } else { 1.0 };
            if sys.quadratic_driver() || cfg.converged(increment, (left, increment), previous, 1.0 + size) {
                return Ok(());
            }
            if out.iterations >= cfg.max_iter {
                let diverged = StepFailure::NewtonDiverged { iterations: out.iterations, increment };
                return counted(out.iterations, Err(diverged));
            }
            previous = increment;
        }
    }

    /// The stages' kicks k_j (j < s) and velocities V_l for multipliers Z, through the
    /// responses of K's entries; `g0` is ∇V(q₀), whose driver component no kick takes (a
    /// kick's is its stage's own, −h V_d'(ζ_m)).
    fn motion(
        &self,
        st: &State<N, R>,
        g0: &Vector<N>,
        terms: &[DriverTerms<N, R>; S],
        responses: &Responses,
        z: &[Vector<R>; S],
    ) -> ([Vector<N>; S], [Vector<N>; S]) {
        let (t, h) = (self.t, self.h);
        let raw: [Vector<N>; S] = std::array::from_fn(|m| {
            let mut u = constraint_force(&terms[m].constraint, &z[m]) - h * g0;
            u[N - 1] = -h * terms[m].potential_d1;
            u
        });
        let mut kick = raw;
        kick[S - 1] = Vector::zeros();
        for r in 0..N - 1 {
            let g = &responses.groups()[responses.group(r)];
            if g.kappa != 0.0 {
                for j in 1..S - 1 {
                    let mut k = -g.psi[j] * st.v[r];
                    for m in 0..S - 1 {
                        k += g.phi[j][m] * raw[m][r];
                    }
                    kick[j][r] = k;
                }
            }
        }
        let v = std::array::from_fn(|l| {
            let mut v = st.v;
            for j in 0..S - 1 {
                v += t.abar[l][j] * kick[j];
            }
            v
        });
        (kick, v)
    }

    /// The multipliers: the constraints G_k = Σ_l a_kl A(ζ_l) V_l (k = 2 … s) are affine in Z,
    /// with blocks ∂G_k/∂Z_m = Σ_l a_kl A(ζ_l) diag(Ω_lm) A(ζ_m)ᵀ (Ω by each coordinate's
    /// response); one solve of (s − 1)R unknowns.
    fn multipliers(
        &self,
        scratch: &mut Scratch,
        st: &State<N, R>,
        g0: &Vector<N>,
        terms: &[DriverTerms<N, R>; S],
        responses: &Responses,
    ) -> Result<[Vector<R>; S], StepFailure> {
        let t = self.t;
        let d = (S - 1) * R;
        let (jac, swaps, rhs) = scratch.sized(d);
        let (_, v) = self.motion(st, g0, terms, responses, &[Vector::zeros(); S]);
        for k in 1..S {
            let mut g = Vector::<R>::zeros();
            for l in 0..S {
                g += t.a[k][l] * (terms[l].constraint * v[l]);
            }
            rhs[(k - 1) * R..k * R].copy_from_slice((-g).as_slice());
        }
        jac.fill(0.0);
        for (index, g) in responses.groups().iter().enumerate() {
            self.add_block(jac, d, terms, g, |r| r + 1 < N && responses.group(r) == index);
        }
        if lu_in_place(jac, d, swaps).is_none() {
            return Err(StepFailure::Singular);
        }
        lu_solve_in_place(jac, d, swaps, rhs);
        let z = std::array::from_fn(|m| {
            if m + 1 < S { Vector::<R>::from_column_slice(&rhs[m * R..(m + 1) * R]) } else { Vector::zeros() }
        });
        Ok(z)
    }

    /// Adds to the multipliers' matrix one group of coordinates' part (those `in_group`, of
    /// response `g`): block (k, m) gains Σ_l a_kl Ω_lm A(ζ_l) P A(ζ_m)ᵀ, P the projection on them.
    fn add_block(
        &self,
        jac: &mut [f64],
        d: usize,
        terms: &[DriverTerms<N, R>; S],
        g: &Response,
        in_group: impl Fn(usize) -> bool,
    ) {
        let masked: [Matrix<R, N>; S] = std::array::from_fn(|l| {
            let mut a = terms[l].constraint;
            for r in 0..N {
                if !in_group(r) {
                    a.column_mut(r).fill(0.0);
                }
            }
            a
        });
        for m in 0..S - 1 {
            let gram: [Matrix<R, R>; S] = std::array::from_fn(|l| masked[l] * terms[m].constraint.transpose());
            for k in 1..S {
                let mut block = Matrix::<R, R>::zeros();
                for l in 0..S {
                    block += g.weight[k][m][l] * gram[l];
                }
                for row in 0..R {
                    let line = ((k - 1) * R + row) * d + m * R;
                    for col in 0..R {
                        jac[line + col] += block[(row, col)];
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::systems::{AnharmonicCvt, Cvt, CvtPendulum, KnifeEdge, RollingDisk};

    /// The class step runs where U is quadratic with a diagonal Hessian (so the tests that
    /// compare it with the general step compare two solves), and not on the quartic spring.
    #[test]
    fn the_class_step_runs_where_u_is_quadratic_and_diagonal() {
        let q3 = Vector::<3>::new(0.3, -0.2, 1.1);
        assert_eq!(diagonal_hessian(&KnifeEdge { epsilon: 0.1 }, &q3), Some(Vector::<3>::zeros()));
        let spring = Some(Vector::<3>::new(1.0, 1.0, 0.0));
        assert_eq!(diagonal_hessian(&CvtPendulum { epsilon: 0.5 }, &q3), spring);
        assert_eq!(diagonal_hessian(&Cvt, &q3), spring);
        assert!(diagonal_hessian(&RollingDisk, &Vector::<4>::zeros()).is_some());
        assert_eq!(diagonal_hessian(&AnharmonicCvt { epsilon: 0.0, kappa: 1.0 }, &q3), None);
    }
}
