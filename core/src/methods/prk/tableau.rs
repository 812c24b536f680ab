//! A partitioned Runge–Kutta tableau as a user gives it or nhlab stores it (`docs/model.md`
//! §3, "methods given as tableaux"): `a`, `b`, `c` for the positions, `a_hat`, `b_hat` for the
//! velocities and the forces, at most [`MAX_STAGES`] stages, kept inline so that a method
//! stays a small `Copy` value. [`Tableau::checked`] refuses what no step can be built from
//! (sizes, non-finite entries, weights that do not sum to 1, nodes that are not the row
//! sums); [`Tableau::symmetric`] says whether the pair is symmetric.

use crate::InputError;
use crate::linalg::lu_in_place;

/// Most stages a tableau may have.
pub const MAX_STAGES: usize = 5;

/// Entries closer than this are taken equal by the checks (the stored tableaux are exact to
/// a few ulps; a user's typed decimals to more digits than that).
const TOLERANCE: f64 = 1e-12;

/// A partitioned Runge–Kutta tableau with `stages` stages; entries past them are zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tableau {
    /// Stages s.
    pub stages: usize,
    /// Positions' coefficients, s×s.
    pub a: [[f64; MAX_STAGES]; MAX_STAGES],
    /// Positions' weights.
    pub b: [f64; MAX_STAGES],
    /// Nodes, the row sums of `a` (those of `a_hat` may differ: Lobatto IIIB's do).
    pub c: [f64; MAX_STAGES],
    /// Velocities' and forces' coefficients, s×s.
    pub a_hat: [[f64; MAX_STAGES]; MAX_STAGES],
    /// Velocities' weights.
    pub b_hat: [f64; MAX_STAGES],
}

/// A tableau as a request gives it: rows of numbers; `c` defaults to the row sums of `a`,
/// `a_hat` and `b_hat` to `a` and `b` (a Runge–Kutta method that is not partitioned).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TableauSpec {
    /// `a`, s rows of s.
    pub a: Vec<Vec<f64>>,
    /// `b`, s entries.
    pub b: Vec<f64>,
    /// `c`, s entries, if given.
    pub c: Option<Vec<f64>>,
    /// `a_hat`, s rows of s, if given.
    pub a_hat: Option<Vec<Vec<f64>>>,
    /// `b_hat`, s entries, if given.
    pub b_hat: Option<Vec<f64>>,
}

/// A tableau as a request names it: a stored one by id, or given.
#[derive(Debug, Clone, PartialEq)]
pub enum TableauChoice {
    /// A stored tableau's id (`gauss2`, …).
    Stored(String),
    /// The tableau itself.
    Given(TableauSpec),
}

/// Whether `x` and `y` are equal to [`TOLERANCE`]; false where either is NaN.
fn close(x: f64, y: f64) -> bool {
    (x - y).abs() <= TOLERANCE
}

fn error(field: &str, message: String) -> InputError {
    InputError::Tableau { field: format!("tableau.{field}"), message }
}

fn vector(field: &str, given: &[f64], s: usize) -> Result<[f64; MAX_STAGES], InputError> {
    if given.len() != s {
        return Err(error(field, format!("{field} has {} entries; the tableau has {s} stages", given.len())));
    }
    let mut out = [0.0; MAX_STAGES];
    for (i, &x) in given.iter().enumerate() {
        if !x.is_finite() {
            return Err(error(&format!("{field}[{i}]"), format!("{field}[{i}] is not a finite number")));
        }
        out[i] = x;
    }
    Ok(out)
}

fn matrix(field: &str, rows: &[Vec<f64>], s: usize) -> Result<[[f64; MAX_STAGES]; MAX_STAGES], InputError> {
    if rows.len() != s {
        return Err(error(field, format!("{field} has {} rows; the tableau has {s} stages", rows.len())));
    }
    let mut out = [[0.0; MAX_STAGES]; MAX_STAGES];
    for (i, row) in rows.iter().enumerate() {
        out[i] = vector(&format!("{field}[{i}]"), row, s)?;
    }
    Ok(out)
}

impl Tableau {
    /// The tableau of `spec`, checked: s = len(b) between 1 and [`MAX_STAGES`], every array
    /// of size s (s×s), finite entries, Σb = Σb̂ = 1, and `c` the row sums of `a`.
    pub fn checked(spec: &TableauSpec) -> Result<Self, InputError> {
        let s = spec.b.len();
        if !(1..=MAX_STAGES).contains(&s) {
            return Err(error(
                "b",
                format!("b has {s} entries; a tableau has 1 to {MAX_STAGES} stages, one weight each"),
            ));
        }
        let a = matrix("a", &spec.a, s)?;
        let b = vector("b", &spec.b, s)?;
        let a_hat = match &spec.a_hat {
            Some(rows) => matrix("a_hat", rows, s)?,
            None => a,
        };
        let b_hat = match &spec.b_hat {
            Some(w) => vector("b_hat", w, s)?,
            None => b,
        };
        let row_sums = |m: &[[f64; MAX_STAGES]; MAX_STAGES]| {
            let mut out = [0.0; MAX_STAGES];
            for i in 0..s {
                out[i] = m[i][..s].iter().sum();
            }
            out
        };
        let c = match &spec.c {
            Some(c) => vector("c", c, s)?,
            None => row_sums(&a),
        };
        for (name, w) in [("b", &b), ("b_hat", &b_hat)] {
            let sum: f64 = w[..s].iter().sum();
            if !close(sum, 1.0) {
                return Err(error(name, format!("the weights {name} sum to {sum}, not 1 (order 1 needs Σ{name} = 1)")));
            }
        }
        let sums = row_sums(&a);
        // Also refused where a row sum overflows: NaN fails every comparison.
        if let Some(i) = (0..s).find(|&i| !close(sums[i], c[i])) {
            return Err(error(
                &format!("c[{i}]"),
                format!("c[{i}] = {}, but row {i} of a sums to {}: c_i = Σ_j a_ij", c[i], sums[i]),
            ));
        }
        Ok(Self { stages: s, a, b, c, a_hat, b_hat })
    }

    /// The tableau as a request would give it.
    pub fn spec(&self) -> TableauSpec {
        let s = self.stages;
        let rows = |m: &[[f64; MAX_STAGES]; MAX_STAGES]| m[..s].iter().map(|r| r[..s].to_vec()).collect();
        TableauSpec {
            a: rows(&self.a),
            b: self.b[..s].to_vec(),
            c: Some(self.c[..s].to_vec()),
            a_hat: Some(rows(&self.a_hat)),
            b_hat: Some(self.b_hat[..s].to_vec()),
        }
    }

    /// Whether `a_hat = a` and `b_hat = b`: a Runge–Kutta method, not partitioned.
    pub fn is_unpartitioned(&self) -> bool {
        self.a == self.a_hat && self.b == self.b_hat
    }

    /// Whether both halves are symmetric: `b_j = b_{s+1−j}` and
    /// `a_ij + a_{s+1−i, s+1−j} = b_j` (Hairer, Lubich & Wanner, V.2), the same for the hats.
    /// Then the method taken without a constraint is symmetric.
    pub fn symmetric(&self) -> bool {
        let s = self.stages;
        let half = |a: &[[f64; MAX_STAGES]; MAX_STAGES], b: &[f64; MAX_STAGES]| {
            (0..s).all(|j| (b[j] - b[s - 1 - j]).abs() <= TOLERANCE)
                && (0..s).all(|i| (0..s).all(|j| (a[i][j] + a[s - 1 - i][s - 1 - j] - b[j]).abs() <= TOLERANCE))
        };
        half(&self.a, &self.b) && half(&self.a_hat, &self.b_hat)
    }

    /// The stages whose multipliers enter some stage velocity: the nonzero columns of `a_hat`.
    pub fn forced_stages(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.stages).filter(|&j| (0..self.stages).any(|i| self.a_hat[i][j] != 0.0))
    }

    /// The stages that carry a weighted constraint: the nonzero rows of `a`.
    pub fn constrained_stages(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.stages).filter(|&i| self.a[i][..self.stages].iter().any(|&x| x != 0.0))
    }

    /// Whether the stage conditions fix the multipliers: to first order in h the conditions
    /// read the multipliers through `(a â)_ij A M⁻¹ Aᵀ` (rows: the constrained stages,
    /// columns: the forced ones), so that matrix must be invertible. Classical RK4 has as
    /// many rows as columns, but its first condition sees no multiplier: refused.
    pub fn stage_conditions_fix_multipliers(&self) -> bool {
        let s = self.stages;
        let rows: Vec<usize> = self.constrained_stages().collect();
        let cols: Vec<usize> = self.forced_stages().collect();
        if rows.len() != cols.len() {
            return false;
        }
        let k = rows.len();
        let mut m = [0.0; MAX_STAGES * MAX_STAGES];
        for (r, &i) in rows.iter().enumerate() {
            for (c, &j) in cols.iter().enumerate() {
                m[r * k + c] = (0..s).map(|l| self.a[i][l] * self.a_hat[l][j]).sum();
            }
        }
        let scale = m[..k * k].iter().fold(0.0_f64, |x, y| x.max(y.abs()));
        // LU with partial pivoting; a pivot below round-off is singular.
        let mut swaps = [0; MAX_STAGES];
        lu_in_place(&mut m[..k * k], k, &mut swaps[..k]).is_some()
            && (0..k).all(|p| m[p * k + p].abs() > 1e-12 * scale)
    }

    /// Whether the midpoint condition fixes its multiplier: to first order it reads it
    /// through `Σ_j b_j Σ_l â_jl` (½ for a method of order 2), which must not vanish.
    pub fn midpoint_condition_fixes_its_multiplier(&self) -> bool {
        let s = self.stages;
        let weight: f64 = (0..s).map(|j| self.b[j] * self.a_hat[j][..s].iter().sum::<f64>()).sum();
        weight.abs() > TOLERANCE
    }

    /// Whether the end projection is the last stage's own constraint force, as in the
    /// Lobatto IIIA–IIIB pairs: the last stage is the step's end (`a`'s last row is `b`), and
    /// its multiplier enters no stage (`a_hat`'s last column is zero) but the end velocity.
    pub fn ends_on_a_stage(&self) -> bool {
        let s = self.stages;
        (0..s).all(|j| (self.a[s - 1][j] - self.b[j]).abs() <= TOLERANCE)
            && (0..s).all(|i| self.a_hat[i][s - 1] == 0.0)
            && self.b_hat[s - 1] != 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(a: Vec<Vec<f64>>, b: Vec<f64>) -> TableauSpec {
        TableauSpec { a, b, ..TableauSpec::default() }
    }

    #[test]
    fn overflowing_rows_and_bad_weights_are_refused_at_their_entry() {
        let huge = spec(vec![vec![1e308, 1e308], vec![1e308, 1e308]], vec![2.0, -1.0]);
        let e = Tableau::checked(&huge).unwrap_err();
        assert_eq!(e.field(), "tableau.c[0]", "{e}");
        let e = Tableau::checked(&spec(vec![vec![0.5]], vec![f64::NAN])).unwrap_err();
        assert_eq!(e.field(), "tableau.b[0]", "{e}");
    }

    #[test]
    fn stage_conditions_fix_the_multipliers_of_gauss_not_of_rk4() {
        let r3 = 3f64.sqrt();
        let gauss2 = spec(vec![vec![0.25, 0.25 - r3 / 6.0], vec![0.25 + r3 / 6.0, 0.25]], vec![0.5, 0.5]);
        assert!(Tableau::checked(&gauss2).unwrap().stage_conditions_fix_multipliers());
        let rk4 = spec(
            vec![vec![0.0; 4], vec![0.5, 0.0, 0.0, 0.0], vec![0.0, 0.5, 0.0, 0.0], vec![0.0, 0.0, 1.0, 0.0]],
            vec![1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
        );
        let rk4 = Tableau::checked(&rk4).unwrap();
        assert_eq!((rk4.constrained_stages().count(), rk4.forced_stages().count()), (3, 3));
        assert!(!rk4.stage_conditions_fix_multipliers());
        assert!(rk4.midpoint_condition_fixes_its_multiplier());
    }
}
