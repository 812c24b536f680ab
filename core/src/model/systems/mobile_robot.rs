//! `mobile_robot`: the rolling disk with a heading potential `V_d = sin ζ`.
//!
//! Same geometry as `rolling_disk`; the potential makes the heading a pendulum, so the
//! driver is no longer uniform.

use super::rolling_disk::{DISK_INTEGRALS, disk_kernel, disk_terms};
use crate::model::system::{BuiltIn, Form, FormulaForm, DriverTerms, Preset, System, SystemInfo};
use crate::{Matrix, Vector};

/// The mobile robot (no parameters).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MobileRobot;

static INFO: SystemInfo = SystemInfo {
    id: "mobile_robot",
    name: "Mobile robot",
    description: "A rolling disk whose heading ζ feels the potential sin ζ, so it swings like a pendulum.",
    source: "Iglesias, Marrero, Martín de Diego & Martínez, J. Nonlinear Sci. (2008); odelab's Robot",
    params: &[],
    integrals: DISK_INTEGRALS,
    presets: &[Preset {
        id: "default",
        label: "Heading swinging about −π/2",
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
        driver_potential: "sin(zeta)",
        constraints: &[&["1", "0", "cos(zeta)"], &["0", "1", "sin(zeta)"]],
    }),
    exact: None,
};

impl BuiltIn<4, 2> for MobileRobot {
    fn info() -> &'static SystemInfo {
        &INFO
    }
    fn new(_params: &[f64]) -> Self {
        Self
    }
}

impl System<4, 2> for MobileRobot {
    fn rank_is_constant(&self) -> bool {
        true
    }
    fn quadratic_passenger(&self) -> bool {
        true
    }
    fn free_passenger(&self) -> bool {
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
    fn driver_potential(&self, zeta: f64) -> f64 {
        self.driver_terms(zeta).potential
    }
    fn driver_potential_d1(&self, zeta: f64) -> f64 {
        self.driver_terms(zeta).potential_d1
    }
    fn driver_potential_d2(&self, zeta: f64) -> f64 {
        self.driver_terms(zeta).potential_d2
    }
    fn constraint(&self, zeta: f64) -> Matrix<2, 4> {
        self.driver_terms(zeta).constraint
    }
    fn constraint_d(&self, zeta: f64) -> Matrix<2, 4> {
        self.driver_terms(zeta).constraint_d
    }
    // V_d = sin ζ.
    #[inline]
    fn driver_terms_trig(&self, _zeta: f64, s: f64, c: f64) -> DriverTerms<4, 2> {
        disk_terms(s, c, [s, c, -s])
    }
    fn kernel(&self, zeta: f64) -> Vector<4> {
        disk_kernel(zeta)
    }
    fn driver_is_periodic(&self) -> bool {
        true
    }
}
