//! [`CustomSystem`]: a system given as formulas (in the paper's form or the general one, or
//! a built-in given as formulas), compiled for one scene and paired with the code of its
//! sizes and the order its code holds the coordinates in; and the formula forms of a
//! built-in system ([`FormulaSpec::of`], [`GeneralSpec::of_built_in`]).

use super::registry::{SystemCode, SystemEntry, class_code, general_code};
use crate::model::custom::{
    Compiled, CustomLimits, FormulaSpec, Formulated, GeneralSpec, Invariants, MassSpec, Passenger,
    Structure,
};
use crate::model::system::{Form, SystemInfo};
use crate::{InputError, Integral, Short};
use std::sync::Arc;

/// A system as formulas, in either form.
#[derive(Debug, Clone, PartialEq)]
pub enum SystemSpec {
    /// The paper's form: passenger, driver, U, V_d, A's passenger columns.
    Coupled(FormulaSpec),
    /// The general form: coordinates, M, V, A, invariants.
    General(GeneralSpec),
}

impl SystemSpec {
    /// Its label.
    pub fn name(&self) -> &str {
        match self {
            Self::Coupled(s) => &s.name,
            Self::General(s) => &s.name,
        }
    }
    /// Its parameters with their values.
    pub fn parameters(&self) -> &[(String, f64)] {
        match self {
            Self::Coupled(s) => &s.parameters,
            Self::General(s) => &s.parameters,
        }
    }
    fn parameters_mut(&mut self) -> &mut [(String, f64)] {
        match self {
            Self::Coupled(s) => &mut s.parameters,
            Self::General(s) => &mut s.parameters,
        }
    }
}

/// A compiled system given as formulas; see the module's doc.
#[derive(Debug)]
pub struct CustomSystem {
    /// As given, with the parameters at the values compiled in.
    pub spec: SystemSpec,
    /// What it compiled to.
    pub structure: Structure,
    /// The code of its sizes.
    pub code: &'static SystemCode,
    /// The integrals it has.
    pub integrals: Vec<Integral>,
    /// Its invariants.
    pub invariants: Option<Arc<Invariants>>,
    /// `order[i]`: the user's index of the coordinate its code holds at i (the code may hold
    /// more, padding, after these).
    pub order: Vec<usize>,
    /// Its coordinates, as given.
    pub dof: usize,
    /// Why the paper's class was not found in it, for one given in the general form.
    pub not_class: Option<String>,
    /// The built-in it is, for a built-in given as formulas.
    pub built_in: Option<&'static SystemEntry>,
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
            class_code(compiled.n + 1, compiled.r).ok_or_else(|| InputError::CustomSystem {
                field: "system.passenger".into(),
                message: "a system given as formulas needs at least 2 passenger coordinates".into(),
            })?;
        let mut integrals =
            vec![Integral::Energy, Integral::PassengerEnergy, Integral::DriverEnergy];
        if compiled.latitude {
            integrals.push(Integral::Latitude);
        }
        integrals.push(Integral::Constraint);
        let mut spec = SystemSpec::Coupled(spec.clone());
        for (p, value) in spec.parameters_mut().iter_mut().zip(&compiled.values) {
            p.1 = *value;
        }
        let dof = compiled.n + 1;
        let driver = compiled.n;
        Ok(Self {
            spec,
            structure: Structure::Class { compiled: Arc::new(compiled), driver },
            code,
            integrals,
            invariants: None,
            order: (0..dof).collect(),
            dof,
            not_class: None,
            built_in: None,
        })
    }

    /// Compiles `spec`, given in the general form, with the parameter `overrides` of a
    /// request: the paper's class where nhlab finds it, the general class otherwise.
    pub fn compile_general(
        spec: &GeneralSpec,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        let f = Formulated::new(spec, overrides, limits)?;
        let code = match &f.structure {
            Structure::Class { .. } => class_code(f.n, f.m),
            Structure::General(_) => general_code(f.n, f.m),
        }
        .ok_or_else(|| InputError::CustomSystem {
            field: "system.coordinates".into(),
            message: format!("no code for {} coordinates and {} constraints", f.n, f.m),
        })?;
        let mut spec = SystemSpec::General(spec.clone());
        for (p, value) in spec.parameters_mut().iter_mut().zip(&f.values) {
            p.1 = *value;
        }
        let integrals = f.integrals();
        Ok(Self {
            spec,
            structure: f.structure,
            code,
            integrals,
            invariants: f.invariants,
            order: f.order,
            dof: f.n,
            not_class: f.not_class,
            built_in: None,
        })
    }

    /// A built-in given as formulas, compiled for these parameter values (in the order of
    /// its `params`).
    pub fn built_in(
        entry: &'static SystemEntry,
        params: &[f64],
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        let Form::General(spec) = entry.info().form else {
            unreachable!("a built-in given as formulas has the general form")
        };
        let mut system = Self::compile_general(&spec(params)?, &[], limits)?;
        system.built_in = Some(entry);
        Ok(system)
    }

    /// The class's compilation, where it runs as the paper's class.
    pub fn class_compiled(&self) -> Option<&Arc<Compiled>> {
        match &self.structure {
            Structure::Class { compiled, .. } => Some(compiled),
            Structure::General(_) => None,
        }
    }

    /// `q` in the user's order as the code holds it (reordered, padded with zeros).
    pub fn to_internal(&self, q: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.code.dof];
        for (i, &j) in self.order.iter().enumerate() {
            out[i] = q[j];
        }
        out
    }

    /// `q` as the code holds it, in the user's order.
    pub fn to_user(&self, q: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.dof];
        for (i, &j) in self.order.iter().enumerate() {
            out[j] = q[i];
        }
        out
    }

    /// Checks the initial configuration: every formula finite there, and `A_x(ζ₀)` of full
    /// rank (its smallest singular value above 10⁻¹⁰ of its largest, and of 1).
    pub fn check_start(&self, q: &[f64]) -> Result<(), InputError> {
        let Some(c) = self.class_compiled().filter(|_| matches!(self.spec, SystemSpec::Coupled(_)))
        else {
            return Ok(());
        };
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
    /// The paper's formula form of a built-in of the paper's class, its parameters at their
    /// defaults; `None` for the others.
    pub fn of(info: &SystemInfo) -> Option<Self> {
        let Form::Coupled(f) = &info.form else { return None };
        Some(Self {
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
        })
    }
}

impl GeneralSpec {
    /// The general form of a built-in, its parameters at `params` (in the order of its
    /// `params`): its own, or the paper's form written out (`q = (x, ζ)`, `V = U + V_d`, A
    /// with a zero driver column).
    pub fn of_built_in(info: &SystemInfo, params: &[f64]) -> Result<Self, InputError> {
        match &info.form {
            Form::General(spec) => spec(params),
            Form::Coupled(f) => {
                let mut coordinates: Vec<String> =
                    f.passenger.iter().map(|s| s.to_string()).collect();
                coordinates.push(f.driver.into());
                Ok(Self {
                    name: info.name.into(),
                    coordinates,
                    parameters: info
                        .params
                        .iter()
                        .map(|p| p.name.to_string())
                        .zip(params.iter().copied())
                        .collect(),
                    mass: MassSpec::Identity,
                    potential: format!("({}) + ({})", f.passenger_potential, f.driver_potential),
                    constraints: f
                        .constraints
                        .iter()
                        .map(|row| {
                            row.iter().map(|s| s.to_string()).chain(["0".to_string()]).collect()
                        })
                        .collect(),
                    invariants: Vec::new(),
                    detect_class: true,
                })
            }
        }
    }
}
