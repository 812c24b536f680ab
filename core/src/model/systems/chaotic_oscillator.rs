//! `chaotic_oscillator`: McLachlan & Perlmutter's nonholonomic quartic oscillator (J.
//! Nonlinear Sci. 16, 2006; Celledoni et al. 2019), given as formulas: non-integrable, H its
//! only integral.
//!
//! `q = (x, y₁…yₙ, z₁…zₙ)`, n = 1 or 2, unit masses,
//! `V = ½(|q|² + Σ yᵢ²zᵢ² + z₁²z₂² [n = 2])`, constraint `ẋ + Σ yᵢ żᵢ = 0`. (odelab writes
//! the row as `ẋ + Σ zᵢ żᵢ = 0`, which is the derivative of `x + ½Σzᵢ²` and so holonomic.)
//! V couples the yᵢ with the zᵢ, so it is outside the paper's class.

use crate::model::custom::GeneralSpec;
use crate::model::system::{Form, ParamSpec, Preset, SystemInfo};
use crate::{InputError, Integral};

static INFO: SystemInfo = SystemInfo {
    id: "chaotic_oscillator",
    name: "Chaotic quartic oscillator (McLachlan & Perlmutter)",
    description: "ẋ + Σ yᵢ żᵢ = 0 with V = ½(|q|² + Σ yᵢ²zᵢ² [+ z₁²z₂²]), n = 1 or 2: non-integrable, energy its only integral.",
    source: "McLachlan & Perlmutter, J. Nonlinear Sci. 16 (2006); Celledoni et al., J. Nonlinear Sci. (2019)",
    params: &[ParamSpec {
        name: "n",
        default: 1.0,
        min: 1.0,
        max: 2.0,
        min_open: false,
        max_open: false,
        description: "n = 1 or 2 pairs (yᵢ, zᵢ): 3 or 5 coordinates",
    }],
    integrals: &[Integral::Energy, Integral::Constraint],
    presets: &[
        Preset {
            id: "n1",
            label: "n = 1: (x, y, z)",
            params: &[("n", 1.0)],
            q: &[0.0, 1.0, 0.0],
            v: &[-1.0, 0.5, 1.0],
            step: 0.1,
            t_end: 1000.0,
        },
        Preset {
            id: "n2",
            label: "n = 2: (x, y₁, y₂, z₁, z₂)",
            params: &[("n", 2.0)],
            q: &[0.0, 1.0, 0.5, 0.0, 0.0],
            v: &[-1.25, 0.3, -0.2, 1.0, 0.5],
            step: 0.1,
            t_end: 1000.0,
        },
    ],
    form: Form::General(spec),
    exact: None,
};

/// Its description.
pub(crate) fn info() -> &'static SystemInfo {
    &INFO
}

fn spec(params: &[f64]) -> Result<GeneralSpec, InputError> {
    let (potential, coordinates, row): (&str, &[&str], &[&str]) = match params[0] {
        1.0 => ("(x^2 + y^2 + z^2 + y^2*z^2)/2", &["x", "y", "z"], &["1", "0", "y"]),
        2.0 => (
            "(x^2 + y1^2 + y2^2 + z1^2 + z2^2 + y1^2*z1^2 + y2^2*z2^2 + z1^2*z2^2)/2",
            &["x", "y1", "y2", "z1", "z2"],
            &["1", "0", "0", "y1", "y2"],
        ),
        n => {
            return Err(InputError::ParamOutOfRange {
                field: "params.n".into(),
                name: "n".into(),
                value: n,
                range: "1 or 2".into(),
            });
        }
    };
    Ok(GeneralSpec::of(INFO.name, coordinates, (&["n"], params), potential, &[row]))
}
