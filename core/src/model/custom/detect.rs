//! The paper's class found in a system given in the general form (`docs/model.md` §10): a
//! coordinate ζ such that M = I, every entry of A depends on ζ alone (and the parameters),
//! ζ's column of A is zero, and V splits as `U(x) + V_d(ζ)` (every mixed second derivative
//! `∂²V/∂ζ∂x_i` is zero as the graph simplifies it). Where several coordinates qualify, the
//! last. The class's compilation is then built from the same graph: U is V with ζ fixed,
//! V_d is V with the passengers fixed (less the constant they share), A's passenger columns
//! are A's with ζ as the driver's variable.

use super::compile::{ClassGraphs, Compiled, Parameters, point};
use super::spec::{CustomLimits, MAX_PASSENGERS};
use crate::InputError;
use crate::formula::derive::Derivative;
use crate::formula::{Graph, Id, PARAM_VAR};
use std::collections::HashMap;

/// The driver found: its index among the user's coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ClassFound {
    pub driver: usize,
}

/// The driver of the paper's class in the system `(V, A)` of the graph `g` (variables: the N
/// coordinates), or why there is none, in words.
pub(crate) fn find(
    g: &mut Graph,
    v: Id,
    a: &[Id],
    names: &[String],
    m: usize,
    unit_mass: bool,
) -> Result<ClassFound, String> {
    let n = names.len();
    if !unit_mass {
        return Err("M ≠ I (the paper's class has unit masses)".into());
    }
    if n < 3 || m > n - 2 {
        return Err(format!(
            "{m} constraint{} on {n} coordinates leave the passengers no direction of their own \
             (the paper's class has 1 ≤ m ≤ N − 2)",
            if m == 1 { "" } else { "s" }
        ));
    }
    if n - 1 > MAX_PASSENGERS {
        return Err(format!(
            "more than {} coordinates (the paper's class is compiled for at most {MAX_PASSENGERS} \
             passengers and a driver)",
            MAX_PASSENGERS + 1
        ));
    }
    // The coordinates A reads (parameters given as inputs are variables too, not coordinates).
    let mut in_a: Vec<u16> =
        a.iter().flat_map(|&e| g.variables(e)).filter(|&k| k < PARAM_VAR).collect();
    in_a.sort_unstable();
    in_a.dedup();
    if in_a.len() > 1 {
        let which: Vec<&str> = in_a.iter().map(|&k| names[k as usize].as_str()).collect();
        return Err(format!(
            "A depends on {} (the paper's class: on the driver alone)",
            which.join(" and ")
        ));
    }
    let candidates: Vec<usize> = match in_a.first() {
        Some(&k) => vec![k as usize],
        None => (0..n).rev().collect(),
    };
    let mut why = String::new();
    for k in candidates {
        if let Some(j) = (0..m).find(|&r| g.constant(a[r * n + k]) != Some(0.0)) {
            why = format!(
                "A depends on {} only, but its row {j} has an entry in {}'s column (the paper's \
                 class: the driver's column is zero)",
                names[k], names[k]
            );
            continue;
        }
        let dv = Derivative::new(k as u16).of(g, v);
        let coupled = (0..n).filter(|&j| j != k).find(|&j| {
            let d = Derivative::new(j as u16).of(g, dv);
            g.constant(d) != Some(0.0)
        });
        if let Some(j) = coupled {
            why = format!(
                "V couples {} and {} (∂²V/∂{}∂{} ≠ 0; the paper's class has V = U(x) + V_d(ζ))",
                names[k], names[j], names[k], names[j]
            );
            continue;
        }
        return Ok(ClassFound { driver: k });
    }
    Err(why)
}

/// The class's compilation of `(V, A)` with `driver` as ζ, the passengers in the user's
/// order.
pub(crate) fn class_compilation(
    g: &Graph,
    v: Id,
    a: &[Id],
    (n, m): (usize, usize),
    driver: usize,
    (values, parameters): (&[f64], Parameters),
    limits: &CustomLimits,
) -> Result<Compiled, InputError> {
    // A point where V is finite (at these parameter values), at which the other part is
    // held fixed.
    let at = [0.0, 1.0, 0.5, 2.0, -1.0]
        .into_iter()
        .find(|&c| g.eval(v, &point(&vec![c; n], values)).is_finite())
        .ok_or_else(|| InputError::CustomSystem {
            field: "system.potential".into(),
            message: "V is not finite at any of q = 0, 1, 0.5, 2, −1 (every coordinate), where \
                      nhlab splits it into the passengers' and the driver's parts"
                .into(),
        })?;
    let passenger_index = |j: u16| (j as usize) - usize::from(j as usize > driver);
    let mut passenger = Graph::new();
    let u = passenger.import(
        g,
        v,
        &mut |pg: &mut Graph, j| {
            if j >= PARAM_VAR {
                pg.var(j)
            } else if j as usize == driver {
                pg.num(at)
            } else {
                pg.var(passenger_index(j) as u16)
            }
        },
        &mut HashMap::new(),
    );
    let mut dg = Graph::new();
    let mut done = HashMap::new();
    let mut to_driver = |dg: &mut Graph, j: u16| {
        if j >= PARAM_VAR {
            dg.var(j)
        } else if j as usize == driver {
            dg.var(0)
        } else {
            dg.num(at)
        }
    };
    let v_driver = dg.import(g, v, &mut to_driver, &mut done);
    // V with every coordinate held: a number, or a formula in the parameters given as inputs.
    let shared = match parameters {
        Parameters::Folded => dg.num(g.eval(v, &point(&vec![at; n], values))),
        Parameters::Inputs => {
            let mut held =
                |dg: &mut Graph, j: u16| if j >= PARAM_VAR { dg.var(j) } else { dg.num(at) };
            dg.import(g, v, &mut held, &mut HashMap::new())
        }
    };
    let vd = dg.sub(v_driver, shared);
    let mut entries = Vec::with_capacity(m * (n - 1));
    for r in 0..m {
        for j in (0..n).filter(|&j| j != driver) {
            entries.push(dg.import(g, a[r * n + j], &mut to_driver, &mut done));
        }
    }
    let graphs = ClassGraphs {
        n: n - 1,
        r: m,
        values: values.to_vec(),
        parameters,
        passenger,
        u,
        driver: dg,
        vd,
        a: entries,
    };
    Compiled::from_graphs(graphs, limits)
}
