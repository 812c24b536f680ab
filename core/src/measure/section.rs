//! [`Section`]: a Poincaré section of a run. The surface is a formula s(q, q̇, t) (an
//! [`Observables`] of one); each time a step crosses s = 0 in the asked direction, the
//! crossing is located inside the step and the plotted observables are taken there.
//!
//! Inside a step nhlab knows the states at both ends. The configuration between them is the
//! cubic Hermite interpolant of q with q̇ as its derivative (error O(h⁴) for a smooth
//! trajectory; the velocity, its derivative, O(h³)); the crossing is the root of s along it,
//! found by regula falsi (Illinois) to round-off. A method of order p ≤ 3 thus places its
//! crossings as accurately as its states; one of higher order (a composition) to O(h⁴) in q.

use super::observables::{Observables, Scratch};

/// Which crossings of s = 0 count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// s from negative to zero or positive.
    Up,
    /// s from positive to zero or negative.
    Down,
    /// Either.
    Both,
}

/// A section: its surface and what is plotted at each crossing.
#[derive(Debug, Clone)]
pub struct Section {
    /// The surface s, the first (only) observable.
    pub surface: Observables,
    /// The plotted observables.
    pub plot: Observables,
    /// Which crossings count.
    pub direction: Direction,
}

/// One run's pass over a section: the previous state, the interpolated one and scratch for
/// the evaluations.
#[derive(Debug, Clone)]
pub struct SectionTracker {
    /// The previous step's end: t, q, q̇ and s there (`None` before the start).
    prev: Option<(f64, Vec<f64>, Vec<f64>, f64)>,
    /// The state inside a step where the surface is evaluated.
    inside: Inside,
    plot: Scratch,
}

/// A state inside a step and the surface's value there.
#[derive(Debug, Clone)]
struct Inside {
    q: Vec<f64>,
    v: Vec<f64>,
    surface: Scratch,
    s: [f64; 1],
}

impl Inside {
    /// The surface at (t, q, q̇).
    fn surface(&mut self, section: &Section, t: f64, q: &[f64], v: &[f64]) -> f64 {
        section.surface.eval(t, q, v, &mut self.surface, &mut self.s);
        self.s[0]
    }

    /// The surface at θ of the step from state 0 to state 1, the interpolated state kept.
    fn surface_at(
        &mut self,
        section: &Section,
        theta: f64,
        (t0, q0, v0): (f64, &[f64], &[f64]),
        (t1, q1, v1): (f64, &[f64], &[f64]),
    ) -> f64 {
        let h = t1 - t0;
        hermite(theta, h, (q0, v0), (q1, v1), &mut self.q, &mut self.v);
        section.surface.eval(t0 + theta * h, &self.q, &self.v, &mut self.surface, &mut self.s);
        self.s[0]
    }
}

impl SectionTracker {
    /// A tracker for states of `dof` coordinates.
    pub fn new(section: &Section, dof: usize) -> Self {
        let inside = Inside {
            q: vec![0.0; dof],
            v: vec![0.0; dof],
            surface: section.surface.scratch(),
            s: [0.0],
        };
        Self { prev: None, inside, plot: section.plot.scratch() }
    }

    /// Takes the state at the end of a step (the start first); where the step from the
    /// previous state crossed the section, writes the plotted observables into `out` and
    /// returns the crossing's time.
    pub fn observe(
        &mut self,
        section: &Section,
        t: f64,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
    ) -> Option<f64> {
        let s1 = self.inside.surface(section, t, q, v);
        let Some((t0, q0, v0, s0)) = &mut self.prev else {
            self.prev = Some((t, q.to_vec(), v.to_vec(), s1));
            return None;
        };
        let mut found = None;
        if crosses(section.direction, *s0, s1) {
            let tc = locate(section, &mut self.inside, (*t0, q0, v0, *s0), (t, q, v, s1));
            section.plot.eval(tc, &self.inside.q, &self.inside.v, &mut self.plot, out);
            found = Some(tc);
        }
        (*t0, *s0) = (t, s1);
        q0.copy_from_slice(q);
        v0.copy_from_slice(v);
        found
    }
}

/// The crossing's time between two states with s of opposite signs (or s1 = 0), by regula
/// falsi with the Illinois modification (the value kept twice halved), to round-off; leaves
/// the interpolated state there in `inside`.
fn locate(
    section: &Section,
    inside: &mut Inside,
    (t0, q0, v0, s0): (f64, &[f64], &[f64], f64),
    (t1, q1, v1, s1): (f64, &[f64], &[f64], f64),
) -> f64 {
    let (start, end) = ((t0, q0, v0), (t1, q1, v1));
    let (mut a, mut fa, mut b, mut fb): (f64, f64, f64, f64) = (0.0, s0, 1.0, s1);
    let mut side = 0;
    let mut theta = 1.0;
    for _ in 0..60 {
        if fb == 0.0 || (b - a).abs() < 1e-15 {
            break;
        }
        theta = (a * fb - b * fa) / (fb - fa);
        if !theta.is_finite() {
            theta = 0.5 * (a + b);
        }
        let f = inside.surface_at(section, theta, start, end);
        if f == 0.0 {
            break;
        }
        if (f > 0.0) == (fb > 0.0) {
            (b, fb) = (theta, f);
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            (a, fa) = (theta, f);
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    // The state at the final θ, whichever branch ended the search.
    inside.surface_at(section, theta, start, end);
    t0 + theta * (t1 - t0)
}

/// Whether s going from `s0` to `s1` crosses zero in `direction` (reaching zero counts,
/// leaving it does not: a crossing is counted once).
fn crosses(direction: Direction, s0: f64, s1: f64) -> bool {
    let up = s0 < 0.0 && s1 >= 0.0;
    let down = s0 > 0.0 && s1 <= 0.0;
    match direction {
        Direction::Up => up,
        Direction::Down => down,
        Direction::Both => up || down,
    }
}

/// The cubic Hermite interpolant at θ ∈ [0, 1] of a step of length h from (q0, v0) to
/// (q1, v1), q̇ taken as q's derivative: q(θ) into `q`, its time derivative into `v`.
fn hermite(
    theta: f64,
    h: f64,
    (q0, v0): (&[f64], &[f64]),
    (q1, v1): (&[f64], &[f64]),
    q: &mut [f64],
    v: &mut [f64],
) {
    let (t2, t3) = (theta * theta, theta * theta * theta);
    let (h00, h10, h01, h11) =
        (2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + theta, -2.0 * t3 + 3.0 * t2, t3 - t2);
    let (d00, d10, d01, d11) = (
        6.0 * t2 - 6.0 * theta,
        3.0 * t2 - 4.0 * theta + 1.0,
        -6.0 * t2 + 6.0 * theta,
        3.0 * t2 - 2.0 * theta,
    );
    for i in 0..q.len() {
        q[i] = h00 * q0[i] + h10 * h * v0[i] + h01 * q1[i] + h11 * h * v1[i];
        v[i] = (d00 * q0[i] + d01 * q1[i]) / h + d10 * v0[i] + d11 * v1[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formula::Limits;

    fn obs(given: &[(&str, &str)], coordinates: &[&str]) -> Observables {
        let given: Vec<(String, String)> =
            given.iter().map(|(n, f)| ((*n).to_owned(), (*f).to_owned())).collect();
        let coordinates: Vec<String> = coordinates.iter().map(|c| (*c).to_owned()).collect();
        Observables::compile(&given, &coordinates, &[], &Limits::default()).expect("compiles")
    }

    /// The harmonic oscillator's exact states x = sin(t − 1) at steps of h: the section
    /// x = 0 upwards is crossed at t = 1 + 2πk, with ẋ = 1 there.
    #[test]
    fn crossings_of_an_exact_trajectory_are_found_to_the_interpolants_order() {
        let section = Section {
            surface: obs(&[("s", "x")], &["x"]),
            plot: obs(&[("v", "x_dot")], &["x"]),
            direction: Direction::Up,
        };
        let errors: Vec<f64> = [0.1, 0.05]
            .iter()
            .map(|&h| {
                let mut tracker = SectionTracker::new(&section, 1);
                let mut out = [0.0];
                let mut worst: f64 = 0.0;
                // x = sin(t − 1): crossing upwards at t = 1 + 2πk, where ẋ = 1.
                for k in 0..=200 {
                    let t = k as f64 * h;
                    let (q, v) = ([(t - 1.0).sin()], [(t - 1.0).cos()]);
                    if let Some(tc) = tracker.observe(&section, t, &q, &v, &mut out) {
                        let k = ((tc - 1.0) / std::f64::consts::TAU).round();
                        let exact = 1.0 + std::f64::consts::TAU * k;
                        worst = worst.max((tc - exact).abs()).max((out[0] - 1.0).abs());
                    }
                }
                worst
            })
            .collect();
        assert!(errors[0] < 1e-4, "{errors:?}");
        // At least third order (the time of a crossing of a Hermite cubic is fourth order).
        assert!(errors[0] / errors[1] > 7.0, "{errors:?}");
    }

    #[test]
    fn only_crossings_in_the_direction_asked_count() {
        let surface = obs(&[("s", "x")], &["x"]);
        for (direction, expected) in
            [(Direction::Up, 1), (Direction::Down, 1), (Direction::Both, 2)]
        {
            let section =
                Section { surface: surface.clone(), plot: obs(&[("x", "x")], &["x"]), direction };
            let mut tracker = SectionTracker::new(&section, 1);
            let mut out = [0.0];
            let found = [-1.0, 1.0, -1.0]
                .iter()
                .enumerate()
                .filter(|(k, x)| {
                    tracker.observe(&section, *k as f64, &[**x], &[0.0], &mut out).is_some()
                })
                .count();
            assert_eq!(found, expected, "{direction:?}");
        }
    }
}
