//! `nonholonomic_oscillator`: the nonholonomic oscillator (Bloch, *Nonholonomic Mechanics and
//! Control*; Chang et al. 2018), given as formulas.
//!
//! `q = (x, y, z)`, unit masses, `V = ½y²`, constraint `ż = y ẋ`. Found in the paper's class
//! with y as the driver (a harmonic oscillator on its own) and a free passenger (x, z).

use crate::model::custom::GeneralSpec;
use crate::model::system::{Form, Preset, SystemInfo};
use crate::{InputError, Integral};

static INFO: SystemInfo = SystemInfo {
    id: "nonholonomic_oscillator",
    name: "Nonholonomic oscillator",
    description: "ż = y ẋ with V = ½y²: given in the general form, found in the paper's class with y as the driver.",
    source: "Bloch, Nonholonomic Mechanics and Control; Chang et al., arXiv 1811.03757",
    params: &[],
    integrals: &[
        Integral::Energy,
        Integral::PassengerEnergy,
        Integral::DriverEnergy,
        Integral::Constraint,
    ],
    presets: &[Preset {
        id: "default",
        label: "y swinging, x and z sliding",
        params: &[],
        q: &[0.0, 1.0, 0.0],
        v: &[1.0, 0.0, 1.0],
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
    Ok(GeneralSpec::of(INFO.name, &["x", "y", "z"], (&[], params), "y^2/2", &[&["-y", "0", "1"]]))
}
