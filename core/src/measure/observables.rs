//! [`Observables`]: quantities a user names and gives as formulas in a system's coordinates,
//! their velocities (`x_dot` for the coordinate `x`), the time `t` and the parameters,
//! evaluated at the states a run samples ([`Observer::sample`](super::simulate::Observer)).
//! A bare coordinate or velocity is read from the state; the other formulas are compiled into
//! one tape (the parameters folded in) and evaluated together, once per sample.

use crate::InputError;
use crate::formula::parse::{Name, Names, parse};
use crate::formula::{Graph, Limits, Tape};

/// Most observables per request.
pub const MAX_OBSERVABLES: usize = 16;

/// How one observable is read from a sampled state.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Read {
    /// Coordinate i.
    Q(usize),
    /// Velocity i.
    V(usize),
    /// Output k of the tape.
    Formula(usize),
}

/// The observables of a request, checked and compiled; see the module's doc.
#[derive(Debug, Clone)]
pub struct Observables {
    names: Vec<String>,
    reads: Vec<Read>,
    /// The formulas' tape over (q, q̇, t), and its number of coordinates.
    tape: Option<Tape>,
    dof: usize,
}

/// The names of an observable's formula: coordinates, velocities, t, parameters.
struct Scope<'a> {
    coordinates: &'a [String],
    params: &'a [(&'a str, f64)],
}

impl Names for Scope<'_> {
    fn resolve(&self, name: &str) -> Option<Name> {
        let n = self.coordinates.len();
        if let Some(i) = self.coordinates.iter().position(|c| c == name) {
            return Some(Name::Var(i as u16));
        }
        if let Some(c) = name.strip_suffix("_dot")
            && let Some(i) = self.coordinates.iter().position(|x| x == c)
        {
            return Some(Name::Var((n + i) as u16));
        }
        if name == "t" {
            return Some(Name::Var((2 * n) as u16));
        }
        self.params.iter().find(|(p, _)| *p == name).map(|&(_, v)| Name::Value(v))
    }

    fn allowed(&self) -> String {
        let mut names: Vec<String> = self.coordinates.to_vec();
        names.extend(self.coordinates.iter().map(|c| format!("{c}_dot")));
        names.push("t".into());
        names.extend(self.params.iter().map(|(p, _)| (*p).to_owned()));
        format!("it may name {} and pi", names.join(", "))
    }
}

impl Observables {
    /// Checks and compiles `given` (name, formula) for a system with these coordinates and
    /// parameter values. Errors name the field `observables.NAME`.
    pub fn compile(
        given: &[(String, String)],
        coordinates: &[String],
        params: &[(&str, f64)],
        limits: &Limits,
    ) -> Result<Self, InputError> {
        Self::compile_at(
            given,
            "observables",
            &|_, name| format!("observables.{name}"),
            (coordinates, params, limits),
        )
    }

    /// [`compile`](Self::compile), the errors of observable i named `NAME` at `field(i,
    /// NAME)`, those of the whole at `whole`.
    pub fn compile_at(
        given: &[(String, String)],
        whole: &str,
        field: &dyn Fn(usize, &str) -> String,
        (coordinates, params, limits): (&[String], &[(&str, f64)], &Limits),
    ) -> Result<Self, InputError> {
        let bad = |field: String, message: String| InputError::CustomSystem { field, message };
        if given.len() > MAX_OBSERVABLES {
            return Err(bad(
                whole.into(),
                format!("{} observables exceed the limit of {MAX_OBSERVABLES}", given.len()),
            ));
        }
        let n = coordinates.len();
        let scope = Scope { coordinates, params };
        let mut g = Graph::new();
        let (mut reads, mut outputs) = (Vec::new(), Vec::new());
        for (i, (name, text)) in given.iter().enumerate() {
            let field = field(i, name);
            if name.is_empty() || name == "t" {
                let why =
                    "an observable's name must not be empty nor 't' (the sample times' column)";
                return Err(bad(field, why.into()));
            }
            let bare = text.trim();
            let read = if let Some(i) = coordinates.iter().position(|c| c == bare) {
                Read::Q(i)
            } else if let Some(i) =
                bare.strip_suffix("_dot").and_then(|c| coordinates.iter().position(|x| x == c))
            {
                Read::V(i)
            } else {
                let id = parse(&mut g, text, &scope, limits)
                    .map_err(|error| InputError::Formula { field, error })?;
                outputs.push(id);
                Read::Formula(outputs.len() - 1)
            };
            reads.push(read);
        }
        let tape = (!outputs.is_empty()).then(|| Tape::compile(&g, &outputs, 2 * n + 1));
        Ok(Self { names: given.iter().map(|(n, _)| n.clone()).collect(), reads, tape, dof: n })
    }

    /// The observables' names, in the order given.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// A scratch for [`eval`](Self::eval): the variables and the formulas' outputs.
    pub fn scratch(&self) -> Scratch {
        let outputs = self.tape.as_ref().map_or(0, Tape::outputs);
        Scratch { vars: vec![0.0; 2 * self.dof + 1], outputs: vec![0.0; outputs] }
    }

    /// The observables at time t and state (q, q̇) (in the user's order), written to `out`
    /// in the order given.
    pub fn eval(&self, t: f64, q: &[f64], v: &[f64], scratch: &mut Scratch, out: &mut [f64]) {
        if let Some(tape) = &self.tape {
            let n = self.dof;
            scratch.vars[..n].copy_from_slice(&q[..n]);
            scratch.vars[n..2 * n].copy_from_slice(&v[..n]);
            scratch.vars[2 * n] = t;
            tape.eval(&scratch.vars, &mut scratch.outputs);
        }
        for (o, read) in out.iter_mut().zip(&self.reads) {
            *o = match *read {
                Read::Q(i) => q[i],
                Read::V(i) => v[i],
                Read::Formula(k) => scratch.outputs[k],
            };
        }
    }
}

/// What [`Observables::eval`] writes into between calls: allocated once per run.
#[derive(Debug, Clone)]
pub struct Scratch {
    vars: Vec<f64>,
    outputs: Vec<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(xs: &[&str]) -> Vec<String> {
        xs.iter().map(|x| (*x).to_owned()).collect()
    }

    #[test]
    fn observables_read_coordinates_velocities_time_and_parameters() {
        let given = vec![
            ("theta".to_owned(), "theta".to_owned()),
            ("speed".to_owned(), "x_dot*cos(theta) + y_dot*sin(theta)".to_owned()),
            ("w".to_owned(), " theta_dot ".to_owned()),
            ("clock".to_owned(), "k*t".to_owned()),
        ];
        let coords = names(&["x", "y", "theta"]);
        let obs = Observables::compile(&given, &coords, &[("k", 2.0)], &Limits::default())
            .expect("compiles");
        assert_eq!(obs.names(), ["theta", "speed", "w", "clock"]);
        let (q, v) = ([1.0, 2.0, 0.5], [3.0, 4.0, 0.25]);
        let mut out = [0.0; 4];
        obs.eval(1.5, &q, &v, &mut obs.scratch(), &mut out);
        assert_eq!(out[0], 0.5);
        assert!((out[1] - (3.0 * 0.5f64.cos() + 4.0 * 0.5f64.sin())).abs() < 1e-15);
        assert_eq!(out[2], 0.25);
        assert_eq!(out[3], 3.0);
    }

    #[test]
    fn an_observables_error_names_its_field() {
        let coords = names(&["x", "y"]);
        let bad = |text: &str| {
            let given = vec![("e".to_owned(), text.to_owned())];
            Observables::compile(&given, &coords, &[], &Limits::default()).unwrap_err()
        };
        let e = bad("x^");
        assert_eq!(e.field(), "observables.e");
        let e = bad("z + 1");
        assert_eq!(e.field(), "observables.e");
        assert!(e.to_string().contains("x_dot"), "{e}");
        let given = vec![("t".to_owned(), "x".to_owned())];
        let e = Observables::compile(&given, &coords, &[], &Limits::default()).unwrap_err();
        assert_eq!(e.field(), "observables.t");
    }
}
