//! [`CustomSystem`]: a system given as formulas, compiled for one request and paired with
//! the code of its sizes; and the formula form of a built-in system ([`FormulaSpec::of`]).

use super::registry::{SystemCode, custom_code};
use crate::model::custom::{Compiled, CustomLimits, FormulaSpec, Passenger};
use crate::model::system::SystemInfo;
use crate::{InputError, Integral, Short};
use std::sync::Arc;

/// A compiled system given as formulas; see the module's doc.
#[derive(Debug)]
pub struct CustomSystem {
    /// As the user gave it, with the parameters at the values compiled in.
    pub spec: FormulaSpec,
    /// The compiled formulas.
    pub compiled: Arc<Compiled>,
    /// The code of its sizes.
    pub code: &'static SystemCode,
    /// The integrals it has.
    pub integrals: Vec<Integral>,
}

impl CustomSystem {
    /// Compiles `spec` with the parameter `overrides` of a request.
    pub fn compile(
        spec: &FormulaSpec,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        let compiled = Compiled::new(spec, overrides, limits)?;
        let code =
            custom_code(compiled.n + 1, compiled.r).ok_or_else(|| InputError::CustomSystem {
                field: "system.passenger".into(),
                message: "a system given as formulas needs at least 2 passenger coordinates".into(),
            })?;
        let mut integrals =
            vec![Integral::Energy, Integral::PassengerEnergy, Integral::DriverEnergy];
        if compiled.latitude {
            integrals.push(Integral::Latitude);
        }
        integrals.push(Integral::Constraint);
        let mut spec = spec.clone();
        for (p, value) in spec.parameters.iter_mut().zip(&compiled.values) {
            p.1 = *value;
        }
        Ok(Self { spec, compiled: Arc::new(compiled), code, integrals })
    }

    /// Checks the initial configuration: every formula finite there, and `A_x(ζ₀)` of full
    /// rank (its smallest singular value above 10⁻¹⁰ of its largest, and of 1).
    pub fn check_start(&self, q: &[f64]) -> Result<(), InputError> {
        let c = &self.compiled;
        let (n, r) = (c.n, c.r);
        let mut terms = vec![0.0; c.driver.outputs()];
        let (sin, cos) = q[n].sin_cos();
        c.driver.eval(&[q[n], sin, cos], &mut terms);
        let not_finite = |field: String, what: &str, value: f64| InputError::CustomSystem {
            field,
            message: format!("{what} is {} at the initial state", Short(value)),
        };
        let x = &q[..n];
        let u = match &c.passenger {
            Passenger::Quadratic { u0, b, h } => {
                let bx: f64 = b.iter().zip(x).map(|(b, x)| b * x).sum();
                let xhx: f64 =
                    (0..n).map(|i| (0..n).map(|j| x[i] * h[i * n + j] * x[j]).sum::<f64>()).sum();
                u0 + bx + 0.5 * xhx
            }
            Passenger::General(p) => {
                let mut g = vec![0.0; n];
                p.gradient.eval(x, &mut g);
                if let Some(bad) = g.iter().find(|g| !g.is_finite()) {
                    return Err(not_finite("system.passenger_potential".into(), "∇U", *bad));
                }
                let mut out = [0.0];
                p.u.eval(x, &mut out);
                out[0]
            }
        };
        if !u.is_finite() {
            return Err(not_finite("system.passenger_potential".into(), "U", u));
        }
        for (k, what) in ["V_d", "V_d′", "V_d″"].iter().enumerate() {
            if !terms[k].is_finite() {
                return Err(not_finite("system.driver_potential".into(), what, terms[k]));
            }
        }
        for i in 0..r {
            for j in 0..n {
                for (offset, what) in [(3, "this entry of A"), (3 + r * n, "its derivative dA/dζ")]
                {
                    let value = terms[offset + i * n + j];
                    if !value.is_finite() {
                        return Err(not_finite(
                            format!("system.constraints[{i}][{j}]"),
                            what,
                            value,
                        ));
                    }
                }
            }
        }
        let a = nalgebra::DMatrix::from_row_slice(r, n, &terms[3..3 + r * n]);
        let sv = a.singular_values();
        let (min, max) = (sv.min(), sv.max());
        // NaN singular values fail too.
        if min.is_nan() || min <= 1e-10 * max.max(1.0) {
            return Err(InputError::CustomSystem {
                field: "system.constraints".into(),
                message: format!(
                    "A loses rank at the initial ζ = {}: its smallest singular value is {:.3e} \
                     (largest {:.3e}); the constraint rows must be independent",
                    Short(q[n]),
                    min,
                    max
                ),
            });
        }
        Ok(())
    }
}

impl FormulaSpec {
    /// The formula form of a built-in system, its parameters at their defaults.
    pub fn of(info: &SystemInfo) -> Self {
        let f = &info.formulas;
        Self {
            name: info.name.into(),
            passenger: f.passenger.iter().map(|s| s.to_string()).collect(),
            driver: f.driver.into(),
            parameters: info.params.iter().map(|p| (p.name.to_string(), p.default)).collect(),
            passenger_potential: f.passenger_potential.into(),
            driver_potential: f.driver_potential.into(),
            constraints: f
                .constraints
                .iter()
                .map(|row| row.iter().map(|s| s.to_string()).collect())
                .collect(),
        }
    }
}
