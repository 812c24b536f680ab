//! The latitude integral of `docs/model.md` §5 (`cvt`, `cvt_pendulum`): a first integral with no
//! closed formula, visible only at the driver's returns to a section.
//!
//! The reduced passenger state `u = (x₁, x₂, v)` obeys `u̇ = M(ζ) u` with `M ∈ so(3)`. Over one
//! driver period its flow is a rotation whose axis `a` is computed once per scene by
//! [`LatitudeAxis::compute`]: the driver and the 3×3 fundamental matrix are solved together
//! with Dop853 (ode_solvers) at tolerance 1e-13, the return to the section located by the
//! secant method on restarted solves. A numerical run then reports `ℓ = a·u/|u|` at each
//! section crossing, with `u` interpolated linearly between the two bracketing steps
//! ([`LatitudeTracker`]).

use crate::model::system::System;
use crate::{InputError, Vector};
use nalgebra::{Matrix3, SVector, Vector3};
use ode_solvers::dop_shared::OutputType;
use ode_solvers::dop853::Dop853;

type Y = SVector<f64, 11>;

/// The reduced passenger state `u = (x₁, x₂, v)` with `v = k(ζ)·ẋ` (`docs/model.md` §5).
#[inline]
fn reduced_passenger<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    q: &Vector<N>,
    v: &Vector<N>,
) -> Vector3<f64> {
    Vector3::new(q[0], q[1], sys.kernel(q[N - 1]).dot(v))
}

/// The section `ζ = ζ(0) + 2πm` (m = 0 only for a non-periodic driver), crossed in the
/// direction of `ζ̇(0)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// `ζ(0)`.
    pub zeta0: f64,
    /// Sign of `ζ̇(0)`.
    pub direction: f64,
    /// Whether `V_d` is 2π-periodic, so that `ζ(0) + 2πm` are returns too.
    pub periodic: bool,
}

impl Section {
    /// Where `ζ` is along the section's sheets: sheet `m` spans `[m, m + 1)` (for a
    /// non-periodic driver, `[0, ∞)` is sheet 0 and `(−∞, 0)` sheet −1).
    #[inline]
    fn position(&self, zeta: f64) -> f64 {
        let s = self.direction * (zeta - self.zeta0);
        if self.periodic { s / std::f64::consts::TAU } else { s }
    }

    /// Which sheet of the section `ζ` has passed: the index grows by one at each crossing.
    #[inline]
    pub fn index(&self, zeta: f64) -> i64 {
        let p = self.position(zeta);
        if self.periodic {
            p.floor() as i64
        } else if p < 0.0 {
            -1
        } else {
            0
        }
    }

    /// The positions `[lo, hi)` of sheet `index`.
    #[inline]
    fn sheet(&self, index: i64) -> (f64, f64) {
        match (self.periodic, index) {
            (true, m) => (m as f64, (m + 1) as f64),
            (false, 0) => (0.0, f64::INFINITY),
            (false, _) => (f64::NEG_INFINITY, 0.0),
        }
    }

    /// The ζ of sheet `index`.
    #[inline]
    pub fn zeta(&self, index: i64) -> f64 {
        if self.periodic {
            self.zeta0 + self.direction * std::f64::consts::TAU * index as f64
        } else {
            self.zeta0
        }
    }
}

/// The monodromy axis of a scene, and what it was computed from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatitudeAxis {
    /// Unit axis `a`, signed so that `a·u(0) ≥ 0`.
    pub axis: Vector3<f64>,
    /// The driver's period (time from the section back to it).
    pub period: f64,
    /// The section.
    pub section: Section,
    /// The monodromy rotation itself.
    pub monodromy: Matrix3<f64>,
    /// `ℓ(0)`.
    pub latitude0: f64,
}

/// Solver tolerance of the monodromy solve.
const TOL: f64 = 1e-13;
/// Longest time searched for the driver's return.
const HORIZON: f64 = 1e4;

// N and R only tie the impl below to S's sizes.
struct Ode<'a, S, const N: usize, const R: usize> {
    sys: &'a S,
    section: Section,
    last_index: i64,
    stop_at_crossing: bool,
}

impl<S: System<N, R>, const N: usize, const R: usize> ode_solvers::System<f64, Y>
    for Ode<'_, S, N, R>
{
    fn system(&self, _t: f64, y: &Y, dy: &mut Y) {
        let k = self.sys.kernel(y[0]);
        dy[0] = y[1];
        dy[1] = -self.sys.driver_potential_d1(y[0]);
        // Φ' = M Φ, column by column; M = [[0,0,k₁],[0,0,k₂],[−k₁,−k₂,0]].
        for c in 0..3 {
            let (p1, p2, p3) = (y[2 + 3 * c], y[3 + 3 * c], y[4 + 3 * c]);
            dy[2 + 3 * c] = k[0] * p3;
            dy[3 + 3 * c] = k[1] * p3;
            dy[4 + 3 * c] = -k[0] * p1 - k[1] * p2;
        }
    }
    fn solout(&mut self, _t: f64, y: &Y, _dy: &Y) -> bool {
        let index = self.section.index(y[0]);
        let crossed = index > self.last_index;
        self.last_index = index;
        self.stop_at_crossing && crossed
    }
}

fn solve<S: System<N, R>, const N: usize, const R: usize>(
    ode: Ode<'_, S, N, R>,
    t0: f64,
    t1: f64,
    y0: Y,
) -> Result<(Vec<f64>, Vec<Y>), String> {
    let mut solver = Dop853::new(ode, t0, t1, 0.0, y0, TOL, TOL);
    solver.set_output(OutputType::Sparse);
    solver.integrate().map_err(|e| format!("monodromy solve failed: {e}"))?;
    let (t, y) = solver.results().get();
    Ok((t.clone(), y.clone()))
}

impl LatitudeAxis {
    /// Computes the axis for the scene starting at `(q, v)`.
    pub fn compute<S: System<N, R>, const N: usize, const R: usize>(
        sys: &S,
        q: &Vector<N>,
        v: &Vector<N>,
    ) -> Result<Self, InputError> {
        let undefined = |reason: String| InputError::LatitudeUndefined { reason };
        let (zeta0, zdot0) = (q[N - 1], v[N - 1]);
        if zdot0 == 0.0 {
            return Err(undefined(
                "the driver starts at rest (ζ̇(0) = 0), so it has no section".into(),
            ));
        }
        let u0 = reduced_passenger(sys, q, v);
        if u0.norm() == 0.0 {
            return Err(undefined("the passenger starts at rest at the origin (u(0) = 0)".into()));
        }
        let section =
            Section { zeta0, direction: zdot0.signum(), periodic: sys.driver_is_periodic() };
        let mut y0 = Y::zeros();
        y0[0] = zeta0;
        y0[1] = zdot0;
        for c in 0..3 {
            y0[2 + 4 * c] = 1.0;
        }
        let ode = |stop| Ode::<S, N, R> { sys, section, last_index: 0, stop_at_crossing: stop };
        let (ts, ys) = solve(ode(true), 0.0, HORIZON, y0).map_err(undefined)?;
        let Some(n) = (1..ys.len())
            .find(|&i| section.index(ys[i][0]) > section.index(ys[i - 1][0]))
            .map(|i| i + 1)
        else {
            return Err(undefined(format!(
                "the driver does not return to its section within t = {HORIZON}"
            )));
        };
        let target = section.zeta(section.index(ys[n - 1][0]));
        let (ta, ya) = (ts[n - 2], ys[n - 2]);
        // Secant on τ ↦ ζ(ta + τ) − target, each evaluation a fresh high-accuracy solve.
        let at = |tau: f64| -> Result<Y, InputError> {
            if tau == 0.0 {
                return Ok(ya);
            }
            let (_, y) = solve(ode(false), ta, ta + tau, ya).map_err(undefined)?;
            y.last().copied().ok_or_else(|| undefined("empty monodromy solve".into()))
        };
        let (mut t_lo, mut f_lo) = (0.0, ya[0] - target);
        let (mut t_hi, mut f_hi) = (ts[n - 1] - ta, ys[n - 1][0] - target);
        let mut y_cross = ys[n - 1];
        let mut tau = t_hi;
        for _ in 0..60 {
            if f_hi == f_lo {
                break;
            }
            let next = t_hi - f_hi * (t_hi - t_lo) / (f_hi - f_lo);
            let y = at(next)?;
            (t_lo, f_lo, t_hi, f_hi) = (t_hi, f_hi, next, y[0] - target);
            y_cross = y;
            tau = next;
            if (t_hi - t_lo).abs() <= 1e-15 * (ta + tau) || f_hi == 0.0 {
                break;
            }
        }
        let monodromy = Matrix3::from_iterator(y_cross.iter().skip(2).copied());
        let svd = (monodromy - Matrix3::identity()).svd(false, true);
        let v_t = svd.v_t.ok_or_else(|| undefined("SVD of the monodromy failed".into()))?;
        let smallest = svd.singular_values.imin();
        let mut axis: Vector3<f64> = v_t.row(smallest).transpose();
        if axis.dot(&u0) < 0.0 {
            axis = -axis;
        }
        let latitude0 = axis.dot(&u0) / u0.norm();
        Ok(Self { axis, period: ta + tau, section, monodromy, latitude0 })
    }

    /// The number of section crossings of the exact driver in `(0, t]`.
    pub fn crossings_until(&self, t: f64) -> u64 {
        (t / self.period).floor().max(0.0) as u64
    }
}

/// Watches a run's steps and reports `|ℓ − ℓ(0)|` at each section crossing. It keeps the
/// previous state rather than its reduced passenger: `k(ζ)` (a sine and a square root) is
/// then evaluated only at the two steps that bracket a crossing, not at every step.
#[derive(Debug, Clone)]
pub struct LatitudeTracker<const N: usize> {
    axis: LatitudeAxis,
    index: i64,
    /// The sheet `index` spans, so that a step that stays on it (nearly all) needs no floor.
    sheet: (f64, f64),
    prev_t: f64,
    prev_q: Vector<N>,
    prev_v: Vector<N>,
}

impl<const N: usize> LatitudeTracker<N> {
    /// Starts at the initial state.
    pub fn new(axis: LatitudeAxis, q: &Vector<N>, v: &Vector<N>) -> Self {
        let index = axis.section.index(q[N - 1]);
        let sheet = axis.section.sheet(index);
        Self { axis, index, sheet, prev_t: 0.0, prev_q: *q, prev_v: *v }
    }

    /// The exact driver's period (from the section back to it).
    pub fn period(&self) -> f64 {
        self.axis.period
    }

    /// Takes the state after a step; returns `(t, |ℓ − ℓ(0)|)` at a crossing inside the step
    /// (NaN where `u = 0`: the latitude is undefined there).
    #[inline]
    pub fn observe<S: System<N, R>, const R: usize>(
        &mut self,
        sys: &S,
        t: f64,
        q: &Vector<N>,
        v: &Vector<N>,
    ) -> Option<(f64, f64)> {
        let zeta = q[N - 1];
        let p = self.axis.section.position(zeta);
        let out = if self.sheet.0 <= p && p < self.sheet.1 {
            None
        } else {
            self.changed_sheet(sys, t, q, v)
        };
        self.prev_t = t;
        self.prev_q = *q;
        self.prev_v = *v;
        out
    }

    /// The rare step that leaves its sheet: the new sheet, and the latitude where the step
    /// crossed the section forwards. Kept out of line so that `observe` inlines.
    #[inline(never)]
    fn changed_sheet<S: System<N, R>, const R: usize>(
        &mut self,
        sys: &S,
        t: f64,
        q: &Vector<N>,
        v: &Vector<N>,
    ) -> Option<(f64, f64)> {
        let zeta = q[N - 1];
        let index = self.axis.section.index(zeta);
        self.sheet = self.axis.section.sheet(index);
        let mut out = None;
        if index > self.index {
            let (prev_zeta, target) = (self.prev_q[N - 1], self.axis.section.zeta(index));
            let theta = ((target - prev_zeta) / (zeta - prev_zeta)).clamp(0.0, 1.0);
            let prev_u = reduced_passenger(sys, &self.prev_q, &self.prev_v);
            let uc = prev_u + theta * (reduced_passenger(sys, q, v) - prev_u);
            let latitude = self.axis.axis.dot(&uc) / uc.norm();
            out = Some((
                self.prev_t + theta * (t - self.prev_t),
                (latitude - self.axis.latitude0).abs(),
            ));
        }
        self.index = index;
        out
    }
}
