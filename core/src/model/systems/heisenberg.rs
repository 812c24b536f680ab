//! `heisenberg`: the Heisenberg system (Bloch, *Nonholonomic Mechanics and Control*; Chang et
//! al. 2018), given as formulas, with a harmonic potential in the plane.
//!
//! `q = (x, y, z)`, unit masses, `V = (k/2)(x² + y²)`, constraint `ż = y ẋ − x ẏ`. Its
//! coefficients depend on both x and y, so it is outside the paper's class (k = 0: Bloch's
//! free particle on the Heisenberg group).

use crate::model::custom::GeneralSpec;
use crate::model::system::{Form, ParamSpec, Preset, SystemInfo};
use crate::{InputError, Integral};

static INFO: SystemInfo = SystemInfo {
    id: "heisenberg",
    name: "Heisenberg system",
    description: "ż = y ẋ − x ẏ with V = (k/2)(x² + y²): its coefficients depend on two coordinates, so it is outside the paper's class.",
    source: "Bloch, Nonholonomic Mechanics and Control; Chang et al., arXiv 1811.03757",
    params: &[ParamSpec {
        name: "k",
        default: 1.0,
        min: 0.0,
        max: 100.0,
        min_open: false,
        max_open: false,
        description: "stiffness k of the planar potential (k/2)(x² + y²); 0: free",
    }],
    integrals: &[Integral::Energy, Integral::Constraint],
    presets: &[Preset {
        id: "default",
        label: "Circling the origin",
        params: &[("k", 1.0)],
        q: &[1.0, 0.0, 0.0],
        v: &[0.0, 1.0, -1.0],
        step: 0.1,
        t_end: 100.0,
    }],
    form: Form::General(spec),
    exact: None,
};

/// Its description.
pub(crate) fn info() -> &'static SystemInfo {
    &INFO
}

fn spec(params: &[f64]) -> Result<GeneralSpec, InputError> {
    Ok(GeneralSpec::of(
        INFO.name,
        &["x", "y", "z"],
        (&["k"], params),
        "k*(x^2 + y^2)/2",
        &[&["-y", "x", "1"]],
    ))
}
