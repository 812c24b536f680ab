//! [`Axis`]: one axis of a sweep, checked: what it sets ([`Target`], parsed from its path)
//! and its values (a list, or spaced linearly or logarithmically). An axis sets its value in
//! a cell's `/simulate` body ([`Axis::apply`]) and says which errors of a cell's scene it may
//! have caused ([`Axis::may_cause`]): those are the cell's, the others the request's.

use crate::error::AppError;
use crate::request::{AxisRequest, MethodRequest, SimulateRequest};
use nhlab_core::Short;

/// What an axis sets.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// A parameter of the system, `params.NAME`.
    Param(String),
    /// A component of the initial configuration, `q[i]`.
    Q(usize),
    /// A component of the initial velocity, `v[i]`.
    V(usize),
    /// `step`.
    Step,
    /// `t_end`.
    TEnd,
    /// A parameter of the methods: of every method that has it (`methods.NAME`), or of one
    /// (`methods[i].NAME`).
    Method {
        /// The method's index, if one.
        index: Option<usize>,
        /// The parameter.
        name: String,
    },
}

impl Target {
    /// Whether two axes would set the same value (`methods.alpha` and `methods[0].alpha`).
    pub fn overlaps(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::Method { index: a, name: x }, Self::Method { index: b, name: y }) => {
                x == y && (a.is_none() || b.is_none() || a == b)
            }
            _ => self == other,
        }
    }
}

/// The forms of a path, for errors.
const PATHS: &str = "params.NAME, q[i], v[i], step, t_end, methods.NAME or methods[i].NAME";

impl Target {
    /// Parses a path; `None` if it has none of the forms.
    pub fn parse(path: &str) -> Option<Self> {
        let name = |s: &str| {
            (!s.is_empty() && s.chars().all(|c| c.is_alphanumeric() || c == '_'))
                .then(|| s.to_owned())
        };
        // Digits only, without leading zeros: `q[01]` and `q[+1]` are not `q[1]`.
        let index = |s: &str, prefix: &str| -> Option<usize> {
            let digits = s.strip_prefix(prefix)?.strip_suffix(']')?;
            let canonical = digits.bytes().all(|b| b.is_ascii_digit())
                && !(digits.len() > 1 && digits.starts_with('0'));
            if canonical { digits.parse().ok() } else { None }
        };
        match path {
            "step" => Some(Self::Step),
            "t_end" => Some(Self::TEnd),
            _ if path.starts_with("q[") => index(path, "q[").map(Self::Q),
            _ if path.starts_with("v[") => index(path, "v[").map(Self::V),
            _ if path.starts_with("params.") => name(&path["params.".len()..]).map(Self::Param),
            _ if path.starts_with("methods.") => {
                name(&path["methods.".len()..]).map(|name| Self::Method { index: None, name })
            }
            _ if path.starts_with("methods[") => {
                let (head, param) = path.split_once("].")?;
                let i = index(&format!("{head}]"), "methods[")?;
                name(param).map(|name| Self::Method { index: Some(i), name })
            }
            _ => None,
        }
    }
}

/// A checked axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The path as given.
    pub path: String,
    /// What it sets.
    pub target: Target,
    /// Its values.
    pub values: Vec<f64>,
}

impl Axis {
    /// Checks axis `k` of a request, of at most `max_values` values.
    pub fn check(k: usize, given: &AxisRequest, max_values: u64) -> Result<Self, AppError> {
        let at = |field: &str| format!("axes[{k}].{field}");
        let target = Target::parse(&given.path).ok_or_else(|| {
            AppError::invalid(
                at("path"),
                format!("`{}` is not an axis path; a path is one of {PATHS}", given.path),
            )
        })?;
        let values = match (&given.values, &given.linspace, &given.logspace) {
            (Some(values), None, None) => {
                if values.is_empty() {
                    return Err(AppError::invalid(at("values"), "values must not be empty"));
                }
                if values.len() as u64 > max_values {
                    return Err(too_many(at("values"), values.len() as f64, max_values));
                }
                values.clone()
            }
            (None, Some(spec), None) => spaced(&at("linspace"), spec, max_values, false)?,
            (None, None, Some(spec)) => spaced(&at("logspace"), spec, max_values, true)?,
            _ => {
                return Err(AppError::invalid(
                    format!("axes[{k}]"),
                    "give exactly one of values, linspace or logspace",
                ));
            }
        };
        if let Some(i) = values.iter().position(|x| !x.is_finite()) {
            let field = [("linspace", &given.linspace), ("logspace", &given.logspace)]
                .into_iter()
                .find_map(|(f, g)| g.is_some().then_some(f))
                .unwrap_or("values");
            return Err(AppError::invalid(at(field), format!("value {i} is not finite")));
        }
        Ok(Self { path: given.path.clone(), target, values })
    }

    /// Sets `value` in a cell's body; `q0`/`v0` are the scene's initial state where the body
    /// gives none (a preset's).
    pub fn apply(
        &self,
        value: f64,
        body: &mut SimulateRequest,
        methods: &mut [MethodRequest],
        q0: &[f64],
        v0: &[f64],
    ) {
        let set = |list: &mut Vec<(String, f64)>, name: &str| match list
            .iter_mut()
            .find(|(n, _)| n == name)
        {
            Some(entry) => entry.1 = value,
            None => list.push((name.to_owned(), value)),
        };
        match &self.target {
            Target::Param(name) => set(&mut body.params.get_or_insert_default().0, name),
            Target::Q(i) => body.q.get_or_insert_with(|| q0.to_vec())[*i] = value,
            Target::V(i) => body.v.get_or_insert_with(|| v0.to_vec())[*i] = value,
            Target::Step => body.step = Some(value),
            Target::TEnd => body.t_end = Some(value),
            Target::Method { index, name } => {
                for (i, m) in methods.iter_mut().enumerate() {
                    if index.is_none_or(|j| j == i) && has_param(&m.id, name) {
                        set(&mut m.params, name);
                    }
                }
            }
        }
    }

    /// Whether an error of a cell's scene at `path` may come from this axis's value: the
    /// field it sets, and the checks its value enters (a velocity consistent with the
    /// constraints, a step within t_end, formulas finite and of full rank at the start).
    pub fn may_cause(&self, path: &str) -> bool {
        let field = |name: &str| path == name || path.starts_with(&format!("{name}["));
        match &self.target {
            Target::Param(name) => {
                path == format!("params.{name}")
                    || field("q")
                    || field("v")
                    || path.starts_with("system.")
            }
            Target::Q(_) => field("q") || field("v") || path.starts_with("system."),
            Target::V(_) => field("v"),
            Target::Step | Target::TEnd => field("step") || field("t_end"),
            Target::Method { .. } => false,
        }
    }
}

/// Whether method `id` has a parameter `name`.
pub fn has_param(id: &str, name: &str) -> bool {
    nhlab_core::method_infos()
        .iter()
        .any(|info| info.id == id && info.params.iter().any(|p| p.name == name))
}

fn too_many(path: String, n: f64, max: u64) -> AppError {
    AppError::invalid(
        path,
        format!("{} values exceed the limit of {max} cells per sweep (max_sweep_cells)", Short(n)),
    )
}

/// `[start, stop, n]` → n values from start to stop, in a straight line or (`log`) a geometric
/// progression; the ends exactly as given.
fn spaced(path: &str, spec: &[f64], max: u64, log: bool) -> Result<Vec<f64>, AppError> {
    let [start, stop, n] = *spec else {
        return Err(AppError::invalid(path, "give [start, stop, n]: three numbers"));
    };
    if !(start.is_finite() && stop.is_finite()) {
        return Err(AppError::invalid(path, "start and stop must be finite"));
    }
    if !(n >= 1.0 && n.fract() == 0.0) {
        return Err(AppError::invalid(
            path,
            format!("n must be a whole number ≥ 1, got {}", Short(n)),
        ));
    }
    if n > max as f64 {
        return Err(too_many(path.to_owned(), n, max));
    }
    if log && !(start > 0.0 && stop > 0.0) {
        return Err(AppError::invalid(
            path,
            format!(
                "a logarithmic axis needs start and stop above 0, got {} and {}",
                Short(start),
                Short(stop)
            ),
        ));
    }
    let n = n as usize;
    let (a, b) = if log { (start.ln(), stop.ln()) } else { (start, stop) };
    Ok((0..n)
        .map(|i| match i {
            0 => start,
            _ if i == n - 1 => stop,
            _ => {
                let x = a + (b - a) * (i as f64 / (n - 1) as f64);
                // To 15 significant digits: 0.4, not 0.39999999999999997, in the rows and
                // links a reader sees; a change of an ulp or two in a swept value.
                let x = if log { x.exp() } else { x };
                format!("{x:.14e}").parse().unwrap_or(x)
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_parse_into_their_targets() {
        assert_eq!(Target::parse("params.epsilon"), Some(Target::Param("epsilon".into())));
        assert_eq!(Target::parse("q[2]"), Some(Target::Q(2)));
        assert_eq!(Target::parse("v[0]"), Some(Target::V(0)));
        assert_eq!(Target::parse("step"), Some(Target::Step));
        assert_eq!(Target::parse("t_end"), Some(Target::TEnd));
        assert_eq!(
            Target::parse("methods.alpha"),
            Some(Target::Method { index: None, name: "alpha".into() })
        );
        assert_eq!(
            Target::parse("methods[1].alpha"),
            Some(Target::Method { index: Some(1), name: "alpha".into() })
        );
        for bad in [
            "",
            "params.",
            "q[]",
            "q[-1]",
            "q[x]",
            "q[01]",
            "q[+1]",
            "methods[a].alpha",
            "x",
            "params.a.b",
        ] {
            assert_eq!(Target::parse(bad), None, "{bad}");
        }
    }

    #[test]
    fn spaced_values_keep_their_ends_exactly() {
        let lin = spaced("p", &[0.3, 0.7, 5.0], 100, false).unwrap();
        assert_eq!(lin.len(), 5);
        assert_eq!((lin[0], lin[4]), (0.3, 0.7));
        assert!((lin[2] - 0.5).abs() < 1e-15);
        let log = spaced("p", &[1e-3, 0.5, 12.0], 100, true).unwrap();
        assert_eq!((log[0], log[11]), (1e-3, 0.5));
        assert!(log.windows(2).all(|w| (w[1] / w[0] - (500f64).powf(1.0 / 11.0)).abs() < 1e-12));
        assert_eq!(spaced("p", &[2.0, 3.0, 1.0], 100, false).unwrap(), vec![2.0]);
        assert!(spaced("p", &[0.0, 1.0, 5.0], 100, true).is_err());
        assert!(spaced("p", &[0.0, 1.0, 2.5], 100, false).is_err());
        assert!(spaced("p", &[0.0, 1.0, 101.0], 100, false).is_err());
    }
}
