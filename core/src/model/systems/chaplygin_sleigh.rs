//! `chaplygin_sleigh`: the Chaplygin sleigh (`docs/model.md` §2), a rigid body on a plane
//! resting on a knife edge at distance a behind its centre of mass, which may slide along its
//! blade but not across it (Fedorov & Zenkov 2005; Jay's and odelab's tests).
//!
//! `q = (x, y, θ)`, the centre of mass and the heading; `L = ½m(ẋ² + ẏ²) + ½Iθ̇² − m g y`;
//! constraint `−sin θ ẋ + cos θ ẏ − a θ̇ = 0`. The constraint has a column for the turning
//! speed, so the sleigh is outside the paper's class: it runs on the methods' general steps.
//! Free (g = 0) it turns ever slower and tends to straight motion; g tilts the plane.

use crate::model::custom::{GeneralSpec, MassEntry, MassSpec};
use crate::model::mechanical::{Derivatives, Forces, GeneralBuiltIn, Mass, Mechanical};
use crate::model::system::{Form, ParamSpec, Preset, SystemInfo};
use crate::{InputError, Integral, Matrix, Vector};

/// The sleigh with mass m, inertia I about its centre of mass, knife edge at distance a
/// behind it, on a plane tilted by g.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChaplyginSleigh {
    mass: Mass<3>,
    m: f64,
    a: f64,
    g: f64,
}

const fn param(name: &'static str, default: f64, description: &'static str) -> ParamSpec {
    ParamSpec {
        name,
        default,
        min: 0.0,
        max: 100.0,
        min_open: true,
        max_open: false,
        description,
    }
}

static INFO: SystemInfo = SystemInfo {
    id: "chaplygin_sleigh",
    name: "Chaplygin sleigh",
    description: "A rigid body on a knife edge at distance a behind its centre of mass: it slides along the blade, not across it (−sin θ ẋ + cos θ ẏ − a θ̇ = 0). Outside the paper's class: the constraint has a column for the turning speed.",
    source: "Fedorov & Zenkov, Nonlinearity 18 (2005); Jay's and odelab's tests",
    params: &[
        param("m", 1.0, "mass m"),
        param("I", 1.0, "moment of inertia I about the centre of mass"),
        param("a", 0.5, "distance a from the knife edge to the centre of mass"),
        ParamSpec {
            name: "g",
            default: 0.0,
            min: -100.0,
            max: 100.0,
            min_open: false,
            max_open: false,
            description: "gravity g along y (the plane's tilt); 0: the free sleigh",
        },
    ],
    integrals: &[Integral::Energy, Integral::Constraint],
    presets: &[
        Preset {
            id: "free",
            label: "Free sleigh: turning ever slower",
            params: &[("m", 1.0), ("I", 1.0), ("a", 0.5), ("g", 0.0)],
            q: &[0.0, 0.0, 0.0],
            v: &[0.0, 0.5, 1.0],
            step: 0.1,
            t_end: 100.0,
        },
        Preset {
            id: "inclined",
            label: "Inclined sleigh (Jay's and odelab's test)",
            params: &[("m", 1.0), ("I", 1.0), ("a", 1.0), ("g", 0.1)],
            q: &[0.0, 0.0, 0.0],
            v: &[0.0, 1.0, 1.0],
            step: 0.1,
            t_end: 100.0,
        },
    ],
    form: Form::General(spec),
    exact: None,
};

/// The sleigh in the general form.
fn spec(params: &[f64]) -> Result<GeneralSpec, InputError> {
    let names = ["m", "I", "a", "g"];
    let entry = |s: &str| MassEntry::Formula(s.into());
    Ok(GeneralSpec {
        name: INFO.name.into(),
        coordinates: vec!["x".into(), "y".into(), "theta".into()],
        parameters: names.iter().map(|n| n.to_string()).zip(params.iter().copied()).collect(),
        mass: MassSpec::Diagonal(vec![entry("m"), entry("m"), entry("I")]),
        potential: "m*g*y".into(),
        constraints: vec![vec!["-sin(theta)".into(), "cos(theta)".into(), "-a".into()]],
        invariants: Vec::new(),
        detect_class: true,
    })
}

impl GeneralBuiltIn<3, 1> for ChaplyginSleigh {
    fn info() -> &'static SystemInfo {
        &INFO
    }
    fn new(params: &[f64]) -> Self {
        let (m, inertia, a, g) = (params[0], params[1], params[2], params[3]);
        Self { mass: Mass::Diagonal(Vector::<3>::new(m, m, inertia)), m, a, g }
    }
}

impl ChaplyginSleigh {
    #[inline]
    fn forces_at(&self, sin: f64, cos: f64) -> Forces<3, 1> {
        Forces {
            gradient: Vector::<3>::new(0.0, self.m * self.g, 0.0),
            constraint: Matrix::<1, 3>::new(-sin, cos, -self.a),
        }
    }
}

impl Mechanical<3, 1> for ChaplyginSleigh {
    #[inline]
    fn mass(&self) -> &Mass<3> {
        &self.mass
    }
    fn angle(&self) -> Option<usize> {
        Some(2)
    }
    fn quadratic_potential(&self) -> bool {
        true
    }
    #[inline]
    fn potential(&self, q: &Vector<3>) -> f64 {
        self.m * self.g * q[1]
    }
    #[inline]
    fn forces(&self, q: &Vector<3>) -> Forces<3, 1> {
        let (s, c) = q[2].sin_cos();
        self.forces_at(s, c)
    }
    #[inline]
    fn derivatives(&self, q: &Vector<3>) -> Derivatives<3, 1> {
        self.forces_and_derivatives(q).1
    }
    #[inline]
    fn forces_and_derivatives(&self, q: &Vector<3>) -> (Forces<3, 1>, Derivatives<3, 1>) {
        let (s, c) = q[2].sin_cos();
        let zero = Matrix::<1, 3>::zeros();
        let partials = [zero, zero, Matrix::<1, 3>::new(-c, -s, 0.0)];
        (self.forces_at(s, c), Derivatives { hessian: Matrix::zeros(), partials })
    }
}
