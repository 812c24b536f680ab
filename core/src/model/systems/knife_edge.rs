//! `knife_edge`: a skate on an inclined plane (Modin & Verdier, Fig. "energy_knife_edge").
//!
//! `q = (x₁, x₂, ζ)`, `U = −x₁` (gravity along x₁: `docs/model.md` correction 3), no driver
//! potential, constraint `−sin ζ ẋ₁ + (cos ζ − ε) ẋ₂ = 0`. The perturbation ε breaks the
//! reversibility that the paper credits for near conservation; |ε| < 1 keeps A of full rank.

use crate::model::system::{BuiltIn, Form, FormulaForm, DriverTerms, ParamSpec, Preset, System, SystemInfo};
use crate::{Integral, Matrix, Vector};
use std::f64::consts::{FRAC_PI_2, PI};

/// The knife edge with perturbation `ε`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KnifeEdge {
    /// Perturbation of the constraint.
    pub epsilon: f64,
}

static INFO: SystemInfo = SystemInfo {
    id: "knife_edge",
    name: "Knife edge (skate on an inclined plane)",
    description: "A skate sliding on an inclined plane without sideways slip; ε perturbs the constraint and breaks reversibility.",
    source: "Modin & Verdier, What makes nonholonomic integrators work?, §3.1; Bloch",
    params: &[ParamSpec {
        name: "epsilon",
        default: 0.0,
        min: -1.0,
        max: 1.0,
        min_open: true,
        max_open: true,
        description: "perturbation ε of the constraint −sin ζ ẋ₁ + (cos ζ − ε) ẋ₂ = 0",
    }],
    integrals: &[
        Integral::Energy,
        Integral::PassengerEnergy,
        Integral::DriverEnergy,
        Integral::Constraint,
    ],
    presets: &[
        Preset {
            id: "paper",
            label: "Paper: knife edge, ε = 0",
            params: &[("epsilon", 0.0)],
            q: &[0.0, 0.0, FRAC_PI_2],
            v: &[0.0, 0.0, 1.0],
            step: PI / 10.0,
            t_end: 100.0,
        },
        Preset {
            id: "paper-perturbed",
            label: "Paper: knife edge, ε = 0.1",
            params: &[("epsilon", 0.1)],
            q: &[0.0, 0.0, FRAC_PI_2],
            v: &[0.0, 0.0, 1.0],
            step: PI / 10.0,
            t_end: 100.0,
        },
    ],
    form: Form::Coupled(FormulaForm {
        passenger: &["x1", "x2"],
        driver: "zeta",
        passenger_potential: "-x1",
        driver_potential: "0",
        constraints: &[&["-sin(zeta)", "cos(zeta) - epsilon"]],
    }),
    exact: None,
};

impl BuiltIn<3, 1> for KnifeEdge {
    fn info() -> &'static SystemInfo {
        &INFO
    }
    fn new(params: &[f64]) -> Self {
        Self { epsilon: params[0] }
    }
}

impl System<3, 1> for KnifeEdge {
    fn rank_is_constant(&self) -> bool {
        true
    }
    fn quadratic_passenger(&self) -> bool {
        true
    }
    fn quadratic_driver(&self) -> bool {
        true
    }
    fn zeta_is_angle(&self) -> bool {
        true
    }
    fn passenger_potential(&self, q: &Vector<3>) -> f64 {
        -q[0]
    }
    fn passenger_gradient(&self, _q: &Vector<3>) -> Vector<3> {
        Vector::<3>::new(-1.0, 0.0, 0.0)
    }
    fn passenger_hessian(&self, _q: &Vector<3>) -> Matrix<3, 3> {
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
    fn constraint(&self, zeta: f64) -> Matrix<1, 3> {
        self.driver_terms(zeta).constraint
    }
    fn constraint_d(&self, zeta: f64) -> Matrix<1, 3> {
        self.driver_terms(zeta).constraint_d
    }
    #[inline]
    fn driver_terms_trig(&self, _zeta: f64, s: f64, c: f64) -> DriverTerms<3, 1> {
        DriverTerms {
            constraint: Matrix::<1, 3>::new(-s, c - self.epsilon, 0.0),
            constraint_d: Matrix::<1, 3>::new(-c, -s, 0.0),
            potential: 0.0,
            potential_d1: 0.0,
            potential_d2: 0.0,
        }
    }
    fn kernel(&self, zeta: f64) -> Vector<3> {
        let (s, c) = zeta.sin_cos();
        Vector::<3>::new(c - self.epsilon, s, 0.0).normalize()
    }
}
