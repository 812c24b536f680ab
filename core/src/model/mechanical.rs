//! [`Mechanical`]: nhlab's model, a mechanical system with linear velocity constraints
//! (`docs/model.md` §1): `q ∈ Rᴺ`, `L = ½ q̇ᵀM q̇ − V(q)`, `A(q) q̇ = 0` with R rows of full
//! rank, M constant, symmetric and positive definite.
//!
//! A system gives V with its gradient and Hessian, A with its partial derivatives, and M
//! (with its inverse) as a [`Mass`]; the energy, the continuous multiplier and the constrained
//! ODE with the multiplier eliminated are derived here once. The paper's class
//! ([`System`]) is the special case `M = I`, `V = U(x) + V_d(ζ)`, `A = [A_x(ζ) | 0]`; any
//! member of it is a `Mechanical` system through [`General`], which is how a method's general
//! step runs on it (the general path the class's faster steps are tested against).

use crate::linalg;
use crate::model::custom::Invariants;
use crate::model::system::{System, SystemInfo};
use crate::{Matrix, Vector};

/// The mass matrix M of a system: constant, symmetric, positive definite, with its inverse.
/// Kept by kind, so that the identity and a diagonal cost no matrix products.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mass<const N: usize> {
    /// `M = I`.
    Identity,
    /// `M = diag(m)`, every `mᵢ > 0`.
    Diagonal(Vector<N>),
    /// A full M with its inverse.
    Dense {
        /// M.
        matrix: Matrix<N, N>,
        /// M⁻¹.
        inverse: Matrix<N, N>,
    },
}

impl<const N: usize> Mass<N> {
    /// The mass of a full matrix M, checked symmetric positive definite first: the identity
    /// and diagonal matrices are recognised as such. `None` when M is not symmetric positive
    /// definite.
    pub fn of(matrix: Matrix<N, N>) -> Option<Self> {
        if matrix != matrix.transpose() || matrix.cholesky().is_none() {
            return None;
        }
        if matrix == Matrix::<N, N>::identity() {
            return Some(Self::Identity);
        }
        let diagonal = Matrix::from_diagonal(&matrix.diagonal());
        if matrix == diagonal {
            return Some(Self::Diagonal(matrix.diagonal()));
        }
        let inverse = linalg::inverse(&matrix)?;
        Some(Self::Dense { matrix, inverse })
    }

    /// `M v`.
    #[inline]
    pub fn times(&self, v: &Vector<N>) -> Vector<N> {
        match self {
            Self::Identity => *v,
            Self::Diagonal(m) => m.component_mul(v),
            Self::Dense { matrix, .. } => matrix * v,
        }
    }

    /// `M⁻¹ f`.
    #[inline]
    pub fn solve(&self, f: &Vector<N>) -> Vector<N> {
        match self {
            Self::Identity => *f,
            Self::Diagonal(m) => f.component_div(m),
            Self::Dense { inverse, .. } => inverse * f,
        }
    }

    /// `M⁻¹ B` for a matrix of K columns.
    #[inline]
    pub fn solve_columns<const K: usize>(&self, b: &Matrix<N, K>) -> Matrix<N, K> {
        match self {
            Self::Identity => *b,
            Self::Diagonal(m) => Matrix::<N, K>::from_fn(|i, j| b[(i, j)] / m[i]),
            Self::Dense { inverse, .. } => inverse * b,
        }
    }

    /// M as a matrix.
    #[inline]
    pub fn matrix(&self) -> Matrix<N, N> {
        match self {
            Self::Identity => Matrix::identity(),
            Self::Diagonal(m) => Matrix::from_diagonal(m),
            Self::Dense { matrix, .. } => *matrix,
        }
    }

    /// `½ vᵀ M v`.
    #[inline]
    pub fn kinetic_energy(&self, v: &Vector<N>) -> f64 {
        0.5 * v.dot(&self.times(v))
    }
}

/// What a system gives at one configuration for a step's forces: `∇V(q)` and `A(q)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Forces<const N: usize, const R: usize> {
    /// `∇V(q)`.
    pub gradient: Vector<N>,
    /// `A(q)`.
    pub constraint: Matrix<R, N>,
}

/// What a Newton iteration needs besides [`Forces`]: `∇²V(q)` and the partial derivatives
/// `∂A/∂q_k`, one R×N matrix per coordinate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Derivatives<const N: usize, const R: usize> {
    /// `∇²V(q)`.
    pub hessian: Matrix<N, N>,
    /// `∂A/∂q_k` for k = 0 … N − 1.
    pub partials: [Matrix<R, N>; N],
}

impl<const N: usize, const R: usize> Derivatives<N, R> {
    /// `∂(A(q) u)/∂q`, R×N: column k is `(∂A/∂q_k) u`.
    #[inline]
    pub fn constraint_jacobian(&self, u: &Vector<N>) -> Matrix<R, N> {
        let mut j = Matrix::<R, N>::zeros();
        for (k, partial) in self.partials.iter().enumerate() {
            j.set_column(k, &(partial * u));
        }
        j
    }

    /// `∂(A(q)ᵀ λ)/∂q`, N×N: column k is `(∂A/∂q_k)ᵀ λ`.
    #[inline]
    pub fn force_jacobian(&self, lambda: &Vector<R>) -> Matrix<N, N> {
        let mut j = Matrix::<N, N>::zeros();
        for (k, partial) in self.partials.iter().enumerate() {
            j.set_column(k, &(partial.transpose() * lambda));
        }
        j
    }
}

/// A mechanical system with linear velocity constraints, N coordinates and R constraints;
/// see the module's doc. Derivatives are exact (Newton needs them).
pub trait Mechanical<const N: usize, const R: usize>: Send + Sync {
    /// The mass matrix.
    fn mass(&self) -> &Mass<N>;
    /// `V(q)`.
    fn potential(&self, q: &Vector<N>) -> f64;
    /// `∇V(q)` and `A(q)`.
    fn forces(&self, q: &Vector<N>) -> Forces<N, R>;
    /// `∇²V(q)` and `∂A/∂q`.
    fn derivatives(&self, q: &Vector<N>) -> Derivatives<N, R>;
    /// [`Mechanical::forces`] and [`Mechanical::derivatives`] together (a Newton iteration
    /// needs both; a system whose code computes them at once overrides it).
    #[inline]
    fn forces_and_derivatives(&self, q: &Vector<N>) -> (Forces<N, R>, Derivatives<N, R>) {
        (self.forces(q), self.derivatives(q))
    }
    /// The coordinate that is an angle the whole system is 2π-periodic in, if any: a
    /// reference solve keeps it near 0 by whole turns (`docs/model.md` §7).
    fn angle(&self) -> Option<usize> {
        None
    }
    /// Whether V is quadratic (`∇²V` constant): Gonzalez's correction is then only rounding
    /// (DD's general step).
    fn quadratic_potential(&self) -> bool {
        false
    }
    /// The invariants it declares (`docs/model.md` §4), compiled on its `(q, q̇)`: a system
    /// given as formulas carries those of its spec; a built-in compiled into nhlab has none.
    fn invariants(&self) -> Option<&Invariants> {
        None
    }

    /// `∇V(q)`.
    #[inline]
    fn gradient(&self, q: &Vector<N>) -> Vector<N> {
        self.forces(q).gradient
    }
    /// `A(q)`.
    #[inline]
    fn constraint(&self, q: &Vector<N>) -> Matrix<R, N> {
        self.forces(q).constraint
    }
    /// Total energy `H = ½ q̇ᵀM q̇ + V(q)`.
    #[inline]
    fn energy(&self, q: &Vector<N>, v: &Vector<N>) -> f64 {
        self.mass().kinetic_energy(v) + self.potential(q)
    }
    /// Constraint residual `|A(q) q̇|`.
    #[inline]
    fn constraint_residual(&self, q: &Vector<N>, v: &Vector<N>) -> f64 {
        (self.constraint(q) * v).norm()
    }
    /// The continuous multiplier at `(q, q̇)` (`docs/model.md` §1):
    /// `(A M⁻¹ Aᵀ) λ = A M⁻¹ ∇V − (∂(A q̇)/∂q) q̇`; `None` when `A M⁻¹ Aᵀ` is singular.
    #[inline]
    fn continuous_multiplier(&self, q: &Vector<N>, v: &Vector<N>) -> Option<Vector<R>> {
        self.acceleration(q, v).map(|(_, lambda)| lambda)
    }
    /// The constrained ODE with the multiplier eliminated: `q̈` and `λ` at `(q, q̇)`, from
    /// `M q̈ = −∇V + Aᵀλ` and `A q̈ + (∂(A q̇)/∂q) q̇ = 0`; `None` when `A M⁻¹ Aᵀ` is singular.
    #[inline]
    fn acceleration(&self, q: &Vector<N>, v: &Vector<N>) -> Option<(Vector<N>, Vector<R>)> {
        acceleration_at(self.mass(), &self.forces(q), &self.derivatives(q), v)
    }
}

/// [`Mechanical::acceleration`] from the forces and derivatives at q, where a step has them.
#[inline]
pub fn acceleration_at<const N: usize, const R: usize>(
    mass: &Mass<N>,
    f: &Forces<N, R>,
    d: &Derivatives<N, R>,
    v: &Vector<N>,
) -> Option<(Vector<N>, Vector<R>)> {
    let a_dot_v = d.constraint_jacobian(v) * v;
    let m_at = mass.solve_columns(&f.constraint.transpose());
    let m_g = mass.solve(&f.gradient);
    let lambda = linalg::solve(&(f.constraint * m_at), &(f.constraint * m_g - a_dot_v))?;
    Some((m_at * lambda - m_g, lambda))
}

/// A system of the general class compiled into nhlab: its description, and its
/// construction from parameter values.
pub trait GeneralBuiltIn<const N: usize, const R: usize>: Mechanical<N, R> + Sized {
    /// Its description.
    fn info() -> &'static SystemInfo;
    /// Builds it from parameter values given in the order of `info().params`, already
    /// checked against their ranges.
    fn new(params: &[f64]) -> Self;
}

/// A system of the paper's class ([`System`]) seen as a member of the general class: M = I,
/// `V = U + V_d`, `A(q) = A(ζ)` with `∂A/∂ζ` its only nonzero partial derivative. Runs a
/// method's general step on a class system (the general path; `docs/architecture.md`).
#[derive(Debug, Clone, Copy)]
pub struct General<'a, S>(pub &'a S);

impl<S: System<N, R>, const N: usize, const R: usize> Mechanical<N, R> for General<'_, S> {
    #[inline]
    fn mass(&self) -> &Mass<N> {
        &Mass::Identity
    }
    #[inline]
    fn potential(&self, q: &Vector<N>) -> f64 {
        self.0.potential(q)
    }
    #[inline]
    fn forces(&self, q: &Vector<N>) -> Forces<N, R> {
        let at_q = self.0.driver_terms(q[N - 1]);
        Forces { gradient: at_q.gradient(self.0, q), constraint: at_q.constraint }
    }
    #[inline]
    fn derivatives(&self, q: &Vector<N>) -> Derivatives<N, R> {
        let mut partials = [Matrix::<R, N>::zeros(); N];
        let at_q = self.0.driver_terms(q[N - 1]);
        partials[N - 1] = at_q.constraint_d;
        Derivatives { hessian: at_q.hessian(self.0, q), partials }
    }
    fn angle(&self) -> Option<usize> {
        self.0.zeta_is_angle().then_some(N - 1)
    }
    fn quadratic_potential(&self) -> bool {
        self.0.quadratic_passenger() && self.0.quadratic_driver()
    }
    fn invariants(&self) -> Option<&Invariants> {
        self.0.invariants()
    }
    /// The class's own, so that a reference solve of a class system gives the numbers it
    /// always gave.
    #[inline]
    fn acceleration(&self, q: &Vector<N>, v: &Vector<N>) -> Option<(Vector<N>, Vector<R>)> {
        self.0.acceleration(q, v)
    }
    #[inline]
    fn energy(&self, q: &Vector<N>, v: &Vector<N>) -> f64 {
        self.0.energy(q, v)
    }
    #[inline]
    fn constraint_residual(&self, q: &Vector<N>, v: &Vector<N>) -> f64 {
        self.0.constraint_residual(q, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::systems::{CvtPendulum, MobileRobot};

    #[test]
    fn a_mass_is_recognised_by_kind_and_refused_unless_positive_definite() {
        assert_eq!(Mass::<3>::of(Matrix::identity()), Some(Mass::Identity));
        let d = Matrix::<3, 3>::from_diagonal(&Vector::<3>::new(1.0, 2.0, 4.0));
        assert_eq!(Mass::of(d), Some(Mass::Diagonal(Vector::<3>::new(1.0, 2.0, 4.0))));
        let mut full = d;
        (full[(0, 1)], full[(1, 0)]) = (0.5, 0.5);
        let mass = Mass::of(full).unwrap();
        let v = Vector::<3>::new(1.0, -2.0, 0.5);
        assert!((mass.solve(&mass.times(&v)) - v).amax() < 1e-15);
        full[(0, 1)] = 0.4;
        assert_eq!(Mass::of(full), None, "not symmetric");
        let mut indefinite = d;
        indefinite[(2, 2)] = -1.0;
        assert_eq!(Mass::of(indefinite), None);
    }

    /// The general class's multiplier and acceleration, from ∂A/∂q, agree with the class's
    /// own (from dA/dζ) on class systems.
    #[test]
    fn the_general_acceleration_is_the_class_one() {
        let pendulum = CvtPendulum { epsilon: 0.5 };
        let (q, v) = (Vector::<3>::new(0.3, -0.7, 1.1), Vector::<3>::new(0.0, 0.0, 1.3));
        let mut v = v;
        let k = pendulum.kernel(q[2]);
        v += 0.8 * k;
        let general = General(&pendulum);
        let f = general.forces(&q);
        let m_g = f.gradient;
        let a_dot_v = general.derivatives(&q).constraint_jacobian(&v) * v;
        let lambda = linalg::solve(
            &(f.constraint * f.constraint.transpose()),
            &(f.constraint * m_g - a_dot_v),
        )
        .unwrap();
        let (_, class_lambda) = pendulum.acceleration(&q, &v).unwrap();
        assert!((lambda - class_lambda).amax() < 1e-14);
        let robot = MobileRobot;
        let q = Vector::<4>::new(0.1, 0.2, 0.3, 0.4);
        let v = Vector::<4>::new(-0.4f64.cos(), -0.4f64.sin(), 1.0, 0.5);
        let d = General(&robot).derivatives(&q);
        assert_eq!(d.partials[3], robot.constraint_d(q[3]));
        assert!(d.partials[..3].iter().all(|p| *p == Matrix::<2, 4>::zeros()));
        assert!(General(&robot).constraint_residual(&q, &v) < 1e-15);
    }
}
