//! `cvt_pendulum`: the CVT with a pendulum driver, the paper's main perturbed test problem.
//!
//! `q = (x₁, x₂, ζ)`, `U = ½|x|²`, `V_d = 1 − cos ζ − ε sin(2ζ)/2` (`docs/model.md` corrections 1:
//! the printed potential lacks the `1 −`), constraint `ẋ₁ + sin ζ ẋ₂ = 0`. ε ≠ 0 breaks the
//! driver's reversibility; the driver oscillates or rotates depending on its energy.

use crate::model::system::{BuiltIn, Form, FormulaForm, DriverTerms, ParamSpec, Preset, System, SystemInfo};
use crate::{Integral, Matrix, Vector};

/// The CVT with a pendulum driver perturbed by `ε`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CvtPendulum {
    /// Perturbation of the driver potential.
    pub epsilon: f64,
}

/// ε, the driver's perturbation (shared with `anharmonic_cvt`).
pub(crate) const EPSILON: ParamSpec = ParamSpec {
    name: "epsilon",
    default: 0.0,
    min: -10.0,
    max: 10.0,
    min_open: false,
    max_open: false,
    description: "perturbation ε of the driver potential 1 − cos ζ − ε sin(2ζ)/2",
};

const Q0: &[f64] = &[1.0, 1.0, 0.0];
// The paper's initial driver speeds: H(0) = 2.8 (oscillating) and 5.0 (rotating).
pub(crate) const V_OSC: &[f64] = &[0.0, 0.0, 1.897_366_6];
pub(crate) const V_ROT: &[f64] = &[0.0, 0.0, 2.828_427_12];

/// A preset from the paper's CVT initial state `q = (1, 1, 0)`, driver speed `v`, ε = 0 or 0.5.
pub(crate) const fn paper(id: &'static str, label: &'static str, eps: f64, v: &'static [f64]) -> Preset {
    Preset {
        id,
        label,
        params: if eps == 0.0 { &[("epsilon", 0.0)] } else { &[("epsilon", 0.5)] },
        q: Q0,
        v,
        step: 0.1,
        t_end: 3000.0,
    }
}

static INFO: SystemInfo = SystemInfo {
    id: "cvt_pendulum",
    name: "CVT, pendulum driver",
    description: "Continuously variable transmission driven by a pendulum ζ through ẋ₁ + sin ζ ẋ₂ = 0; ε breaks the driver's reversibility.",
    source: "Modin & Verdier, What makes nonholonomic integrators work?, §3.2",
    params: &[EPSILON],
    integrals: &[
        Integral::Energy,
        Integral::PassengerEnergy,
        Integral::DriverEnergy,
        Integral::Latitude,
        Integral::Constraint,
    ],
    presets: &[
        paper("oscillating", "Paper: oscillating driver, ε = 0", 0.0, V_OSC),
        paper("rotating", "Paper: rotating driver, ε = 0", 0.0, V_ROT),
        paper("oscillating-perturbed", "Paper: oscillating driver, ε = 0.5", 0.5, V_OSC),
        paper("rotating-perturbed", "Paper: rotating driver, ε = 0.5", 0.5, V_ROT),
    ],
    form: Form::Coupled(FormulaForm {
        passenger: &["x1", "x2"],
        driver: "zeta",
        passenger_potential: "(x1^2 + x2^2)/2",
        driver_potential: "1 - cos(zeta) - epsilon*sin(2*zeta)/2",
        constraints: &[&["1", "sin(zeta)"]],
    }),
    exact: None,
};

impl CvtPendulum {
    /// `[V_d, V_d', V_d'']` from `sin ζ` and `cos ζ` (double angles written through them).
    #[inline]
    fn v_d(&self, s: f64, c: f64) -> [f64; 3] {
        let e = self.epsilon;
        [1.0 - c - e * s * c, s - e * (c * c - s * s), c + 4.0 * e * s * c]
    }
}

impl BuiltIn<3, 1> for CvtPendulum {
    fn info() -> &'static SystemInfo {
        &INFO
    }
    fn new(params: &[f64]) -> Self {
        Self { epsilon: params[0] }
    }
}

impl System<3, 1> for CvtPendulum {
    fn rank_is_constant(&self) -> bool {
        true
    }
    fn quadratic_passenger(&self) -> bool {
        true
    }
    fn zeta_is_angle(&self) -> bool {
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
    // Each evaluates its own sin_cos: where a step needs several at one ζ the compiler keeps
    // a single call (built from one `DriverTerms` instead, it made leap-frog's step slower).
    fn driver_potential(&self, zeta: f64) -> f64 {
        let (s, c) = zeta.sin_cos();
        self.v_d(s, c)[0]
    }
    fn driver_potential_d1(&self, zeta: f64) -> f64 {
        let (s, c) = zeta.sin_cos();
        self.v_d(s, c)[1]
    }
    fn driver_potential_d2(&self, zeta: f64) -> f64 {
        let (s, c) = zeta.sin_cos();
        self.v_d(s, c)[2]
    }
    fn constraint(&self, zeta: f64) -> Matrix<1, 3> {
        Matrix::<1, 3>::new(1.0, zeta.sin_cos().0, 0.0)
    }
    fn constraint_d(&self, zeta: f64) -> Matrix<1, 3> {
        Matrix::<1, 3>::new(0.0, zeta.sin_cos().1, 0.0)
    }
    #[inline]
    fn driver_terms_trig(&self, _zeta: f64, s: f64, c: f64) -> DriverTerms<3, 1> {
        let [potential, potential_d1, potential_d2] = self.v_d(s, c);
        DriverTerms {
            constraint: Matrix::<1, 3>::new(1.0, s, 0.0),
            constraint_d: Matrix::<1, 3>::new(0.0, c, 0.0),
            potential,
            potential_d1,
            potential_d2,
        }
    }
    fn kernel(&self, zeta: f64) -> Vector<3> {
        let s = zeta.sin();
        Vector::<3>::new(-s, 1.0, 0.0) / (1.0 + s * s).sqrt()
    }
    fn driver_is_periodic(&self) -> bool {
        true
    }
}
