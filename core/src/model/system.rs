//! The [`System`] trait: a nonholonomically coupled system of `docs/model.md` §1, the paper's
//! class within nhlab's general class ([`Mechanical`]); and what describes a built-in system
//! ([`SystemInfo`]).
//!
//! Configuration `q = (x, ζ)` with the driver `ζ` last, unit masses, potential
//! `V(q) = U(x) + V_d(ζ)` and constraints `A(ζ) q̇ = 0` whose last column is zero. A system
//! gives its pieces with exact derivatives (Newton needs them); the whole potential, its
//! gradient and Hessian, the energies and the continuous multiplier are derived here once.

use crate::model::custom::{GeneralSpec, Invariants};
use crate::{InputError, Integral, Matrix, Vector};

/// One tunable parameter of a system or a method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamSpec {
    /// Name, as in the API (`epsilon`, `alpha`).
    pub name: &'static str,
    /// Value when not given.
    pub default: f64,
    /// Lower bound.
    pub min: f64,
    /// Upper bound.
    pub max: f64,
    /// Whether `min` itself is excluded.
    pub min_open: bool,
    /// Whether `max` itself is excluded.
    pub max_open: bool,
    /// One-line meaning.
    pub description: &'static str,
}

impl ParamSpec {
    /// Whether `value` is allowed.
    pub fn contains(&self, value: f64) -> bool {
        let above = if self.min_open { value > self.min } else { value >= self.min };
        let below = if self.max_open { value < self.max } else { value <= self.max };
        above && below
    }

    /// The allowed range as an interval, e.g. `(-1, 1)`.
    pub fn range(&self) -> String {
        format!(
            "{}{}, {}{}",
            if self.min_open { '(' } else { '[' },
            self.min,
            self.max,
            if self.max_open { ')' } else { ']' }
        )
    }
}

/// A named initial state with its step and horizon (the paper's experiments among them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Preset {
    /// Id, as in the API (`paper`, `rotating-perturbed`).
    pub id: &'static str,
    /// Human label.
    pub label: &'static str,
    /// Parameter values (the rest take their defaults).
    pub params: &'static [(&'static str, f64)],
    /// Initial configuration.
    pub q: &'static [f64],
    /// Initial velocity (consistent with the constraints).
    pub v: &'static [f64],
    /// Step size.
    pub step: f64,
    /// Final time.
    pub t_end: f64,
}

/// What a system is, for listings and validation.
#[derive(Debug, Clone, Copy)]
pub struct SystemInfo {
    /// Id, as in the API.
    pub id: &'static str,
    /// Human name.
    pub name: &'static str,
    /// One or two sentences.
    pub description: &'static str,
    /// Where it comes from: the papers (or software) whose test problem it is.
    pub source: &'static str,
    /// Parameters, in the order [`BuiltIn::new`] takes them.
    pub params: &'static [ParamSpec],
    /// The integrals (and the constraint diagnostic) it has.
    pub integrals: &'static [Integral],
    /// Presets; the first is the default.
    pub presets: &'static [Preset],
    /// The system written as formulas (`docs/model.md` §10), its parameters those above.
    pub form: Form,
    /// The exact solution, where one is known: work–precision measures against it instead
    /// of a numerical reference.
    pub exact: Option<Exact>,
}

/// The exact solution of a system from `(q₀, q̇₀)` at time t, for parameter values (in the
/// order of `SystemInfo::params`): `(q(t), q̇(t))`.
pub type Exact = fn(params: &[f64], q0: &[f64], v0: &[f64], t: f64) -> (Vec<f64>, Vec<f64>);

/// How a built-in system is written as formulas.
#[derive(Debug, Clone, Copy)]
pub enum Form {
    /// A system of the paper's class, in the class's own form (its general form follows:
    /// `GeneralSpec::of_coupled`).
    Coupled(FormulaForm),
    /// A system in the general form, for parameter values (in the order of
    /// `SystemInfo::params`): a built-in given as formulas is compiled from it, and a
    /// parameter may shape it (the chaotic oscillator's n).
    General(fn(&[f64]) -> Result<GeneralSpec, InputError>),
}

/// A built-in system written as formulas, as a user would give it: the same numbers to
/// round-off (`tests/it/formula_systems.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FormulaForm {
    /// Passenger coordinate names.
    pub passenger: &'static [&'static str],
    /// Driver name.
    pub driver: &'static str,
    /// `U(x)`.
    pub passenger_potential: &'static str,
    /// `V_d(ζ)`.
    pub driver_potential: &'static str,
    /// The passenger columns of `A(ζ)`, row by row.
    pub constraints: &'static [&'static [&'static str]],
}

impl SystemInfo {
    /// The parameter values of `preset`, in the order [`BuiltIn::new`] takes them: the preset's
    /// own, the rest at their defaults. (A preset names only parameters of its system: a test
    /// in `catalogue::registry` checks every one.) Requests are resolved with checks by
    /// `Scene::resolve`.
    pub fn preset_params(&self, preset: &Preset) -> Vec<f64> {
        self.params
            .iter()
            .map(|spec| {
                preset
                    .params
                    .iter()
                    .find(|(name, _)| *name == spec.name)
                    .map_or(spec.default, |p| p.1)
            })
            .collect()
    }
}

/// Everything in a system that depends on the driver ζ, at one ζ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DriverTerms<const N: usize, const R: usize> {
    /// `A(ζ)`.
    pub constraint: Matrix<R, N>,
    /// `dA/dζ`.
    pub constraint_d: Matrix<R, N>,
    /// `V_d(ζ)`.
    pub potential: f64,
    /// `V_d'(ζ)`.
    pub potential_d1: f64,
    /// `V_d''(ζ)`.
    pub potential_d2: f64,
}

impl<const N: usize, const R: usize> DriverTerms<N, R> {
    /// The terms from the system's functions, one by one.
    #[inline]
    fn evaluated<S: System<N, R>>(sys: &S, zeta: f64) -> Self {
        Self {
            constraint: sys.constraint(zeta),
            constraint_d: sys.constraint_d(zeta),
            potential: sys.driver_potential(zeta),
            potential_d1: sys.driver_potential_d1(zeta),
            potential_d2: sys.driver_potential_d2(zeta),
        }
    }
    /// `∇V(q)`, with these terms taken at q's ζ.
    #[inline]
    pub fn gradient<S: System<N, R>>(&self, sys: &S, q: &Vector<N>) -> Vector<N> {
        let mut g = sys.passenger_gradient(q);
        g[N - 1] = self.potential_d1;
        g
    }
    /// The continuous multiplier (`docs/model.md` §1, `A Aᵀ λ = A ∇V − Ȧ q̇`) at q, given
    /// `∇V(q)`, with these terms taken at q's ζ; `None` when `A Aᵀ` is singular.
    #[inline]
    pub fn continuous_multiplier(&self, gradient: &Vector<N>, v: &Vector<N>) -> Option<Vector<R>> {
        let (a, a_dot) = (&self.constraint, self.constraint_d * v[N - 1]);
        let rhs = a * gradient - a_dot * v;
        crate::linalg::solve(&(a * a.transpose()), &rhs)
    }
    /// `∇²V(q)`, with these terms taken at q's ζ.
    #[inline]
    pub fn hessian<S: System<N, R>>(&self, sys: &S, q: &Vector<N>) -> Matrix<N, N> {
        let mut h = sys.passenger_hessian(q);
        h[(N - 1, N - 1)] = self.potential_d2;
        h
    }
}

/// The constraint force `Aᵀλ`. Its driver component is zero (A has no driver column), and is
/// written as such rather than computed as `0·λ`: then the driver's update does not depend on
/// λ, and the passenger's multiplier solve stays off the driver's chain of dependencies from
/// step to step (the same numbers, unless λ is not finite, which the steps report anyway).
#[inline]
pub fn constraint_force<const N: usize, const R: usize>(
    a: &Matrix<R, N>,
    lambda: &Vector<R>,
) -> Vector<N> {
    let mut f = a.transpose() * lambda;
    f[N - 1] = 0.0;
    f
}

/// A system compiled into nhlab: its description, and its construction from parameter
/// values. (A system given as formulas is a [`System`] too, built from its compiled formulas:
/// `model::custom`.)
pub trait BuiltIn<const N: usize, const R: usize>: System<N, R> {
    /// Its description.
    fn info() -> &'static SystemInfo;
    /// Builds it from parameter values given in the order of `info().params`, already
    /// checked against their ranges.
    fn new(params: &[f64]) -> Self;
}

/// A nonholonomically coupled system with `N` coordinates and `R` constraints.
pub trait System<const N: usize, const R: usize>: Sized + Send + Sync + 'static {
    /// Passenger potential `U(x)` (the driver's slot of `q` is ignored).
    fn passenger_potential(&self, q: &Vector<N>) -> f64;
    /// `∇U`, with a zero driver component.
    fn passenger_gradient(&self, q: &Vector<N>) -> Vector<N>;
    /// `∇²U`, with a zero driver row and column.
    fn passenger_hessian(&self, q: &Vector<N>) -> Matrix<N, N>;
    /// Driver potential `V_d(ζ)`.
    fn driver_potential(&self, zeta: f64) -> f64;
    /// `V_d'(ζ)`.
    fn driver_potential_d1(&self, zeta: f64) -> f64;
    /// `V_d''(ζ)`.
    fn driver_potential_d2(&self, zeta: f64) -> f64;
    /// `A(ζ)`, R×N, last column zero.
    fn constraint(&self, zeta: f64) -> Matrix<R, N>;
    /// `dA/dζ`.
    fn constraint_d(&self, zeta: f64) -> Matrix<R, N>;
    /// Unit vector spanning `ker A_x(ζ)`, signed as in `docs/model.md` §2, zero driver component.
    fn kernel(&self, zeta: f64) -> Vector<N>;
    /// Whether `U` is quadratic in x (`∇U` affine, `∇²U` constant), as for every test system
    /// of `docs/model.md` §1. The coupled fast paths of the implicit methods rely on it (with the
    /// driver solved alone, the passenger update is then one linear solve), and DD and DD-AVF
    /// skip what it makes zero in their discrete gradients. Checked in `tests/it/derivatives.rs`.
    /// A method of `&self` rather than a constant, as a system given as formulas knows it
    /// only once compiled; a built-in's answer is a constant the compiler folds.
    fn quadratic_passenger(&self) -> bool {
        false
    }
    /// Whether `V_d` is quadratic in ζ (`V_d'` affine, `V_d''` constant; zero counts). The
    /// driver's equation of DLA^α's coupled fast path is then affine, and one Newton step
    /// solves it exactly, without a second one to confirm it; with a quadratic U too, DD's and
    /// DD-AVF's discrete gradients are `∇V(q̄)` (up to DD's rounding term).
    fn quadratic_driver(&self) -> bool {
        false
    }
    /// Whether the passenger feels no potential (`U ≡ 0`). DD's step then reduces to one
    /// equation in the driver's speed (`methods::dd::reduced`). Checked in
    /// `tests/it/derivatives.rs`.
    fn free_passenger(&self) -> bool {
        false
    }
    /// Whether ζ is an angle: `A` and `V_d` are 2π-periodic in it (U never depends on ζ).
    /// The reference solve then keeps ζ near 0 by whole turns, which keeps its rounding small.
    fn zeta_is_angle(&self) -> bool {
        false
    }
    /// Whether `V_d` is 2π-periodic, so that a rotating driver returns to its section.
    fn driver_is_periodic(&self) -> bool {
        false
    }
    /// Whether `A_x(ζ)` has full rank for every ζ (and every parameter value allowed): then
    /// a run need not watch it. True for every built-in (`tests/it/derivatives.rs` samples
    /// it); a system given as formulas is watched.
    fn rank_is_constant(&self) -> bool {
        false
    }
    /// The invariants it declares (`docs/model.md` §4), compiled on its `(q, q̇)`: a system
    /// given as formulas carries those of its spec; a built-in compiled into nhlab has none.
    fn invariants(&self) -> Option<&Invariants> {
        None
    }

    /// [`DriverTerms`] at ζ: through [`System::driver_terms_trig`] where ζ is an angle (one
    /// `sin_cos`), from the functions above otherwise.
    #[inline]
    fn driver_terms(&self, zeta: f64) -> DriverTerms<N, R> {
        if self.zeta_is_angle() {
            let (s, c) = zeta.sin_cos();
            self.driver_terms_trig(zeta, s, c)
        } else {
            DriverTerms::evaluated(self, zeta)
        }
    }
    /// [`DriverTerms`] at ζ given `sin ζ` and `cos ζ`. A system whose ζ is an angle
    /// (`zeta_is_angle`) computes them from these, so that a Newton iteration can carry the
    /// sine and cosine from one iterate to the next by a small rotation instead of calling
    /// `sin_cos` (`AngleTracker`); the default evaluates the functions above and ignores them
    /// (so an angle system that writes those functions through `driver_terms` must implement
    /// this one, or they would call each other).
    #[inline]
    fn driver_terms_trig(&self, zeta: f64, sin: f64, cos: f64) -> DriverTerms<N, R> {
        let _ = (sin, cos);
        DriverTerms::evaluated(self, zeta)
    }

    /// Total potential `V = U + V_d`.
    #[inline]
    fn potential(&self, q: &Vector<N>) -> f64 {
        self.passenger_potential(q) + self.driver_potential(q[N - 1])
    }
    /// `∇V`.
    #[inline]
    fn gradient(&self, q: &Vector<N>) -> Vector<N> {
        let mut g = self.passenger_gradient(q);
        g[N - 1] = self.driver_potential_d1(q[N - 1]);
        g
    }
    /// `∇²V`.
    #[inline]
    fn hessian(&self, q: &Vector<N>) -> Matrix<N, N> {
        let mut h = self.passenger_hessian(q);
        h[(N - 1, N - 1)] = self.driver_potential_d2(q[N - 1]);
        h
    }
    /// Total energy `H = ½|q̇|² + V(q)`.
    #[inline]
    fn energy(&self, q: &Vector<N>, v: &Vector<N>) -> f64 {
        0.5 * v.norm_squared() + self.potential(q)
    }
    /// Passenger energy `E = ½|ẋ|² + U(x)`.
    #[inline]
    fn passenger_energy(&self, q: &Vector<N>, v: &Vector<N>) -> f64 {
        0.5 * (v.norm_squared() - v[N - 1] * v[N - 1]) + self.passenger_potential(q)
    }
    /// Driver energy `h = ½ζ̇² + V_d(ζ)`.
    #[inline]
    fn driver_energy(&self, q: &Vector<N>, v: &Vector<N>) -> f64 {
        0.5 * v[N - 1] * v[N - 1] + self.driver_potential(q[N - 1])
    }
    /// Constraint residual `|A(q) q̇|`.
    #[inline]
    fn constraint_residual(&self, q: &Vector<N>, v: &Vector<N>) -> f64 {
        (self.constraint(q[N - 1]) * v).norm()
    }
    /// The constrained ODE with the multiplier eliminated (`docs/model.md` §1): `q̈` and `λ` at
    /// `(q, q̇)`; `None` when `A Aᵀ` is singular.
    #[inline]
    fn acceleration(&self, q: &Vector<N>, v: &Vector<N>) -> Option<(Vector<N>, Vector<R>)> {
        let at_q = self.driver_terms(q[N - 1]);
        let g = at_q.gradient(self, q);
        let lambda = at_q.continuous_multiplier(&g, v)?;
        Some((constraint_force(&at_q.constraint, &lambda) - g, lambda))
    }
    /// The continuous multiplier of `docs/model.md` §1: `A Aᵀ λ = A ∇V − Ȧ q̇`.
    fn continuous_multiplier(&self, q: &Vector<N>, v: &Vector<N>) -> Option<Vector<R>> {
        let at_q = self.driver_terms(q[N - 1]);
        at_q.continuous_multiplier(&at_q.gradient(self, q), v)
    }
}
