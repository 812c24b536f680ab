//! `contact_oscillator`: McLachlan & Perlmutter's perturbed contact oscillator (J. Nonlinear
//! Sci. 16, 2006, §5.2; odelab's `ContactOscillator`), given as formulas.
//!
//! `q = (x, y, z)`, unit masses, `V = ½|q|² + (ε/2) x²z²`, constraint `ẋ + y ż = 0`. Written in
//! the general form, nhlab finds it in the paper's class with y as the driver (A depends on y
//! alone, y's column is zero, V splits): the CVT `cvt` with a quartic coupling in the
//! passenger. It conserves H, `H_y = ½(y² + ẏ²)` (the driver's energy) and `H − H_y`.

use crate::model::custom::GeneralSpec;
use crate::model::system::{Form, ParamSpec, Preset, SystemInfo};
use crate::{InputError, Integral};

static INFO: SystemInfo = SystemInfo {
    id: "contact_oscillator",
    name: "Contact oscillator (McLachlan & Perlmutter)",
    description: "ẋ + y ż = 0 with V = ½|q|² + (ε/2)x²z²: given in the general form, found in the paper's class with y as the driver.",
    source: "McLachlan & Perlmutter, J. Nonlinear Sci. 16 (2006), §5.2; odelab's ContactOscillator",
    params: &[ParamSpec {
        name: "epsilon",
        default: 0.3,
        min: -10.0,
        max: 10.0,
        min_open: false,
        max_open: false,
        description: "coupling ε of the quartic term (ε/2)x²z²",
    }],
    integrals: &[
        Integral::Energy,
        Integral::PassengerEnergy,
        Integral::DriverEnergy,
        Integral::Constraint,
        Integral::Invariant(0),
    ],
    presets: &[Preset {
        id: "mp",
        label: "McLachlan & Perlmutter's: H = 1.5, H_y = 0.5, z₀ = 0.1√2",
        params: &[("epsilon", 0.3)],
        q: &[1.402_922_255_462_067_7, 1.0, 0.141_421_356_237_309_53],
        v: &[0.0, 0.0, 0.0],
        step: 0.415_823_381_635_518_63,
        t_end: 1000.0,
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
        (&["epsilon"], params),
        "(x^2 + y^2 + z^2)/2 + epsilon*x^2*z^2/2",
        &[&["1", "0", "y"]],
    )
    .with_invariant("H_y", "(y^2 + y_dot^2)/2"))
}
