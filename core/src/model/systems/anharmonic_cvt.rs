//! `anharmonic_cvt`: `cvt_pendulum`'s driver and constraint with an anharmonic passenger,
//! `U = ½|x|² + (κ/4)|x|⁴` (`docs/model.md` §2).
//!
//! The first system whose U is not quadratic: DD's and DD-AVF's discrete gradients and the
//! Newton solves take their general paths here. κ = 0 is `cvt_pendulum`.

use super::CvtPendulum;
use super::cvt_pendulum::{EPSILON, V_OSC, V_ROT, paper};
use crate::model::system::{BuiltIn, Form, FormulaForm, DriverTerms, ParamSpec, System, SystemInfo};
use crate::{Integral, Matrix, Vector};

/// The CVT with a pendulum driver perturbed by `ε` and a passenger potential stiffened by `κ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnharmonicCvt {
    /// Perturbation of the driver potential.
    pub epsilon: f64,
    /// Quartic stiffness of the passenger potential.
    pub kappa: f64,
}

static INFO: SystemInfo = SystemInfo {
    id: "anharmonic_cvt",
    name: "CVT, pendulum driver, anharmonic passenger",
    description: "cvt_pendulum with the passenger potential ½|x|² + (κ/4)|x|⁴: the general paths of the implicit methods; κ = 0 is cvt_pendulum.",
    source: "nhlab's variant of Modin & Verdier's pendulum-driven CVT (a quartic passenger spring)",
    params: &[
        EPSILON,
        ParamSpec {
            name: "kappa",
            default: 1.0,
            min: 0.0,
            max: 100.0,
            min_open: false,
            max_open: false,
            description: "quartic stiffness κ of the passenger potential ½|x|² + (κ/4)|x|⁴",
        },
    ],
    integrals: &[
        Integral::Energy,
        Integral::PassengerEnergy,
        Integral::DriverEnergy,
        Integral::Constraint,
    ],
    presets: &[
        paper("oscillating", "Oscillating driver, ε = 0", 0.0, V_OSC),
        paper("rotating", "Rotating driver, ε = 0", 0.0, V_ROT),
        paper("oscillating-perturbed", "Oscillating driver, ε = 0.5", 0.5, V_OSC),
        paper("rotating-perturbed", "Rotating driver, ε = 0.5", 0.5, V_ROT),
    ],
    form: Form::Coupled(FormulaForm {
        passenger: &["x1", "x2"],
        driver: "zeta",
        passenger_potential: "(x1^2 + x2^2)/2 + kappa*(x1^2 + x2^2)^2/4",
        driver_potential: "1 - cos(zeta) - epsilon*sin(2*zeta)/2",
        constraints: &[&["1", "sin(zeta)"]],
    }),
    exact: None,
};

impl AnharmonicCvt {
    /// The driver and the constraint: `cvt_pendulum`'s.
    #[inline]
    fn driver(&self) -> CvtPendulum {
        CvtPendulum { epsilon: self.epsilon }
    }
}

impl BuiltIn<3, 1> for AnharmonicCvt {
    fn info() -> &'static SystemInfo {
        &INFO
    }
    fn new(params: &[f64]) -> Self {
        Self { epsilon: params[0], kappa: params[1] }
    }
}

impl System<3, 1> for AnharmonicCvt {
    fn rank_is_constant(&self) -> bool {
        true
    }
    fn zeta_is_angle(&self) -> bool {
        true
    }
    fn passenger_potential(&self, q: &Vector<3>) -> f64 {
        let r2 = q[0] * q[0] + q[1] * q[1];
        0.5 * r2 + 0.25 * self.kappa * r2 * r2
    }
    /// `∇U = (1 + κ|x|²) x`.
    fn passenger_gradient(&self, q: &Vector<3>) -> Vector<3> {
        let f = 1.0 + self.kappa * (q[0] * q[0] + q[1] * q[1]);
        Vector::<3>::new(f * q[0], f * q[1], 0.0)
    }
    /// `∇²U = (1 + κ|x|²) I + 2κ x xᵀ` on the passenger block.
    fn passenger_hessian(&self, q: &Vector<3>) -> Matrix<3, 3> {
        let (x, y, k) = (q[0], q[1], self.kappa);
        let f = 1.0 + k * (x * x + y * y);
        Matrix::<3, 3>::new(
            f + 2.0 * k * x * x,
            2.0 * k * x * y,
            0.0,
            2.0 * k * x * y,
            f + 2.0 * k * y * y,
            0.0,
            0.0,
            0.0,
            0.0,
        )
    }
    fn driver_potential(&self, zeta: f64) -> f64 {
        self.driver().driver_potential(zeta)
    }
    fn driver_potential_d1(&self, zeta: f64) -> f64 {
        self.driver().driver_potential_d1(zeta)
    }
    fn driver_potential_d2(&self, zeta: f64) -> f64 {
        self.driver().driver_potential_d2(zeta)
    }
    fn constraint(&self, zeta: f64) -> Matrix<1, 3> {
        self.driver().constraint(zeta)
    }
    fn constraint_d(&self, zeta: f64) -> Matrix<1, 3> {
        self.driver().constraint_d(zeta)
    }
    #[inline]
    fn driver_terms_trig(&self, zeta: f64, s: f64, c: f64) -> DriverTerms<3, 1> {
        self.driver().driver_terms_trig(zeta, s, c)
    }
    fn kernel(&self, zeta: f64) -> Vector<3> {
        self.driver().kernel(zeta)
    }
    fn driver_is_periodic(&self) -> bool {
        true
    }
}
