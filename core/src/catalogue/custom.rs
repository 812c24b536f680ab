//! [`CustomSystem`]: a system given as formulas (in the paper's form or the general one, or
//! a built-in given as formulas), compiled for one scene and paired with the code of its
//! sizes and the order its code holds the coordinates in; and the formula forms of a
//! built-in system ([`FormulaSpec::of`], [`GeneralSpec::of_built_in`]).

use super::registry::{SystemCode, SystemEntry, class_code, general_code};
use crate::formula::MAX_PARAM_INPUTS;
use crate::model::custom::{
    Compiled, CustomLimits, FormulaSpec, Formulated, GeneralSpec, Invariants, MassSpec, Parameters,
    Passenger, Structure, parameter_values,
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
    /// The same with its parameters' values replaced by `values` (in order).
    pub fn with_values(&self, values: &[f64]) -> Self {
        let mut spec = self.clone();
        for (p, value) in spec.parameters_mut().iter_mut().zip(values) {
            p.1 = *value;
        }
        spec
    }
}

/// A compiled system given as formulas; see the module's doc.
#[derive(Debug, Clone)]
pub struct CustomSystem {
    /// As given (the parameters at the values it declares; see `values`), shared by the
    /// systems bound from one compilation.
    pub spec: Arc<SystemSpec>,
    /// The parameters' values it runs with, in the spec's order.
    pub values: Vec<f64>,
    /// How the parameters enter its code: folded in, or inputs it is bound to
    /// ([`bind`](Self::bind)).
    pub parameters: Parameters,
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
    /// Compiles `spec` with the parameter `overrides` of a request, folded into the code.
    pub fn compile(
        spec: &FormulaSpec,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        Self::compile_with(spec, overrides, limits, Parameters::Folded)
    }

    /// [`compile`](Self::compile), the parameters entering the code as `parameters` says
    /// (inputs only where there are at most [`MAX_PARAM_INPUTS`]; folded otherwise).
    pub fn compile_with(
        spec: &FormulaSpec,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
        parameters: Parameters,
    ) -> Result<Self, InputError> {
        let parameters = usable(parameters, spec.parameters.len());
        let compiled = Compiled::new(spec, overrides, limits, parameters)?;
        let code =
            class_code(compiled.n + 1, compiled.r).ok_or_else(|| InputError::CustomSystem {
                field: "system.passenger".into(),
                message: "a system given as formulas needs at least 2 passenger coordinates".into(),
            })?;
        let dof = compiled.n + 1;
        let driver = compiled.n;
        let values = compiled.values.clone();
        let structure = Structure::Class { compiled: Arc::new(compiled), driver };
        let system = Self {
            spec: Arc::new(SystemSpec::Coupled(spec.clone())),
            values,
            parameters,
            integrals: integrals_of(&structure, 0),
            structure,
            code,
            invariants: None,
            order: (0..dof).collect(),
            dof,
            not_class: None,
            built_in: None,
        };
        system.bound(parameters, overrides, limits)
    }

    /// Compiles `spec`, given in the general form, with the parameter `overrides` of a
    /// request: the paper's class where nhlab finds it, the general class otherwise.
    pub fn compile_general(
        spec: &GeneralSpec,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        Self::compile_general_with(spec, overrides, limits, Parameters::Folded)
    }

    /// [`compile_general`](Self::compile_general), the parameters entering the code as
    /// `parameters` says (as [`compile_with`](Self::compile_with)).
    pub fn compile_general_with(
        spec: &GeneralSpec,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
        parameters: Parameters,
    ) -> Result<Self, InputError> {
        let parameters = usable(parameters, spec.parameters.len());
        let f = Formulated::new(spec, overrides, limits, parameters)?;
        let code = match &f.structure {
            Structure::Class { .. } => class_code(f.n, f.m),
            Structure::General(_) => general_code(f.n, f.m),
        }
        .ok_or_else(|| InputError::CustomSystem {
            field: "system.coordinates".into(),
            message: format!("no code for {} coordinates and {} constraints", f.n, f.m),
        })?;
        let system = Self {
            spec: Arc::new(SystemSpec::General(spec.clone())),
            values: f.values,
            parameters,
            integrals: integrals_of(
                &f.structure,
                f.invariants.as_ref().map_or(0, |i| i.names().len()),
            ),
            structure: f.structure,
            code,
            invariants: f.invariants,
            order: f.order,
            dof: f.n,
            not_class: f.not_class,
            built_in: None,
        };
        system.bound(parameters, overrides, limits)
    }

    /// The system as compiled, its code bound to the values of `overrides` where the
    /// parameters are its inputs (code reading inputs it is not given never runs).
    fn bound(
        self,
        parameters: Parameters,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        match parameters {
            Parameters::Folded => Ok(self),
            Parameters::Inputs => self.bind(overrides, limits),
        }
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

    /// The same system with the parameter `overrides` of another request (over the values
    /// its spec declares): its code bound to the new values where the parameters are its
    /// inputs (M evaluated and checked again), compiled again where they are folded in.
    pub fn bind(
        &self,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        if self.parameters == Parameters::Folded {
            let mut system = match &*self.spec {
                SystemSpec::Coupled(s) => Self::compile(s, overrides, limits)?,
                SystemSpec::General(s) => Self::compile_general(s, overrides, limits)?,
            };
            system.built_in = self.built_in;
            return Ok(system);
        }
        let values = parameter_values(self.spec.parameters(), overrides)?;
        let params: Arc<[f64]> = values.as_slice().into();
        let structure = match (&self.structure, &*self.spec) {
            (Structure::Class { compiled, driver }, _) => {
                Structure::Class { compiled: Arc::new(compiled.bind(&values)), driver: *driver }
            }
            (Structure::General(g), SystemSpec::General(spec)) => {
                Structure::General(Arc::new(g.bind(spec, &values, limits)?))
            }
            (Structure::General(_), SystemSpec::Coupled(_)) => {
                unreachable!("the paper's form compiles to the paper's class")
            }
        };
        let invariants = self.invariants.as_ref().map(|i| Arc::new(i.bind(&params)));
        Ok(Self {
            values,
            integrals: integrals_of(&structure, invariants.as_ref().map_or(0, |i| i.names().len())),
            structure,
            invariants,
            ..self.clone()
        })
    }

    /// The spec with the parameters at the values it runs with (as a request echoes it).
    pub fn spec_at_values(&self) -> SystemSpec {
        self.spec.with_values(&self.values)
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
        self.to_user_into(q, &mut out);
        out
    }

    /// [`to_user`](Self::to_user) into `out` (`dof` long).
    pub fn to_user_into(&self, q: &[f64], out: &mut [f64]) {
        for (i, &j) in self.order.iter().enumerate() {
            out[j] = q[i];
        }
    }

    /// Checks the initial configuration: every formula finite there, and `A_x(ζ₀)` of full
    /// rank (its smallest singular value above 10⁻¹⁰ of its largest, and of 1).
    pub fn check_start(&self, q: &[f64]) -> Result<(), InputError> {
        let Some(c) =
            self.class_compiled().filter(|_| matches!(*self.spec, SystemSpec::Coupled(_)))
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

/// The integrals of a system compiled to `structure` with `invariants` invariants: H, E and
/// h where it is in the paper's class (the latitude where the class's definition holds), the
/// constraint, its invariants.
fn integrals_of(structure: &Structure, invariants: usize) -> Vec<Integral> {
    let mut out = vec![Integral::Energy];
    if let Structure::Class { compiled, .. } = structure {
        out.extend([Integral::PassengerEnergy, Integral::DriverEnergy]);
        if compiled.latitude {
            out.push(Integral::Latitude);
        }
    }
    out.push(Integral::Constraint);
    out.extend((0..invariants).map(|k| Integral::Invariant(k as u8)));
    out
}

/// `parameters`, or folded where there are too many parameters to be inputs.
fn usable(parameters: Parameters, count: usize) -> Parameters {
    if count > MAX_PARAM_INPUTS { Parameters::Folded } else { parameters }
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
