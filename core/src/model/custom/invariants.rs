//! [`Invariants`]: a system's named invariants, formulas in the coordinates, their velocities
//! (`x_dot`) and the parameters (`docs/model.md` §4), compiled into one tape on the run's
//! `(q, q̇)`, whose coordinates may be reordered from the user's (the paper's class puts the
//! driver last) or followed by padding (sizes compiled once).

use super::compile::Parameters;
use super::general_spec::GeneralSpec;
use super::spec::CustomLimits;
use crate::InputError;
use crate::formula::parse::{Name, Names, parse};
use crate::formula::{Function, Graph, Tape};
use crate::model::integral::MAX_INVARIANTS;
use std::sync::Arc;

/// See the module's doc.
#[derive(Debug, Clone)]
pub struct Invariants {
    names: Vec<String>,
    function: Function,
    /// The coordinates the formulas read: the first n of the run's q and q̇.
    n: usize,
}

/// The names of an invariant's formula: coordinates and velocities as the run holds them.
struct Scope<'a> {
    spec: &'a GeneralSpec,
    values: &'a [f64],
    parameters: Parameters,
    /// `internal[j]`: where the run holds the user's coordinate j.
    internal: &'a [usize],
}

impl Names for Scope<'_> {
    fn resolve(&self, name: &str) -> Option<Name> {
        let n = self.internal.len();
        if let Some(i) = self.spec.parameters.iter().position(|(p, _)| p == name) {
            return Some(self.parameters.name(i, self.values));
        }
        if let Some(j) = self.spec.coordinates.iter().position(|c| c == name) {
            return Some(Name::Var(self.internal[j] as u16));
        }
        let velocity = name.strip_suffix("_dot")?;
        let j = self.spec.coordinates.iter().position(|c| c == velocity)?;
        Some(Name::Var((n + self.internal[j]) as u16))
    }
    fn allowed(&self) -> String {
        let mut names: Vec<String> = self.spec.coordinates.clone();
        names.extend(self.spec.coordinates.iter().map(|c| format!("{c}_dot")));
        names.extend(self.spec.parameters.iter().map(|(p, _)| p.clone()));
        format!("it may name {} and pi", names.join(", "))
    }
}

impl Invariants {
    /// Compiles the invariants of `spec` with the parameters at `values` (or as inputs), for a
    /// run that holds the user's coordinate `order[i]` at i (field `system.invariants.NAME`).
    pub fn compile(
        spec: &GeneralSpec,
        (values, parameters): (&[f64], Parameters),
        order: &[usize],
        limits: &CustomLimits,
    ) -> Result<Self, InputError> {
        debug_assert!(spec.invariants.len() <= MAX_INVARIANTS);
        let n = order.len();
        let mut internal = vec![0; n];
        for (i, &j) in order.iter().enumerate() {
            internal[j] = i;
        }
        let scope = Scope { spec, values, parameters, internal: &internal };
        let mut g = Graph::new();
        let mut outputs = Vec::with_capacity(spec.invariants.len());
        for (name, text) in &spec.invariants {
            let id = parse(&mut g, text, &scope, &limits.formula).map_err(|error| {
                InputError::Formula { field: format!("system.invariants.{name}"), error }
            })?;
            outputs.push(id);
        }
        Ok(Self {
            names: spec.invariants.iter().map(|(name, _)| name.clone()).collect(),
            function: Function::new(Tape::compile(&g, &outputs, 2 * n), limits.native),
            n,
        })
    }

    /// The same code bound to the parameter values `params` (inputs of it).
    pub fn bind(&self, params: &Arc<[f64]>) -> Self {
        Self { function: self.function.bind(params), ..self.clone() }
    }

    /// The invariants' names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Their values at `(q, q̇)` as the run holds them, into `out` (its first
    /// `names().len()` entries).
    #[inline]
    pub fn eval(&self, q: &[f64], v: &[f64], out: &mut [f64; MAX_INVARIANTS]) {
        let mut vars = [0.0; 2 * super::general_spec::MAX_COORDINATES];
        vars[..self.n].copy_from_slice(&q[..self.n]);
        vars[self.n..2 * self.n].copy_from_slice(&v[..self.n]);
        self.function.eval(&vars[..2 * self.n], &mut out[..self.names.len()]);
    }
}
