//! `particle`: the nonholonomic particle.
//!
//! `q = (x₁, x₂, ζ)`, `U = ½x₂²`, `V_d = ½ζ²`, constraint `ẋ₁ + ζ ẋ₂ = 0`. The paper did not
//! run it; the default state starts the passenger at rest off its equilibrium.

use crate::model::system::{BuiltIn, Form, FormulaForm, Preset, System, SystemInfo};
use crate::{Integral, Matrix, Vector};

/// The nonholonomic particle (no parameters).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Particle;

static INFO: SystemInfo = SystemInfo {
    id: "particle",
    name: "Nonholonomic particle",
    description: "A particle with potential ½x₂² whose velocity obeys ẋ₁ + ζ ẋ₂ = 0, driven by a harmonic ζ.",
    source: "Cortés & Martínez, Nonlinearity 14 (2001); Modin & Verdier",
    params: &[],
    integrals: &[
        Integral::Energy,
        Integral::PassengerEnergy,
        Integral::DriverEnergy,
        Integral::Constraint,
    ],
    presets: &[Preset {
        id: "default",
        label: "Passenger at rest off equilibrium, driver amplitude 1",
        params: &[],
        q: &[0.0, 1.0, 0.0],
        v: &[0.0, 0.0, 1.0],
        step: 0.1,
        t_end: 1000.0,
    }],
    form: Form::Coupled(FormulaForm {
        passenger: &["x1", "x2"],
        driver: "zeta",
        passenger_potential: "x2^2/2",
        driver_potential: "zeta^2/2",
        constraints: &[&["1", "zeta"]],
    }),
    exact: None,
};

impl BuiltIn<3, 1> for Particle {
    fn info() -> &'static SystemInfo {
        &INFO
    }
    fn new(_params: &[f64]) -> Self {
        Self
    }
}

impl System<3, 1> for Particle {
    fn rank_is_constant(&self) -> bool {
        true
    }
    fn quadratic_passenger(&self) -> bool {
        true
    }
    fn quadratic_driver(&self) -> bool {
        true
    }
    fn passenger_potential(&self, q: &Vector<3>) -> f64 {
        0.5 * q[1] * q[1]
    }
    fn passenger_gradient(&self, q: &Vector<3>) -> Vector<3> {
        Vector::<3>::new(0.0, q[1], 0.0)
    }
    fn passenger_hessian(&self, _q: &Vector<3>) -> Matrix<3, 3> {
        Matrix::<3, 3>::from_diagonal(&Vector::<3>::new(0.0, 1.0, 0.0))
    }
    fn driver_potential(&self, zeta: f64) -> f64 {
        0.5 * zeta * zeta
    }
    fn driver_potential_d1(&self, zeta: f64) -> f64 {
        zeta
    }
    fn driver_potential_d2(&self, _zeta: f64) -> f64 {
        1.0
    }
    fn constraint(&self, zeta: f64) -> Matrix<1, 3> {
        Matrix::<1, 3>::new(1.0, zeta, 0.0)
    }
    fn constraint_d(&self, _zeta: f64) -> Matrix<1, 3> {
        Matrix::<1, 3>::new(0.0, 1.0, 0.0)
    }
    fn kernel(&self, zeta: f64) -> Vector<3> {
        Vector::<3>::new(-zeta, 1.0, 0.0) / (1.0 + zeta * zeta).sqrt()
    }
}
