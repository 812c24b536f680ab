//! A system given in the general form ([`GeneralSpec`], `docs/model.md` §10) checked and
//! compiled: names and sizes, the parameters' values in place, M evaluated and checked
//! symmetric positive definite, V and A parsed into one graph, the paper's class looked for
//! ([`detect`](super::detect)), and then either the class's compilation (with the coordinates
//! reordered, ζ last) or the general one ([`GeneralCompiled`]: V, ∇V, ∇²V, A and ∂A/∂q as
//! tapes). The invariants are compiled in either case ([`Invariants`]).
//!
//! Where the parameters are inputs of the code ([`Parameters::Inputs`]), M is still numbers
//! per set of values ([`mass_matrix`], evaluated and checked at each binding), and the class
//! is looked for only where M is the identity whatever the values.

use super::compile::{Compiled, Parameters, is_identifier, parameter_values};
use super::detect::{self, ClassFound};
use super::general_spec::{GeneralSpec, MAX_COORDINATES, MassEntry, MassSpec};
use super::invariants::Invariants;
use super::spec::CustomLimits;
use crate::InputError;
use crate::formula::derive::Derivative;
use crate::formula::parse::{Name, Names, parse};
use crate::formula::{FormulaError, Function, Graph, Id, Tape};
use crate::model::integral::{Integral, MAX_INVARIANTS};
use nalgebra::DMatrix;
use std::sync::Arc;

/// A system of the general class outside the paper's class (or kept out of it), compiled.
#[derive(Debug, Clone)]
pub struct GeneralCompiled {
    /// Coordinates N.
    pub n: usize,
    /// Constraints m.
    pub m: usize,
    /// M, N×N row by row.
    pub mass: Vec<f64>,
    /// `[V]`.
    pub potential: Function,
    /// `[∇V (N), A (m×N row by row)]`.
    pub forces: Function,
    /// `[∇V, A, ∇²V (upper triangle, row by row), ∂A/∂q_k for k = 1…N (each m×N row by row)]`.
    pub terms: Function,
    /// `∇²V` is constant.
    pub quadratic: bool,
}

/// What a system in the general form compiles to.
#[derive(Debug, Clone)]
pub enum Structure {
    /// The paper's class, found: the class's compilation, its coordinates reordered (the
    /// passengers in the user's order, the driver last).
    Class {
        /// The class's compilation.
        compiled: Arc<Compiled>,
        /// The user's index of the driver.
        driver: usize,
    },
    /// The general class.
    General(Arc<GeneralCompiled>),
}

/// A system in the general form, checked and compiled; see the module's doc.
#[derive(Debug, Clone)]
pub struct Formulated {
    /// The coordinates N (as the user gave them).
    pub n: usize,
    /// The constraints m.
    pub m: usize,
    /// The parameters' values, in the spec's order.
    pub values: Vec<f64>,
    /// How the parameters enter the code.
    pub parameters: Parameters,
    /// M, N×N, in the user's order.
    pub mass: DMatrix<f64>,
    /// What it runs as.
    pub structure: Structure,
    /// Why it is not taken as the paper's class, where it is not.
    pub not_class: Option<String>,
    /// Its invariants, compiled on the internal order's (q, q̇).
    pub invariants: Option<Arc<Invariants>>,
    /// `order[i]`: the user's index of the coordinate the run holds at i.
    pub order: Vec<usize>,
}

fn bad(field: impl Into<String>, message: impl Into<String>) -> InputError {
    InputError::CustomSystem { field: field.into(), message: message.into() }
}

/// The names of one formula of a system in the general form.
struct Scope<'a> {
    spec: &'a GeneralSpec,
    values: &'a [f64],
    parameters: Parameters,
    /// Whether the coordinates may be named (not in M).
    coordinates: bool,
}

impl Names for Scope<'_> {
    fn resolve(&self, name: &str) -> Option<Name> {
        if let Some(i) = self.spec.parameters.iter().position(|(p, _)| p == name) {
            return Some(self.parameters.name(i, self.values));
        }
        if let Some(i) = self.spec.coordinates.iter().position(|c| c == name) {
            return Some(if self.coordinates {
                Name::Var(i as u16)
            } else {
                Name::Forbidden(format!(
                    "'{name}' is a coordinate; M is constant in nhlab's class: its entries are \
                     numbers or formulas in the parameters (docs/model.md §1)"
                ))
            });
        }
        let velocity = name.strip_suffix("_dot");
        if velocity.is_some_and(|c| self.spec.coordinates.iter().any(|x| x == c)) {
            return Some(Name::Forbidden(format!(
                "'{name}' is a velocity; velocities appear in invariants only (V and A are \
                 functions of q, docs/model.md §1)"
            )));
        }
        None
    }
    fn allowed(&self) -> String {
        let mut names: Vec<&str> = Vec::new();
        if self.coordinates {
            names.extend(self.spec.coordinates.iter().map(String::as_str));
        }
        names.extend(self.spec.parameters.iter().map(|(p, _)| p.as_str()));
        format!(
            "it may name {} and pi",
            if names.is_empty() { "no name".into() } else { names.join(", ") }
        )
    }
}

impl Formulated {
    /// Checks and compiles `spec` with its parameters overridden by `overrides` (field
    /// `params.NAME`). Errors name the field under `system.`.
    pub fn new(
        spec: &GeneralSpec,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
        parameters: Parameters,
    ) -> Result<Self, InputError> {
        let (n, m) = check_shape(spec, limits)?;
        let values = parameter_values(&spec.parameters, overrides)?;
        let lim = &limits.formula;
        let formula = |g: &mut Graph, field: String, text: &str, scope: &Scope<'_>| {
            parse(g, text, scope, lim).map_err(|error| InputError::Formula { field, error })
        };
        let mass = mass_matrix(spec, &values, limits)?;
        let scope = Scope { spec, values: &values, parameters, coordinates: true };
        let mut g = Graph::new();
        let v = formula(&mut g, "system.potential".into(), &spec.potential, &scope)?;
        let mut a = Vec::with_capacity(m * n);
        for (i, row) in spec.constraints.iter().enumerate() {
            for (j, text) in row.iter().enumerate() {
                a.push(formula(&mut g, format!("system.constraints[{i}][{j}]"), text, &scope)?);
            }
        }
        let unit_mass = mass == DMatrix::identity(n, n)
            && (parameters == Parameters::Folded || !mass_reads_parameters(spec, limits)?);
        let found = if spec.detect_class {
            detect::find(&mut g, v, &a, &spec.coordinates, m, unit_mass)
        } else {
            Err("detect_class is false: the general steps run".into())
        };
        let (structure, not_class, order) = match found {
            Ok(ClassFound { driver }) => {
                let compiled = detect::class_compilation(
                    &g,
                    v,
                    &a,
                    (n, m),
                    driver,
                    (&values, parameters),
                    limits,
                )?;
                let order: Vec<usize> = (0..n).filter(|&i| i != driver).chain([driver]).collect();
                (Structure::Class { compiled: Arc::new(compiled), driver }, None, order)
            }
            Err(why) => {
                let compiled = general_compilation(g, v, &a, (n, m), mass.as_slice(), limits)?;
                (Structure::General(Arc::new(compiled)), Some(why), (0..n).collect())
            }
        };
        let invariants = if spec.invariants.is_empty() {
            None
        } else {
            Some(Arc::new(Invariants::compile(spec, (&values, parameters), &order, limits)?))
        };
        // M row by row in the user's order (nalgebra stores by columns; M is symmetric).
        let mass = DMatrix::from_row_slice(n, n, mass.as_slice());
        Ok(Self { n, m, values, parameters, mass, structure, not_class, invariants, order })
    }
}

impl GeneralCompiled {
    /// The same code bound to other values of its parameters (which are
    /// [inputs](Parameters::Inputs)), M evaluated from `spec` and checked at them.
    pub fn bind(
        &self,
        spec: &GeneralSpec,
        values: &[f64],
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        let mass = mass_matrix(spec, values, limits)?;
        let params: Arc<[f64]> = values.into();
        Ok(Self {
            n: self.n,
            m: self.m,
            mass: mass.as_slice().to_vec(),
            potential: self.potential.bind(&params),
            forces: self.forces.bind(&params),
            terms: self.terms.bind(&params),
            quadratic: self.quadratic,
        })
    }
}

/// Whether an entry of M is a formula that reads a parameter (parse errors are M's, as
/// [`mass_matrix`] reports them).
fn mass_reads_parameters(spec: &GeneralSpec, limits: &CustomLimits) -> Result<bool, InputError> {
    let values = vec![0.0; spec.parameters.len()];
    let scope = Scope { spec, values: &values, parameters: Parameters::Inputs, coordinates: false };
    let entries: Vec<&MassEntry> = match &spec.mass {
        MassSpec::Identity => Vec::new(),
        MassSpec::Diagonal(d) => d.iter().collect(),
        MassSpec::Full(rows) => rows.iter().flatten().collect(),
    };
    for e in entries {
        if let MassEntry::Formula(text) = e {
            let mut g = Graph::new();
            let id = parse(&mut g, text, &scope, &limits.formula)
                .map_err(|error| InputError::Formula { field: "system.mass".into(), error })?;
            if g.constant(id).is_none() {
                return Ok(true);
            }
        }
    }
    Ok(false)
}

/// M from the spec, each entry a number or a formula in the parameters, checked symmetric
/// positive definite (field `system.mass`); row by row.
fn mass_matrix(
    spec: &GeneralSpec,
    values: &[f64],
    limits: &CustomLimits,
) -> Result<DMatrix<f64>, InputError> {
    let n = spec.coordinates.len();
    let scope = Scope { spec, values, parameters: Parameters::Folded, coordinates: false };
    let entry = |e: &MassEntry, field: String| -> Result<f64, InputError> {
        let x = match e {
            MassEntry::Number(x) => *x,
            MassEntry::Formula(text) => {
                let mut g = Graph::new();
                let id = parse(&mut g, text, &scope, &limits.formula)
                    .map_err(|error| InputError::Formula { field: field.clone(), error })?;
                g.constant(id).unwrap_or(f64::NAN)
            }
        };
        if !x.is_finite() {
            return Err(InputError::NonFinite { field, value: x });
        }
        Ok(x)
    };
    let mut mass = DMatrix::<f64>::identity(n, n);
    match &spec.mass {
        MassSpec::Identity => {}
        MassSpec::Diagonal(d) => {
            if d.len() != n {
                return Err(bad(
                    "system.mass",
                    format!("a diagonal mass has one entry per coordinate ({n}), got {}", d.len()),
                ));
            }
            for (i, e) in d.iter().enumerate() {
                mass[(i, i)] = entry(e, format!("system.mass[{i}]"))?;
            }
        }
        MassSpec::Full(rows) => {
            if rows.len() != n || rows.iter().any(|r| r.len() != n) {
                return Err(bad(
                    "system.mass",
                    format!("the mass matrix is {n}×{n} (one row of {n} per coordinate)"),
                ));
            }
            for (i, row) in rows.iter().enumerate() {
                for (j, e) in row.iter().enumerate() {
                    mass[(i, j)] = entry(e, format!("system.mass[{i}][{j}]"))?;
                }
            }
            for i in 0..n {
                for j in 0..i {
                    if mass[(i, j)] != mass[(j, i)] {
                        return Err(bad(
                            format!("system.mass[{i}][{j}]"),
                            format!(
                                "M must be symmetric: M[{i}][{j}] = {} but M[{j}][{i}] = {}",
                                mass[(i, j)],
                                mass[(j, i)]
                            ),
                        ));
                    }
                }
            }
        }
    }
    let smallest = mass.symmetric_eigenvalues().min();
    let largest = mass.symmetric_eigenvalues().amax();
    if smallest.is_nan() || smallest <= 1e-12 * largest.max(1.0) {
        return Err(bad(
            "system.mass",
            format!(
                "M must be positive definite: its smallest eigenvalue is {smallest:.3e} (largest \
                 {largest:.3e})"
            ),
        ));
    }
    // Row by row: the transpose of nalgebra's column storage, which M's symmetry makes equal.
    Ok(mass)
}

/// The general compilation: ∇V, ∇²V and ∂A/∂q by symbolic differentiation, and the tapes.
fn general_compilation(
    mut g: Graph,
    v: Id,
    a: &[Id],
    (n, m): (usize, usize),
    mass: &[f64],
    limits: &CustomLimits,
) -> Result<GeneralCompiled, InputError> {
    let lim = &limits.formula;
    let too_large = || InputError::Formula {
        field: "system".into(),
        error: FormulaError::TooLarge { limit: lim.max_nodes },
    };
    let mut by_var: Vec<Derivative> = (0..n).map(|i| Derivative::new(i as u16)).collect();
    let mut gradient = Vec::with_capacity(n);
    for d in &mut by_var {
        gradient.push(d.of(&mut g, v));
        if g.len() > lim.max_nodes {
            return Err(too_large());
        }
    }
    let mut hessian = Vec::with_capacity(n * (n + 1) / 2);
    for (i, &gi) in gradient.iter().enumerate() {
        for d in &mut by_var[i..] {
            hessian.push(d.of(&mut g, gi));
        }
        if g.len() > lim.max_nodes {
            return Err(too_large());
        }
    }
    let mut partials = Vec::with_capacity(n * m * n);
    for d in &mut by_var {
        partials.extend(a.iter().map(|&e| d.of(&mut g, e)));
        if g.len() > lim.max_nodes {
            return Err(too_large());
        }
    }
    let quadratic = hessian.iter().all(|&h| g.constant(h).is_some());
    let mut forces = gradient.clone();
    forces.extend(a);
    let mut terms = forces.clone();
    terms.extend(&hessian);
    terms.extend(&partials);
    let native = limits.native;
    Ok(GeneralCompiled {
        n,
        m,
        mass: mass.to_vec(),
        potential: Function::new(Tape::compile(&g, &[v], n), native),
        forces: Function::new(Tape::compile(&g, &forces, n), native),
        terms: Function::new(Tape::compile(&g, &terms, n), native),
        quadratic,
    })
}

/// Sizes and names: 1 to 12 coordinates, 1 to N − 1 constraint rows of N entries, distinct
/// identifiers (no coordinate named as another's velocity), at most `max_parameters`
/// parameters with finite values, at most [`MAX_INVARIANTS`] invariants.
fn check_shape(spec: &GeneralSpec, limits: &CustomLimits) -> Result<(usize, usize), InputError> {
    let n = spec.coordinates.len();
    if !(1..=MAX_COORDINATES).contains(&n) {
        return Err(bad(
            "system.coordinates",
            format!("a system has 1 to {MAX_COORDINATES} coordinates, got {n}"),
        ));
    }
    let m = spec.constraints.len();
    if m == 0 || m >= n {
        return Err(bad(
            "system.constraints",
            format!(
                "{n} coordinate{} allow 1 to N − 1 = {} constraint rows, got {m}: the constrained \
                 motion must keep at least one direction (docs/model.md §1)",
                if n == 1 { "" } else { "s" },
                n.saturating_sub(1)
            ),
        ));
    }
    for (i, row) in spec.constraints.iter().enumerate() {
        if row.len() != n {
            return Err(bad(
                format!("system.constraints[{i}]"),
                format!(
                    "each constraint row has one entry per coordinate ({n}), got {}",
                    row.len()
                ),
            ));
        }
    }
    if spec.parameters.len() > limits.max_parameters {
        return Err(bad(
            "system.parameters",
            format!(
                "at most {} parameters are allowed, got {}",
                limits.max_parameters,
                spec.parameters.len()
            ),
        ));
    }
    if spec.invariants.len() > MAX_INVARIANTS {
        return Err(bad(
            "system.invariants",
            format!(
                "at most {MAX_INVARIANTS} invariants are allowed, got {}",
                spec.invariants.len()
            ),
        ));
    }
    let mut seen: Vec<String> = Vec::new();
    let names = spec
        .coordinates
        .iter()
        .enumerate()
        .map(|(i, c)| (format!("system.coordinates[{i}]"), c.as_str()))
        .chain(spec.parameters.iter().map(|(p, _)| (format!("system.parameters.{p}"), p.as_str())));
    for (field, name) in names {
        if !is_identifier(name) {
            return Err(bad(
                field,
                format!(
                    "'{name}' is not a usable name: a name starts with a letter or '_', goes on \
                     with letters, digits or '_', and is not pi or a function"
                ),
            ));
        }
        if seen.iter().any(|s| s == name) {
            return Err(bad(field, format!("'{name}' is named twice")));
        }
        seen.push(name.into());
    }
    // A velocity's name, `x_dot`, must not be another name.
    for c in &spec.coordinates {
        let dot = format!("{c}_dot");
        if let Some(clash) = seen.iter().find(|s| **s == dot) {
            return Err(bad(
                "system.coordinates",
                format!("'{clash}' is the name of {c}'s velocity; name it otherwise"),
            ));
        }
    }
    for (p, value) in &spec.parameters {
        if !value.is_finite() {
            return Err(InputError::NonFinite {
                field: format!("system.parameters.{p}"),
                value: *value,
            });
        }
    }
    let fixed = Integral::ALL.map(Integral::id);
    for (k, (name, _)) in spec.invariants.iter().enumerate() {
        let field = format!("system.invariants.{name}");
        if !is_identifier(name) || fixed.contains(&name.as_str()) {
            return Err(bad(
                field,
                format!(
                    "'{name}' cannot name an invariant: it must be an identifier and not one of \
                     {}",
                    fixed.join(", ")
                ),
            ));
        }
        if spec.invariants[..k].iter().any(|(other, _)| other == name) {
            return Err(bad(field, format!("the invariant '{name}' is named twice")));
        }
    }
    Ok((n, m))
}
