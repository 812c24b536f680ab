//! Work priced before admission: a request's runs, each estimated in CPU time by the core's
//! cost model ([`nhlab_core::catalogue::cost`]: ns per step of the method on the system ×
//! steps, sub-steps of a composition counted), are refused together (422, with the estimate
//! in words a person reads) when they would take more than `max_request_seconds`. The step
//! limits bound a built-in's runs; this bounds a system given as formulas too, whose step may
//! cost a thousand times a built-in's.

use crate::config::Config;
use crate::error::AppError;
use nhlab_core::catalogue::cost::RunCost;

/// Runs of one kind in a request: `runs` runs of `label`, each costing `cost`.
#[derive(Debug, Clone, PartialEq)]
pub struct Priced {
    /// What runs: a method's label (`DLA^0.5∘p8s15`), or what else computes.
    pub label: String,
    /// How many such runs.
    pub runs: f64,
    /// What each costs.
    pub cost: RunCost,
}

impl Priced {
    /// `runs` runs of `label` at `cost` each.
    pub fn new(label: impl Into<String>, runs: f64, cost: RunCost) -> Self {
        Self { label: label.into(), runs, cost }
    }

    /// Their CPU time together, in seconds.
    pub fn seconds(&self) -> f64 {
        self.runs * self.cost.seconds()
    }
}

/// The CPU seconds of `priced` together, or a 422 at `field` when that is over
/// `max_request_seconds`: the estimate, what costs most in it, the limit and `advice`.
pub fn check_price(
    priced: &[Priced],
    config: &Config,
    field: &str,
    advice: &str,
) -> Result<f64, AppError> {
    let total: f64 = priced.iter().map(Priced::seconds).sum();
    if total <= config.max_request_seconds {
        return Ok(total);
    }
    let mut groups = merged(priced);
    groups.sort_by(|a, b| b.seconds().total_cmp(&a.seconds()));
    let shown: Vec<String> = groups.iter().take(3).map(describe).collect();
    let rest: f64 = groups.iter().skip(3).map(|g| g.runs).sum();
    let more = if rest > 0.0 { format!("; and {} more runs", about(rest)) } else { String::new() };
    Err(AppError::invalid(
        field,
        format!(
            "the request would take about {} s of CPU ({}{more}), over the limit of {} s \
             (max_request_seconds); {advice}",
            about(total),
            shown.join("; "),
            about(config.max_request_seconds),
        ),
    ))
}

/// Runs of the same label, cost per step and steps, counted together.
fn merged(priced: &[Priced]) -> Vec<Priced> {
    let mut out: Vec<Priced> = Vec::new();
    for p in priced {
        match out.iter_mut().find(|g| g.label == p.label && g.cost == p.cost) {
            Some(g) => g.runs += p.runs,
            None => out.push(p.clone()),
        }
    }
    out
}

/// `16 runs of DLA^0.5∘p8s15 at about 1.2 ms per step × 1.3·10⁶ steps`.
fn describe(g: &Priced) -> String {
    let runs = if g.runs == 1.0 { "1 run".to_owned() } else { format!("{} runs", about(g.runs)) };
    format!(
        "{runs} of {} at about {} per step × {} steps",
        g.label,
        duration(g.cost.ns_per_step * 1e-9),
        about(g.cost.steps)
    )
}

/// `x` to two significant digits as a person reads it: `0.25`, `300`, `1,600`, `1.3·10⁶`.
pub fn about(x: f64) -> String {
    if !x.is_finite() {
        return if x > 0.0 { "∞".into() } else { "?".into() };
    }
    if x == 0.0 {
        return "0".into();
    }
    let exponent = x.abs().log10().floor() as i32;
    let scale = 10f64.powi(exponent - 1);
    let rounded = (x / scale).round() * scale;
    if !(1e-3..1e5).contains(&rounded.abs()) {
        let exponent = rounded.abs().log10().floor() as i32;
        let mantissa = rounded / 10f64.powi(exponent);
        let mantissa = format!("{mantissa:.1}");
        let mantissa = mantissa.strip_suffix(".0").unwrap_or(&mantissa);
        return format!("{mantissa}·10{}", superscript(exponent));
    }
    if rounded.abs() >= 1000.0 {
        let digits = format!("{:.0}", rounded.abs());
        let mut grouped = String::new();
        for (i, c) in digits.chars().enumerate() {
            if i > 0 && (digits.len() - i).is_multiple_of(3) {
                grouped.push(',');
            }
            grouped.push(c);
        }
        return if rounded < 0.0 { format!("-{grouped}") } else { grouped };
    }
    let decimals = (1 - exponent).max(0) as usize;
    let text = format!("{rounded:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

/// `seconds` in the unit that reads best: `850 ns`, `1.2 µs`, `1.2 ms`, `3.4 s`.
pub fn duration(seconds: f64) -> String {
    let (value, unit) = if seconds < 1e-6 {
        (seconds * 1e9, "ns")
    } else if seconds < 1e-3 {
        (seconds * 1e6, "µs")
    } else if seconds < 1.0 {
        (seconds * 1e3, "ms")
    } else {
        (seconds, "s")
    };
    format!("{} {unit}", about(value))
}

fn superscript(n: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let digits = n.unsigned_abs().to_string();
    let digits = digits.chars().map(|c| DIGITS[c.to_digit(10).unwrap_or(0) as usize]);
    (if n < 0 { "⁻" } else { "" }).chars().chain(digits).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_as_a_person_writes_them() {
        let cases = [
            (0.25, "0.25"),
            (300.0, "300"),
            (1600.0, "1,600"),
            (1612.0, "1,600"),
            (99_999.0, "1·10⁵"),
            (1.3e6, "1.3·10⁶"),
            (2e9, "2·10⁹"),
            (1.2, "1.2"),
            (0.0004, "4·10⁻⁴"),
            (16.0, "16"),
            (0.0, "0"),
        ];
        for (x, text) in cases {
            assert_eq!(about(x), text, "{x}");
        }
        assert_eq!(duration(1.2e-3), "1.2 ms");
        assert_eq!(duration(850e-9), "850 ns");
        assert_eq!(duration(1.66e-6), "1.7 µs");
        assert_eq!(duration(3.0), "3 s");
    }

    #[test]
    fn a_request_over_the_limit_is_refused_with_its_estimate() {
        let config = Config { max_request_seconds: 300.0, ..Config::default() };
        let heavy = RunCost { ns_per_step: 1.2e6, steps: 1.3e6 };
        let light = RunCost { ns_per_step: 100.0, steps: 1e4 };
        let runs: Vec<Priced> = (0..16)
            .map(|_| Priced::new("DLA^0.5∘p8s15", 1.0, heavy))
            .chain([Priced::new("LF", 1.0, light)])
            .collect();
        let e = check_price(&runs, &config, "t_end", "shorten t_end").unwrap_err();
        assert_eq!(e.path.as_deref(), Some("t_end"));
        assert_eq!(
            e.message,
            "the request would take about 25,000 s of CPU (16 runs of DLA^0.5∘p8s15 at about \
             1.2 ms per step × 1.3·10⁶ steps; 1 run of LF at about 100 ns per step × 10,000 \
             steps), over the limit of 300 s (max_request_seconds); shorten t_end"
        );
        // Within the limit: the total.
        let total = check_price(&runs[16..], &config, "t_end", "").unwrap();
        assert!((total - 1e-3).abs() < 1e-12);
    }
}
