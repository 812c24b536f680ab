//! [`Gap`]: why a series has no values from some time on although its run went on. Only the
//! latitude can have one: it is defined at section crossings (`docs/model.md` §5), so it has
//! no value when the numerical driver stops returning to the section, and none when the
//! reduced passenger `u` is zero (`ℓ = a·u/|u|` is then 0/0: the passenger is at rest, as a
//! method that dissipates its energy leaves it). A run reports a gap at its end, with the
//! time of the series' last value; the undefined values themselves are left out of the
//! series rather than written as NaN.

/// Why a series stopped having values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GapReason {
    /// The reduced passenger `u` is zero at the crossings: `a·u/|u|` is undefined.
    PassengerAtRest,
    /// No section crossing for more than two driver periods before the run's end.
    NoCrossing,
}

impl GapReason {
    /// The API's id.
    pub fn id(self) -> &'static str {
        match self {
            Self::PassengerAtRest => "passenger_at_rest",
            Self::NoCrossing => "no_crossing",
        }
    }
}

/// A series' trailing gap: no value after `since` up to the run's end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// Time of the series' last value (0 when it has none).
    pub since: f64,
    /// Why.
    pub reason: GapReason,
}

impl Gap {
    /// What the page and the API say of it.
    pub fn message(&self) -> String {
        let since = short(self.since);
        match self.reason {
            GapReason::PassengerAtRest => format!(
                "no value since t = {since}: the passenger is at rest (u = 0 at the section \
                 crossings), where the latitude a·u/|u| is undefined"
            ),
            GapReason::NoCrossing => format!(
                "no value since t = {since}: the driver has not returned to the section since \
                 (no section crossing in the rest of the run)"
            ),
        }
    }
}

/// A time with four significant digits, as people read it (`73400`, `7.340e5`, `0.5`).
fn short(t: f64) -> String {
    if t == 0.0 || !t.is_finite() {
        return t.to_string();
    }
    if (1e-2..1e5).contains(&t.abs()) {
        let digits = (3 - t.abs().log10().floor() as i32).max(0) as usize;
        let s = format!("{t:.digits$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_owned() } else { s }
    } else {
        format!("{t:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_read_with_four_significant_digits() {
        assert_eq!(short(0.0), "0");
        assert_eq!(short(73404.79925), "73405");
        assert_eq!(short(1234.5678), "1235");
        assert_eq!(short(0.5), "0.5");
        assert_eq!(short(1.23456), "1.235");
        assert_eq!(short(734047.99), "7.340e5");
        let gap = Gap { since: 73404.8, reason: GapReason::PassengerAtRest };
        assert!(gap.message().starts_with("no value since t = 73405: the passenger is at rest"));
    }
}
