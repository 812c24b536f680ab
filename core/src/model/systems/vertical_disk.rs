//! `vertical_disk`: the vertical rolling disk with its masses (odelab's `VerticalRollingDisk`;
//! Chang et al. 2018), given as formulas, with its exact solution.
//!
//! `q = (x, y, φ, θ)`: the contact point, the heading, the rolling angle;
//! `T = ½m(ẋ² + ẏ²) + ½I_flip φ̇² + ½I_rot θ̇²`, no potential; constraints `ẋ = R cos φ θ̇`,
//! `ẏ = R sin φ θ̇`. φ̇ and θ̇ are constant (`(I_rot + mR²) θ̈ = 0`), and with
//! `ρ = R θ̇/φ̇` the contact point runs on a circle:
//! `x = x₀ + ρ(sin φ − sin φ₀)`, `y = y₀ − ρ(cos φ − cos φ₀)` (a line where φ̇ = 0).
//! With unit masses nhlab finds it in the paper's class, φ the driver; otherwise it runs on
//! the general steps.

use crate::model::custom::GeneralSpec;
use crate::model::system::{Form, ParamSpec, Preset, SystemInfo};
use crate::{InputError, Integral};

const fn positive(name: &'static str, description: &'static str) -> ParamSpec {
    ParamSpec {
        name,
        default: 1.0,
        min: 0.0,
        max: 100.0,
        min_open: true,
        max_open: false,
        description,
    }
}

static INFO: SystemInfo = SystemInfo {
    id: "vertical_disk",
    name: "Vertical rolling disk (with masses)",
    description: "A disk rolling upright without slipping, with mass m, radius R and inertias I_flip, I_rot; its exact solution is known, so work–precision measures against it.",
    source: "odelab's VerticalRollingDisk; Chang et al., arXiv 1811.03757",
    params: &[
        positive("m", "mass m"),
        positive("R", "radius R"),
        positive("I_flip", "inertia I_flip about the vertical axis"),
        positive("I_rot", "inertia I_rot about the disk's axle"),
    ],
    integrals: &[
        Integral::Energy,
        Integral::PassengerEnergy,
        Integral::DriverEnergy,
        Integral::Constraint,
        Integral::Invariant(0),
        Integral::Invariant(1),
    ],
    presets: &[
        Preset {
            id: "odelab",
            label: "odelab's test: ω_φ = 2, ω_θ = 1, t = 1",
            params: &[("m", 1.0), ("R", 1.0), ("I_flip", 1.0), ("I_rot", 1.0)],
            q: &[0.0, 0.0, 0.0, 0.0],
            v: &[1.0, 0.0, 2.0, 1.0],
            step: 0.1,
            t_end: 1.0,
        },
        Preset {
            id: "long",
            label: "ω_φ = 2, ω_θ = 1 to t = 100",
            params: &[("m", 1.0), ("R", 1.0), ("I_flip", 1.0), ("I_rot", 1.0)],
            q: &[0.0, 0.0, 0.0, 0.0],
            v: &[1.0, 0.0, 2.0, 1.0],
            step: 0.1,
            t_end: 100.0,
        },
        Preset {
            id: "heavy",
            label: "m = 2, R = 0.5, I_flip = 0.25, I_rot = 0.125: outside the paper's class",
            params: &[("m", 2.0), ("R", 0.5), ("I_flip", 0.25), ("I_rot", 0.125)],
            q: &[0.0, 0.0, 0.0, 0.0],
            v: &[0.5, 0.0, 2.0, 1.0],
            step: 0.1,
            t_end: 100.0,
        },
    ],
    form: Form::General(spec),
    exact: Some(exact),
};

/// Its description.
pub(crate) fn info() -> &'static SystemInfo {
    &INFO
}

fn spec(params: &[f64]) -> Result<GeneralSpec, InputError> {
    Ok(GeneralSpec::of(
        INFO.name,
        &["x", "y", "phi", "theta"],
        (&["m", "R", "I_flip", "I_rot"], params),
        "0",
        &[&["1", "0", "0", "-R*cos(phi)"], &["0", "1", "0", "-R*sin(phi)"]],
    )
    .with_diagonal_mass(&["m", "m", "I_flip", "I_rot"])
    .with_invariant("heading_rate", "phi_dot")
    .with_invariant("rolling_rate", "theta_dot"))
}

/// The exact solution (see the module's doc).
fn exact(params: &[f64], q0: &[f64], v0: &[f64], t: f64) -> (Vec<f64>, Vec<f64>) {
    let r = params[1];
    let (w_phi, w_theta) = (v0[2], v0[3]);
    let phi = q0[2] + w_phi * t;
    let (x, y) = if w_phi == 0.0 {
        let speed = r * w_theta * t;
        (q0[0] + speed * q0[2].cos(), q0[1] + speed * q0[2].sin())
    } else {
        let rho = r * w_theta / w_phi;
        (q0[0] + rho * (phi.sin() - q0[2].sin()), q0[1] - rho * (phi.cos() - q0[2].cos()))
    };
    let q = vec![x, y, phi, q0[3] + w_theta * t];
    let v = vec![r * phi.cos() * w_theta, r * phi.sin() * w_theta, w_phi, w_theta];
    (q, v)
}
