//! [`SystemView`]: a system as code outside nhlab sees it inside a step, sizes erased:
//! vectors and matrices as slices (matrices row by row), each function of `docs/model.md`
//! §1 one call, for a system of the paper's class its pieces ([`ClassView`]), and the
//! integrals a run measures as functions of `(q, q̇)` besides H, by name (the energies E and h
//! of the paper's class, the invariants a system declares). Slices of the wrong length never
//! panic: missing entries read as NaN, extra ones are ignored (the caller checks shapes and
//! says so).

use crate::linalg;
use crate::model::custom::Invariants;
use crate::model::mechanical::{General, Mechanical};
use crate::model::system::System;
use crate::{Integral, MAX_INVARIANTS, Matrix, Vector};

/// A system of the general class, seen from outside (see the module's doc).
pub trait SystemView {
    /// `(N, R)`: coordinates and constraints.
    fn sizes(&self) -> (usize, usize);
    /// M, N×N.
    fn mass(&self, out: &mut [f64]);
    /// M⁻¹, N×N.
    fn mass_inverse(&self, out: &mut [f64]);
    /// `V(q)`.
    fn potential(&self, q: &[f64]) -> f64;
    /// `∇V(q)`, N.
    fn gradient(&self, q: &[f64], out: &mut [f64]);
    /// `∇²V(q)`, N×N.
    fn hessian(&self, q: &[f64], out: &mut [f64]);
    /// `A(q)`, R×N.
    fn constraint(&self, q: &[f64], out: &mut [f64]);
    /// `∂(A(q) u)/∂q`, R×N: column k is `(∂A/∂q_k) u`.
    fn constraint_jacobian(&self, q: &[f64], u: &[f64], out: &mut [f64]);
    /// `H(q, q̇) = ½ q̇ᵀM q̇ + V(q)`.
    fn energy(&self, q: &[f64], v: &[f64]) -> f64;
    /// The M-orthogonal projection of `v` onto `ker A(q)`, `v − M⁻¹Aᵀ(A M⁻¹Aᵀ)⁻¹A v`, into
    /// `out`; false when `A M⁻¹Aᵀ` is singular.
    fn project(&self, q: &[f64], v: &[f64], out: &mut [f64]) -> bool;
    /// The continuous multiplier λ at `(q, q̇)` (`docs/model.md` §1), R, into `out`; false
    /// when `A M⁻¹Aᵀ` is singular.
    fn multiplier(&self, q: &[f64], v: &[f64], out: &mut [f64]) -> bool;
    /// The paper's pieces, for a system of its class.
    fn class(&self) -> Option<&dyn ClassView>;
    /// The names of the integrals besides H that a run of the system measures as functions
    /// of `(q, q̇)`: for the paper's class `passenger_energy` and `driver_energy` (E and h),
    /// then the invariants the system declares (`docs/model.md` §4), in order.
    fn invariant_names(&self) -> Vec<&str>;
    /// Their values at `(q, q̇)`, in the order of [`invariant_names`](Self::invariant_names),
    /// into `out`.
    fn invariants(&self, q: &[f64], v: &[f64], out: &mut [f64]);
}

/// A system of the paper's class, seen from outside: `q = (x, ζ)` with ζ last,
/// `V = U(x) + V_d(ζ)`, `A(q) = A(ζ)` with a zero last column.
pub trait ClassView {
    /// `U(x)` (q given whole).
    fn passenger_potential(&self, q: &[f64]) -> f64;
    /// `∇U`, N (zero ζ component).
    fn passenger_gradient(&self, q: &[f64], out: &mut [f64]);
    /// `V_d(ζ)`, `V_d'(ζ)`, `V_d''(ζ)`.
    fn driver_potential(&self, zeta: f64) -> [f64; 3];
    /// `A(ζ)`, R×N.
    fn constraint_at(&self, zeta: f64, out: &mut [f64]);
    /// `dA/dζ`, R×N.
    fn constraint_d(&self, zeta: f64, out: &mut [f64]);
}

fn vector<const N: usize>(s: &[f64]) -> Vector<N> {
    Vector::from_fn(|i, _| s.get(i).copied().unwrap_or(f64::NAN))
}

fn write<const A: usize, const B: usize>(m: &Matrix<A, B>, out: &mut [f64]) {
    // Row by row, as numpy lays out a C-ordered array.
    for (slot, x) in out.iter_mut().zip((0..A).flat_map(|i| (0..B).map(move |j| m[(i, j)]))) {
        *slot = x;
    }
}

fn write_vector<const N: usize>(x: &Vector<N>, out: &mut [f64]) {
    out.iter_mut().zip(x.iter()).for_each(|(slot, x)| *slot = *x);
}

/// The names of the declared `invariants`.
fn declared(invariants: Option<&Invariants>) -> impl Iterator<Item = &str> {
    invariants.into_iter().flat_map(|i| i.names().iter().map(String::as_str))
}

/// The values of the declared `invariants` at `(q, q̇)`, into `out`.
fn write_declared<const N: usize>(
    invariants: Option<&Invariants>,
    q: &Vector<N>,
    v: &Vector<N>,
    out: &mut [f64],
) {
    let Some(invariants) = invariants else { return };
    let mut values = [f64::NAN; MAX_INVARIANTS];
    invariants.eval(q.as_slice(), v.as_slice(), &mut values);
    out.iter_mut().zip(&values[..invariants.names().len()]).for_each(|(slot, x)| *slot = *x);
}

/// Any system of the general class.
pub(super) struct Mechanics<'a, S, const N: usize, const R: usize>(pub &'a S);

/// A system of the paper's class: the general view of it, and its pieces.
pub(super) struct Class<'a, S, const N: usize, const R: usize>(pub &'a S);

impl<S: Mechanical<N, R>, const N: usize, const R: usize> SystemView
    for Mechanics<'_, S, N, R>
{
    fn sizes(&self) -> (usize, usize) {
        (N, R)
    }
    fn mass(&self, out: &mut [f64]) {
        write(&self.0.mass().matrix(), out);
    }
    fn mass_inverse(&self, out: &mut [f64]) {
        write(&self.0.mass().solve_columns(&Matrix::<N, N>::identity()), out);
    }
    fn potential(&self, q: &[f64]) -> f64 {
        self.0.potential(&vector(q))
    }
    fn gradient(&self, q: &[f64], out: &mut [f64]) {
        write_vector(&self.0.gradient(&vector(q)), out);
    }
    fn hessian(&self, q: &[f64], out: &mut [f64]) {
        write(&self.0.derivatives(&vector(q)).hessian, out);
    }
    fn constraint(&self, q: &[f64], out: &mut [f64]) {
        write(&self.0.constraint(&vector(q)), out);
    }
    fn constraint_jacobian(&self, q: &[f64], u: &[f64], out: &mut [f64]) {
        write(&self.0.derivatives(&vector(q)).constraint_jacobian(&vector(u)), out);
    }
    fn energy(&self, q: &[f64], v: &[f64]) -> f64 {
        self.0.energy(&vector(q), &vector(v))
    }
    fn project(&self, q: &[f64], v: &[f64], out: &mut [f64]) -> bool {
        let (a, v) = (self.0.constraint(&vector(q)), vector::<N>(v));
        let m_at = self.0.mass().solve_columns(&a.transpose());
        let Some(mu) = linalg::solve(&(a * m_at), &(a * v)) else { return false };
        write_vector(&(v - m_at * mu), out);
        true
    }
    fn multiplier(&self, q: &[f64], v: &[f64], out: &mut [f64]) -> bool {
        let lambda = self.0.continuous_multiplier(&vector(q), &vector(v));
        lambda.inspect(|l| write_vector(l, out)).is_some()
    }
    fn class(&self) -> Option<&dyn ClassView> {
        None
    }
    fn invariant_names(&self) -> Vec<&str> {
        declared(self.0.invariants()).collect()
    }
    fn invariants(&self, q: &[f64], v: &[f64], out: &mut [f64]) {
        write_declared(self.0.invariants(), &vector::<N>(q), &vector::<N>(v), out);
    }
}

impl<S: System<N, R>, const N: usize, const R: usize> SystemView for Class<'_, S, N, R> {
    fn sizes(&self) -> (usize, usize) {
        (N, R)
    }
    fn mass(&self, out: &mut [f64]) {
        Mechanics::<_, N, R>(&General(self.0)).mass(out);
    }
    fn mass_inverse(&self, out: &mut [f64]) {
        Mechanics::<_, N, R>(&General(self.0)).mass_inverse(out);
    }
    fn potential(&self, q: &[f64]) -> f64 {
        self.0.potential(&vector(q))
    }
    fn gradient(&self, q: &[f64], out: &mut [f64]) {
        write_vector(&self.0.gradient(&vector(q)), out);
    }
    fn hessian(&self, q: &[f64], out: &mut [f64]) {
        write(&self.0.hessian(&vector(q)), out);
    }
    fn constraint(&self, q: &[f64], out: &mut [f64]) {
        write(&self.0.constraint(vector::<N>(q)[N - 1]), out);
    }
    fn constraint_jacobian(&self, q: &[f64], u: &[f64], out: &mut [f64]) {
        Mechanics::<_, N, R>(&General(self.0)).constraint_jacobian(q, u, out);
    }
    fn energy(&self, q: &[f64], v: &[f64]) -> f64 {
        self.0.energy(&vector(q), &vector(v))
    }
    fn project(&self, q: &[f64], v: &[f64], out: &mut [f64]) -> bool {
        Mechanics::<_, N, R>(&General(self.0)).project(q, v, out)
    }
    fn multiplier(&self, q: &[f64], v: &[f64], out: &mut [f64]) -> bool {
        // The class's own, with which a run of a class system starts.
        let lambda = self.0.continuous_multiplier(&vector(q), &vector(v));
        lambda.inspect(|l| write_vector(l, out)).is_some()
    }
    fn class(&self) -> Option<&dyn ClassView> {
        Some(self)
    }
    fn invariant_names(&self) -> Vec<&str> {
        let energies = [Integral::PassengerEnergy.id(), Integral::DriverEnergy.id()];
        energies.into_iter().chain(declared(self.0.invariants())).collect()
    }
    fn invariants(&self, q: &[f64], v: &[f64], out: &mut [f64]) {
        let (q, v) = (vector::<N>(q), vector::<N>(v));
        let energies = [self.0.passenger_energy(&q, &v), self.0.driver_energy(&q, &v)];
        out.iter_mut().zip(energies).for_each(|(slot, x)| *slot = x);
        let rest = out.get_mut(energies.len()..).unwrap_or_default();
        write_declared(self.0.invariants(), &q, &v, rest);
    }
}

impl<S: System<N, R>, const N: usize, const R: usize> ClassView for Class<'_, S, N, R> {
    fn passenger_potential(&self, q: &[f64]) -> f64 {
        self.0.passenger_potential(&vector(q))
    }
    fn passenger_gradient(&self, q: &[f64], out: &mut [f64]) {
        write_vector(&self.0.passenger_gradient(&vector(q)), out);
    }
    fn driver_potential(&self, zeta: f64) -> [f64; 3] {
        let s = self.0;
        [s.driver_potential(zeta), s.driver_potential_d1(zeta), s.driver_potential_d2(zeta)]
    }
    fn constraint_at(&self, zeta: f64, out: &mut [f64]) {
        write(&self.0.constraint(zeta), out);
    }
    fn constraint_d(&self, zeta: f64, out: &mut [f64]) {
        write(&self.0.constraint_d(zeta), out);
    }
}
