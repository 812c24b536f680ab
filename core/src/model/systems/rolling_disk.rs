//! `rolling_disk`: the vertical rolling disk, and the disk geometry shared with
//! `mobile_robot`.
//!
//! `q = (x₁, x₂, φ, ζ)`: contact point, rolling angle, heading. Rolling without slipping:
//! `ẋ₁ + cos ζ φ̇ = 0`, `ẋ₂ + sin ζ φ̇ = 0`. No potential, so the heading turns uniformly and
//! the disk runs on a circle: an exact solution for the convergence tests.

use crate::model::system::{BuiltIn, Form, FormulaForm, DriverTerms, Preset, System, SystemInfo};
use crate::{Integral, Matrix, Vector};

/// The vertical rolling disk (no parameters).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RollingDisk;

/// [`DriverTerms`] of a disk rolling without slipping, from `sin ζ` and `cos ζ`, with the
/// heading potential's `[V_d, V_d', V_d'']`.
#[inline]
pub(crate) fn disk_terms(s: f64, c: f64, potential: [f64; 3]) -> DriverTerms<4, 2> {
    DriverTerms {
        constraint: Matrix::<2, 4>::new(1.0, 0.0, c, 0.0, 0.0, 1.0, s, 0.0),
        constraint_d: Matrix::<2, 4>::new(0.0, 0.0, -s, 0.0, 0.0, 0.0, c, 0.0),
        potential: potential[0],
        potential_d1: potential[1],
        potential_d2: potential[2],
    }
}

/// The unit kernel `(−cos ζ, −sin ζ, 1)/√2` of the rolling disk.
pub(crate) fn disk_kernel(zeta: f64) -> Vector<4> {
    let (s, c) = zeta.sin_cos();
    Vector::<4>::new(-c, -s, 1.0, 0.0) * std::f64::consts::FRAC_1_SQRT_2
}

pub(crate) const DISK_INTEGRALS: &[Integral] =
    &[Integral::Energy, Integral::PassengerEnergy, Integral::DriverEnergy, Integral::Constraint];

static INFO: SystemInfo = SystemInfo {
    id: "rolling_disk",
    name: "Vertical rolling disk",
    description: "A disk rolling upright without slipping on a plane; its heading ζ drives the contact point.",
    source: "Bloch, Nonholonomic Mechanics and Control; Modin & Verdier",
    params: &[],
    integrals: DISK_INTEGRALS,
    presets: &[Preset {
        id: "default",
        label: "Rolling and turning at unit rates",
        params: &[],
        q: &[0.0, 0.0, 0.0, 0.0],
        v: &[-1.0, 0.0, 1.0, 1.0],
        step: 0.1,
        t_end: 100.0,
    }],
    form: Form::Coupled(FormulaForm {
        passenger: &["x1", "x2", "phi"],
        driver: "zeta",
        passenger_potential: "0",
        driver_potential: "0",
        constraints: &[&["1", "0", "cos(zeta)"], &["0", "1", "sin(zeta)"]],
    }),
    exact: None,
};

impl BuiltIn<4, 2> for RollingDisk {
    fn info() -> &'static SystemInfo {
        &INFO
    }
    fn new(_params: &[f64]) -> Self {
        Self
    }
}

impl System<4, 2> for RollingDisk {
    fn rank_is_constant(&self) -> bool {
        true
    }
    fn quadratic_passenger(&self) -> bool {
        true
    }
    fn free_passenger(&self) -> bool {
        true
    }
    fn quadratic_driver(&self) -> bool {
        true
    }
    fn zeta_is_angle(&self) -> bool {
        true
    }
    fn passenger_potential(&self, _q: &Vector<4>) -> f64 {
        0.0
    }
    fn passenger_gradient(&self, _q: &Vector<4>) -> Vector<4> {
        Vector::zeros()
    }
    fn passenger_hessian(&self, _q: &Vector<4>) -> Matrix<4, 4> {
        Matrix::zeros()
    }
    fn driver_potential(&self, _zeta: f64) -> f64 {
        0.0
    }
    fn driver_potential_d1(&self, _zeta: f64) -> f64 {
        0.0
    }
    fn driver_potential_d2(&self, _zeta: f64) -> f64 {
        0.0
    }
    fn constraint(&self, zeta: f64) -> Matrix<2, 4> {
        self.driver_terms(zeta).constraint
    }
    fn constraint_d(&self, zeta: f64) -> Matrix<2, 4> {
        self.driver_terms(zeta).constraint_d
    }
    #[inline]
    fn driver_terms_trig(&self, _zeta: f64, s: f64, c: f64) -> DriverTerms<4, 2> {
        disk_terms(s, c, [0.0; 3])
    }
    fn kernel(&self, zeta: f64) -> Vector<4> {
        disk_kernel(zeta)
    }
}
