//! `cvt`: the continuously variable transmission with a harmonic driver
//! (McLachlan–Perlmutter's contact oscillator).
//!
//! `q = (x₁, x₂, ζ)`, `U = ½|x|²`, `V_d = ½ζ²`, constraint `ẋ₁ + ζ ẋ₂ = 0`. The driver is a
//! harmonic oscillator of period 2π, which makes the latitude's monodromy easy to check.

use crate::model::system::{BuiltIn, Form, FormulaForm, Preset, System, SystemInfo};
use crate::{Integral, Matrix, Vector};

/// The CVT with a harmonic driver (no parameters).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Cvt;

static INFO: SystemInfo = SystemInfo {
    id: "cvt",
    name: "CVT, harmonic driver",
    description: "Continuously variable transmission: a 2-d harmonic passenger coupled to a harmonic driver ζ through ẋ₁ + ζ ẋ₂ = 0.",
    source: "Modin & Verdier, What makes nonholonomic integrators work?; McLachlan & Perlmutter (2006)",
    params: &[],
    integrals: &[
        Integral::Energy,
        Integral::PassengerEnergy,
        Integral::DriverEnergy,
        Integral::Latitude,
        Integral::Constraint,
    ],
    presets: &[Preset {
        id: "default",
        label: "Harmonic driver, amplitude 1",
        params: &[],
        q: &[1.0, 1.0, 0.0],
        v: &[0.0, 0.5, 1.0],
        step: 0.1,
        t_end: 1000.0,
    }],
    form: Form::Coupled(FormulaForm {
        passenger: &["x1", "x2"],
        driver: "zeta",
        passenger_potential: "(x1^2 + x2^2)/2",
        driver_potential: "zeta^2/2",
        constraints: &[&["1", "zeta"]],
    }),
    exact: None,
};

impl BuiltIn<3, 1> for Cvt {
    fn info() -> &'static SystemInfo {
        &INFO
    }
    fn new(_params: &[f64]) -> Self {
        Self
    }
}

impl System<3, 1> for Cvt {
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
        0.5 * (q[0] * q[0] + q[1] * q[1])
    }
    fn passenger_gradient(&self, q: &Vector<3>) -> Vector<3> {
        Vector::<3>::new(q[0], q[1], 0.0)
    }
    fn passenger_hessian(&self, _q: &Vector<3>) -> Matrix<3, 3> {
        Matrix::<3, 3>::from_diagonal(&Vector::<3>::new(1.0, 1.0, 0.0))
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
