//! [`Compiled`]: a [`FormulaSpec`] checked (names, sizes, which formula may name what),
//! parsed with its parameters' values in place, differentiated symbolically (∇U, ∇²U, V_d′,
//! V_d″, dA/dζ) and compiled into tapes; with what the methods' fast paths ask of a system
//! (U or V_d quadratic, U absent) read off the derivatives, which are then constants.
//!
//! With [`Parameters::Inputs`] the parameters are variables of the code instead
//! ([`PARAM_VAR`] on), compiled once and bound to each set of values ([`Compiled::bind`]):
//! what the fast paths ask is then decided for the formulas as written, whatever the values
//! (U is taken as quadratic only where neither its second derivatives nor U itself depend on
//! a parameter).

use super::spec::{CustomLimits, FormulaSpec, MAX_PASSENGERS};
use crate::InputError;
use crate::formula::derive::Derivative;
use crate::formula::graph::Node;
use crate::formula::parse::{Name, Names, parse};
use crate::formula::{Func, Function, Graph, Id, PARAM_VAR, Tape};
use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// How a system's parameters enter its code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Parameters {
    /// Their values are constants folded into the code: fastest for one set of values.
    #[default]
    Folded,
    /// They are inputs of the code ([`PARAM_VAR`] on), bound per set of values: one
    /// compilation serves them all.
    Inputs,
}

impl Parameters {
    /// The name of parameter `i` in a formula, whose value is `values[i]`.
    pub(crate) fn name(self, i: usize, values: &[f64]) -> Name {
        match self {
            Self::Folded => Name::Value(values[i]),
            Self::Inputs => Name::Var(PARAM_VAR + i as u16),
        }
    }
}

/// The variables of a graph at the coordinates `coords` and the parameters at `values` (read
/// only where they are inputs).
pub(crate) fn point(coords: &[f64], values: &[f64]) -> Vec<f64> {
    let mut vars = vec![0.0; PARAM_VAR as usize + values.len()];
    vars[..coords.len()].copy_from_slice(coords);
    vars[PARAM_VAR as usize..].copy_from_slice(values);
    vars
}

/// Whether `e` depends on a coordinate (a variable before the parameters).
fn reads_coordinates(g: &Graph, e: Id) -> bool {
    g.variables(e).first().is_some_and(|&v| v < PARAM_VAR)
}

/// U as `u₀ + b·x + ½ xᵀH x` from `[U, ∇U, ∇²U (upper triangle)]` at x = 0 (`code`).
fn quadratic_at_zero(code: &Function, n: usize) -> Passenger {
    let mut out = vec![0.0; code.outputs()];
    code.eval(&vec![0.0; n], &mut out);
    let mut h = vec![0.0; n * n];
    let mut k = 1 + n;
    for i in 0..n {
        for j in i..n {
            (h[i * n + j], h[j * n + i]) = (out[k], out[k]);
            k += 1;
        }
    }
    Passenger::Quadratic { u0: out[0], b: out[1..=n].to_vec(), h }
}

/// Whether the latitude's definition holds (`docs/model.md` §5): two passengers, one
/// constraint, `U = ½|x|²` up to a constant.
fn latitude_holds(n: usize, r: usize, passenger: &Passenger) -> bool {
    n == 2
        && r == 1
        && matches!(passenger, Passenger::Quadratic { b, h, .. }
            if b.iter().all(|&x| x == 0.0) && h == &[1.0, 0.0, 0.0, 1.0])
}

/// The passenger potential, compiled.
#[derive(Debug, Clone)]
pub enum Passenger {
    /// `U = u₀ + b·x + ½ xᵀH x` (every second derivative a constant).
    Quadratic {
        /// `U(0)`.
        u0: f64,
        /// `∇U(0)`.
        b: Vec<f64>,
        /// `∇²U`, n×n, row by row.
        h: Vec<f64>,
    },
    /// Anything else: U, ∇U and ∇²U (upper triangle, row by row) compiled.
    General(Box<GeneralPassenger>),
}

/// U, ∇U and ∇²U (upper triangle, row by row), compiled.
#[derive(Debug, Clone)]
pub struct GeneralPassenger {
    /// `U`.
    pub u: Function,
    /// `∇U`.
    pub gradient: Function,
    /// `∇²U`'s upper triangle.
    pub hessian: Function,
}

/// A system of the class as graphs, before differentiation (see [`Compiled::from_graphs`]).
pub(crate) struct ClassGraphs {
    /// Passenger coordinates.
    pub n: usize,
    /// Constraints.
    pub r: usize,
    /// The parameters' values.
    pub values: Vec<f64>,
    /// How the parameters enter the code.
    pub parameters: Parameters,
    /// The passenger's graph (variables: x₁ … xₙ).
    pub passenger: Graph,
    /// U.
    pub u: Id,
    /// The driver's graph (variable 0: ζ).
    pub driver: Graph,
    /// V_d.
    pub vd: Id,
    /// A's passenger columns, row by row.
    pub a: Vec<Id>,
}

/// A system given as formulas, ready to run; see the module's doc.
#[derive(Debug)]
pub struct Compiled {
    /// Passenger coordinates n (the system has n + 1).
    pub n: usize,
    /// Constraints r.
    pub r: usize,
    /// The parameters' values, in the spec's order.
    pub values: Vec<f64>,
    /// How the parameters enter the code.
    pub parameters: Parameters,
    /// U.
    pub passenger: Passenger,
    /// `[U, ∇U, ∇²U (upper triangle)]` at x = 0, where U is quadratic and the parameters are
    /// inputs: its numbers at each binding.
    at_zero: Option<Function>,
    /// `[V_d, V_d′, V_d″, A (r×n, row by row), dA/dζ (likewise)]` at ζ.
    pub driver: Function,
    /// Identifies this compilation in the per-thread cache of driver terms.
    pub(crate) id: u64,
    /// ∇²U constant.
    pub quadratic_passenger: bool,
    /// V_d″ constant.
    pub quadratic_driver: bool,
    /// ∇U ≡ 0.
    pub free_passenger: bool,
    /// V_d and A are 2π-periodic in ζ (ζ enters only through sin, cos and tan of integer
    /// multiples of it, plus constants).
    pub periodic: bool,
    /// The latitude's definition holds (`docs/model.md` §5): two passengers, one
    /// constraint, `U = ½|x|²` up to a constant.
    pub latitude: bool,
    /// ζ enters V_d and A only through `sin ζ` and `cos ζ`: ζ is an angle
    /// ([`System::zeta_is_angle`](crate::System::zeta_is_angle)), and the driver's code reads
    /// `[ζ, sin ζ, cos ζ]` rather than `[ζ]`.
    pub angle: bool,
}

static NEXT_ID: AtomicU64 = AtomicU64::new(1);

fn bad(field: impl Into<String>, message: impl Into<String>) -> InputError {
    InputError::CustomSystem { field: field.into(), message: message.into() }
}

/// Whether `name` can name a coordinate or parameter.
pub(crate) fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
        && name != "pi"
        && Func::named(name).is_none()
}

/// The names of one formula: which are variables, which parameters, which refused.
struct Scope<'a> {
    spec: &'a FormulaSpec,
    values: &'a [f64],
    parameters: Parameters,
    /// Whether the passenger coordinates are this formula's variables (else the driver is).
    passenger: bool,
    /// Why the other kind of coordinate is refused.
    refusal: &'a str,
}

impl Names for Scope<'_> {
    fn resolve(&self, name: &str) -> Option<Name> {
        if let Some(i) = self.spec.parameters.iter().position(|(p, _)| p == name) {
            return Some(self.parameters.name(i, self.values));
        }
        if let Some(i) = self.spec.passenger.iter().position(|p| p == name) {
            return Some(if self.passenger { Name::Var(i as u16) } else { self.refused(name) });
        }
        if self.spec.driver == name {
            return Some(if self.passenger { self.refused(name) } else { Name::Var(0) });
        }
        None
    }
    fn allowed(&self) -> String {
        let mut names: Vec<&str> = if self.passenger {
            self.spec.passenger.iter().map(String::as_str).collect()
        } else {
            vec![self.spec.driver.as_str()]
        };
        names.extend(self.spec.parameters.iter().map(|(p, _)| p.as_str()));
        format!("it may name {} and pi", names.join(", "))
    }
}

impl Scope<'_> {
    fn refused(&self, name: &str) -> Name {
        let kind = if self.passenger { "the driver" } else { "a passenger coordinate" };
        Name::Forbidden(format!("'{name}' is {kind}; {}", self.refusal))
    }
}

impl Compiled {
    /// Checks and compiles `spec` with its parameters overridden by `overrides` (field
    /// `params.NAME`). Errors name the field under `system.`.
    pub fn new(
        spec: &FormulaSpec,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
        parameters: Parameters,
    ) -> Result<Self, InputError> {
        let (n, r) = check_shape(spec, limits)?;
        let values = parameter_values(&spec.parameters, overrides)?;
        let lim = &limits.formula;
        let formula = |g: &mut Graph, field: String, text: &str, scope: &Scope<'_>| {
            parse(g, text, scope, lim).map_err(|error| InputError::Formula { field, error })
        };
        let passenger_scope = Scope {
            spec,
            values: &values,
            parameters,
            passenger: true,
            refusal: "U may depend on the passenger coordinates and parameters only \
                      (V = U(x) + V_d(ζ), docs/model.md §1)",
        };
        let driver_scope =
            |refusal| Scope { spec, values: &values, parameters, passenger: false, refusal };

        // The passenger: U, ∇U, ∇²U.
        let mut pg = Graph::new();
        let u = formula(
            &mut pg,
            "system.passenger_potential".into(),
            &spec.passenger_potential,
            &passenger_scope,
        )?;
        // The driver: V_d, its derivatives, A and dA/dζ, one graph so that they share work.
        let mut dg = Graph::new();
        let vd = formula(
            &mut dg,
            "system.driver_potential".into(),
            &spec.driver_potential,
            &driver_scope(
                "V_d may depend on the driver and parameters only (V = U(x) + V_d(ζ), docs/model.md §1)",
            ),
        )?;
        let mut a = Vec::with_capacity(r * n);
        let a_scope = driver_scope(
            "the constraints' passenger columns may depend on the driver and parameters only \
             (A(ζ) in the class of the paper's theory, docs/model.md §1)",
        );
        for (i, row) in spec.constraints.iter().enumerate() {
            for (j, text) in row.iter().enumerate() {
                a.push(formula(&mut dg, format!("system.constraints[{i}][{j}]"), text, &a_scope)?);
            }
        }
        let graphs = ClassGraphs { n, r, values, parameters, passenger: pg, u, driver: dg, vd, a };
        Self::from_graphs(graphs, limits)
    }

    /// Differentiates and compiles a system of the class given as graphs: U in `passenger`
    /// (variables: the passenger coordinates), V_d and the passenger columns of A (row by row)
    /// in `driver` (variable 0: ζ), the parameters' values already in place. What
    /// [`Compiled::new`] parses, or what a system given in the general form is found to be
    /// (`model::custom::detect`).
    pub(crate) fn from_graphs(
        graphs: ClassGraphs,
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        let ClassGraphs { n, r, values, parameters, passenger: mut pg, u, driver: mut dg, vd, a } =
            graphs;
        let lim = &limits.formula;
        let too_large = || InputError::Formula {
            field: "system".into(),
            error: crate::formula::FormulaError::TooLarge { limit: lim.max_nodes },
        };
        let mut by_var: Vec<Derivative> = (0..n).map(|i| Derivative::new(i as u16)).collect();
        // Derivatives grow the graph: its size is checked as it grows, not only at the end.
        let mut gradient: Vec<Id> = Vec::with_capacity(n);
        for d in &mut by_var {
            gradient.push(d.of(&mut pg, u));
            if pg.len() > lim.max_nodes {
                return Err(too_large());
            }
        }
        let mut hessian = Vec::new();
        for (i, &gi) in gradient.iter().enumerate() {
            for d in &mut by_var[i..] {
                hessian.push(d.of(&mut pg, gi));
                if pg.len() > lim.max_nodes {
                    return Err(too_large());
                }
            }
        }
        let mut d = Derivative::new(0);
        let vd1 = d.of(&mut dg, vd);
        let vd2 = d.of(&mut dg, vd1);
        let da: Vec<Id> = a.iter().map(|&e| d.of(&mut dg, e)).collect();
        if pg.len() + dg.len() > lim.max_nodes {
            return Err(too_large());
        }

        // Where the parameters are inputs, U is quadratic where its second derivatives read
        // none of the coordinates; its numbers are then taken per binding, from `at_zero`.
        let quadratic_passenger = match parameters {
            Parameters::Folded => hessian.iter().all(|&h| pg.constant(h).is_some()),
            Parameters::Inputs => hessian.iter().all(|&h| !reads_coordinates(&pg, h)),
        };
        let free_passenger = gradient.iter().all(|&g| pg.constant(g) == Some(0.0));
        let at_zero = (quadratic_passenger && parameters == Parameters::Inputs).then(|| {
            let outputs: Vec<Id> = std::iter::once(u)
                .chain(gradient.iter().copied())
                .chain(hessian.iter().copied())
                .collect();
            Function::new(Tape::compile(&pg, &outputs, n), false)
        });
        let passenger = if let Some(code) = &at_zero {
            quadratic_at_zero(&code.bind(&Arc::from(values.as_slice())), n)
        } else if quadratic_passenger {
            let zero = vec![0.0; n];
            let mut h = vec![0.0; n * n];
            let mut k = 0;
            for i in 0..n {
                for j in i..n {
                    let value = pg.constant(hessian[k]).unwrap_or(f64::NAN);
                    (h[i * n + j], h[j * n + i]) = (value, value);
                    k += 1;
                }
            }
            Passenger::Quadratic {
                u0: pg.eval(u, &zero),
                b: gradient.iter().map(|&g| pg.eval(g, &zero)).collect(),
                h,
            }
        } else {
            let native = limits.native;
            Passenger::General(Box::new(GeneralPassenger {
                u: Function::new(Tape::compile(&pg, &[u], n), native),
                gradient: Function::new(Tape::compile(&pg, &gradient, n), native),
                hessian: Function::new(Tape::compile(&pg, &hessian, n), native),
            }))
        };
        let latitude = latitude_holds(n, r, &passenger);
        let zeta = dg.var(0);
        let trig = [(dg.call(Func::Sin, zeta), 1), (dg.call(Func::Cos, zeta), 2)];
        let on_zeta = dependence(&dg);
        let mut seen = HashMap::new();
        let periodic = std::iter::once(vd)
            .chain(a.iter().copied())
            .all(|e| periodic(&dg, &on_zeta, e, &mut seen));
        let mut outputs = vec![vd, vd1, vd2];
        outputs.extend(&a);
        outputs.extend(&da);
        let via_trig = through(&dg, &[trig[0].0, trig[1].0]);
        let angle = std::iter::once(vd).chain(a.iter().copied()).all(|e| via_trig[e.0 as usize]);
        let driver = if angle {
            Tape::compile_reading(&dg, &outputs, 3, &trig)
        } else {
            Tape::compile(&dg, &outputs, 1)
        };
        Ok(Self {
            n,
            r,
            values,
            parameters,
            passenger,
            at_zero,
            driver: Function::new(driver, limits.native),
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            quadratic_passenger,
            quadratic_driver: dg.constant(vd2).is_some(),
            free_passenger,
            periodic,
            latitude,
            angle,
        })
    }
}

impl Compiled {
    /// The same compilation bound to the parameter values `values` (its parameters are
    /// [inputs](Parameters::Inputs)).
    pub fn bind(&self, values: &[f64]) -> Self {
        debug_assert_eq!(self.parameters, Parameters::Inputs);
        let params: Arc<[f64]> = values.into();
        let passenger = match (&self.passenger, &self.at_zero) {
            (Passenger::General(g), _) => Passenger::General(Box::new(GeneralPassenger {
                u: g.u.bind(&params),
                gradient: g.gradient.bind(&params),
                hessian: g.hessian.bind(&params),
            })),
            (Passenger::Quadratic { .. }, Some(code)) => {
                quadratic_at_zero(&code.bind(&params), self.n)
            }
            (quadratic, None) => quadratic.clone(),
        };
        let latitude = latitude_holds(self.n, self.r, &passenger);
        Self {
            n: self.n,
            r: self.r,
            values: values.to_vec(),
            parameters: self.parameters,
            passenger,
            at_zero: self.at_zero.clone(),
            driver: self.driver.bind(&params),
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            quadratic_passenger: self.quadratic_passenger,
            quadratic_driver: self.quadratic_driver,
            free_passenger: self.free_passenger,
            periodic: self.periodic,
            latitude,
            angle: self.angle,
        }
    }
}

/// The parameters' values: their defaults overridden by a request's `params` (field
/// `params.NAME`), each finite.
pub(crate) fn parameter_values(
    parameters: &[(String, f64)],
    overrides: &[(String, f64)],
) -> Result<Vec<f64>, InputError> {
    let mut values: Vec<f64> = parameters.iter().map(|p| p.1).collect();
    for (name, value) in overrides {
        let field = format!("params.{name}");
        let Some(i) = parameters.iter().position(|(p, _)| p == name) else {
            let valid: Vec<&str> = parameters.iter().map(|p| p.0.as_str()).collect();
            return Err(InputError::UnknownParam {
                field,
                name: name.clone(),
                owner: "the system".into(),
                valid: if valid.is_empty() { "none".into() } else { valid.join(", ") },
            });
        };
        if !value.is_finite() {
            return Err(InputError::NonFinite { field, value: *value });
        }
        values[i] = *value;
    }
    Ok(values)
}

/// Sizes and names: n passengers (1 to 6), r constraints (1 to n − 1) of n entries each,
/// distinct identifiers, at most `max_parameters` parameters with finite values.
fn check_shape(spec: &FormulaSpec, limits: &CustomLimits) -> Result<(usize, usize), InputError> {
    let n = spec.passenger.len();
    if !(1..=MAX_PASSENGERS).contains(&n) {
        return Err(bad(
            "system.passenger",
            format!("a system has 1 to {MAX_PASSENGERS} passenger coordinates, got {n}"),
        ));
    }
    let r = spec.constraints.len();
    if r == 0 || r >= n {
        return Err(bad(
            "system.constraints",
            format!(
                "{n} passenger coordinate{} allow 1 to n − 1 = {} constraint rows, got {r}: \
                 the passengers' constrained motion must keep at least one direction \
                 (docs/model.md §1)",
                if n == 1 { "" } else { "s" },
                n - 1
            ),
        ));
    }
    for (i, row) in spec.constraints.iter().enumerate() {
        if row.len() != n {
            return Err(bad(
                format!("system.constraints[{i}]"),
                format!(
                    "each constraint row has one entry per passenger coordinate ({n}), got {}; \
                     the driver's column is zero in this class and is not written",
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
    let mut seen: Vec<&str> = Vec::new();
    let names = spec
        .passenger
        .iter()
        .enumerate()
        .map(|(i, p)| (format!("system.passenger[{i}]"), p.as_str()))
        .chain(std::iter::once(("system.driver".to_string(), spec.driver.as_str())))
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
        if seen.contains(&name) {
            return Err(bad(field, format!("'{name}' is named twice")));
        }
        seen.push(name);
    }
    for (p, value) in &spec.parameters {
        if !value.is_finite() {
            return Err(InputError::NonFinite {
                field: format!("system.parameters.{p}"),
                value: *value,
            });
        }
    }
    Ok((n, r))
}

/// Whether variable 0 enters each node of `g` only through the nodes `via`, in one pass
/// (children come first).
fn through(g: &Graph, via: &[Id]) -> Vec<bool> {
    let mut ok = vec![true; g.len()];
    for i in 0..g.len() {
        let (id, node) = (Id(i as u32), g.node(Id(i as u32)));
        ok[i] = via.contains(&id)
            || (node != Node::Var(0)
                && node.children().into_iter().flatten().all(|c| ok[c.0 as usize]));
    }
    ok
}

/// Whether `e` is 2π-periodic in variable 0 by its form: the variable appears only inside
/// `sin`, `cos` or `tan` of an integer multiple of it plus a constant. Each node is looked
/// at once (`seen`), as nodes are shared.
fn periodic(g: &Graph, on_zeta: &[bool], e: Id, seen: &mut HashMap<Id, bool>) -> bool {
    if let Some(&known) = seen.get(&e) {
        return known;
    }
    let answer = !on_zeta[e.0 as usize]
        || match g.node(e) {
            Node::Call(Func::Sin | Func::Cos | Func::Tan, a) => integer_multiple(g, on_zeta, a),
            Node::Var(_) => false,
            node => node.children().into_iter().flatten().all(|c| periodic(g, on_zeta, c, seen)),
        };
    seen.insert(e, answer);
    answer
}

/// Whether `e` is `kζ + c` with k a nonzero integer and c constant.
fn integer_multiple(g: &Graph, on_zeta: &[bool], e: Id) -> bool {
    let integer = |id: Id| g.constant(id).is_some_and(|k| k.fract() == 0.0 && k != 0.0);
    let free = |id: Id| !on_zeta[id.0 as usize];
    let multiple = |id: Id| integer_multiple(g, on_zeta, id);
    match g.node(e) {
        Node::Var(0) => true,
        Node::Neg(a) => multiple(a),
        Node::Mul(a, b) => (integer(a) && multiple(b)) || (integer(b) && multiple(a)),
        // Only the side that depends on ζ is looked into.
        Node::Add(a, b) | Node::Sub(a, b) if free(b) => multiple(a),
        Node::Add(a, b) | Node::Sub(a, b) if free(a) => multiple(b),
        _ => false,
    }
}

/// Whether each node of `g` depends on variable 0, in one pass (children come first).
fn dependence(g: &Graph) -> Vec<bool> {
    let mut on = vec![false; g.len()];
    for i in 0..g.len() {
        let node = g.node(Id(i as u32));
        on[i] =
            node == Node::Var(0) || node.children().into_iter().flatten().any(|c| on[c.0 as usize]);
    }
    on
}
