//! [`ObservablesView`]: a run's sampled observables as columns, `{"t": [...], "theta":
//! [...], ...}`: the sample times first, then each observable in the order asked for.

use nhlab_core::measure::observables::Observables;
use serde::Serialize;
use serde::ser::SerializeMap;

/// A run's observables: the sample times (`t`) and one column per observable. A value that
/// is not finite is null.
/// (Its schema is an object of number arrays, given where it is a field.)
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ObservablesView {
    /// The sample times.
    pub t: Vec<f64>,
    /// Each observable's name and values, in the order asked for.
    pub columns: Vec<(String, Vec<f64>)>,
}

impl ObservablesView {
    /// Empty columns for `names`, room for `points` samples.
    pub fn new(names: &[String], points: usize) -> Self {
        Self {
            t: Vec::with_capacity(points),
            columns: names.iter().map(|n| (n.clone(), Vec::with_capacity(points))).collect(),
        }
    }

    /// The columns so far, leaving empty ones with the same names (a stream sends what is new).
    pub fn take(&mut self) -> Self {
        let names = self.columns.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
        std::mem::replace(self, Self::new(&names, 0))
    }

    /// Adds a sample: its time and the observables' values in order.
    pub fn push(&mut self, t: f64, values: &[f64]) {
        self.t.push(t);
        for ((_, column), &x) in self.columns.iter_mut().zip(values) {
            column.push(x);
        }
    }
}

/// Observables at one time, by name in the order asked for (a value that is not finite is
/// null): a work–precision row's at t_end.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ValuesView(pub Vec<(String, f64)>);

impl ValuesView {
    /// `observables` at time t and state (q, q̇).
    pub fn at(observables: &Observables, t: f64, q: &[f64], v: &[f64]) -> Self {
        let mut out = vec![0.0; observables.names().len()];
        observables.eval(t, q, v, &mut observables.scratch(), &mut out);
        Self(observables.names().iter().cloned().zip(out).collect())
    }
}

impl Serialize for ValuesView {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (name, x) in &self.0 {
            map.serialize_entry(name, &x.is_finite().then_some(*x))?;
        }
        map.end()
    }
}

impl Serialize for ObservablesView {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.columns.len() + 1))?;
        map.serialize_entry("t", &self.t)?;
        for (name, column) in &self.columns {
            map.serialize_entry(name, column)?;
        }
        map.end()
    }
}
