//! A sweep's rows as CSV (RFC 4180): one header line, then one line per row with the same
//! numbers as the JSON rows (written as JSON writes them), a verdict's numbers in columns
//! `<integral>.kind`, `.max`, `.early`, `.late`, `.ratio`, a gap's start in
//! `<integral>.gap_since` (empty without one), the observables at t_end asked for in
//! `observables.<name>`, the method's label under `method` and the row's `/simulate` body as
//! JSON text in the last column. Nulls are empty fields.
//! Rows come as JSON values, one at a time, so that merged shard files are written by the same
//! code: the server's answer writes each cell's rows as the cell completes ([`header`], then
//! [`write_row`]), [`write`] all of a merge's.

use serde_json::Value;
use std::fmt::Write;

const VERDICT: [&str; 5] = ["kind", "max", "early", "late", "ratio"];

/// What a sweep's CSV has columns for: the axes' paths, the integrals measured and the
/// observables taken at t_end.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Columns {
    /// The axes' paths.
    pub axes: Vec<String>,
    /// The integrals measured.
    pub integrals: Vec<String>,
    /// The observables' names.
    pub observables: Vec<String>,
}

impl Columns {
    /// The columns of the sweep `head`.
    pub fn of(head: &crate::views::SweepHead) -> Self {
        Self {
            axes: head.axes.iter().map(|a| a.path.clone()).collect(),
            integrals: head.integrals.clone(),
            observables: head.observables.clone(),
        }
    }
}

/// The CSV text of `rows` of a sweep with these `columns`.
pub fn write(columns: &Columns, rows: impl Iterator<Item = Value>) -> String {
    let mut out = header(columns);
    for row in rows {
        write_row(&mut out, columns, &row);
    }
    out
}

/// The header line of a sweep with these `columns`.
pub fn header(Columns { axes, integrals, observables }: &Columns) -> String {
    let mut out = String::new();
    let mut header: Vec<String> = vec!["cell".into()];
    header.extend(axes.iter().cloned());
    header.extend(
        ["method_index", "method", "status", "error", "steps", "cpu_ms", "newton_iterations"]
            .map(String::from),
    );
    for i in integrals {
        header.extend(VERDICT.iter().map(|f| format!("{i}.{f}")));
        header.push(format!("{i}.gap_since"));
    }
    header.extend(observables.iter().map(|o| format!("observables.{o}")));
    header.push("simulate".into());
    line(&mut out, header.iter().map(|h| field(h)));
    out
}

/// Appends the line of one row (a JSON row, as the answer gives it) to `out`.
pub fn write_row(out: &mut String, columns: &Columns, row: &Value) {
    let Columns { axes, integrals, observables } = columns;
    let mut fields = vec![scalar(&row["cell"])];
    let values = row["values"].as_array().map(Vec::as_slice).unwrap_or_default();
    fields.extend((0..axes.len()).map(|k| values.get(k).map_or(String::new(), scalar)));
    fields.push(scalar(&row["method_index"]));
    fields.push(scalar(&row["method"]["label"]));
    for key in ["status", "error", "steps", "cpu_ms", "newton_iterations"] {
        fields.push(scalar(&row[key]));
    }
    for i in integrals {
        let verdict = &row["verdicts"][i.as_str()];
        fields.extend(VERDICT.iter().map(|f| scalar(&verdict[*f])));
        fields.push(scalar(&row["gaps"][i.as_str()]["since"]));
    }
    fields.extend(observables.iter().map(|o| scalar(&row["observables"][o.as_str()])));
    fields.push(row["simulate"].to_string());
    line(out, fields.iter().map(|f| field(f)));
}

/// A JSON scalar as text: strings bare, numbers as JSON writes them, null (or absent) empty.
fn scalar(v: &Value) -> String {
    match v {
        Value::Null => String::new(),
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// A field, quoted where it holds a comma, a quote or a line break.
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

fn line(out: &mut String, fields: impl Iterator<Item = String>) {
    let fields: Vec<String> = fields.collect();
    let _ = writeln!(out, "{}", fields.join(","));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_become_tidy_quoted_columns() {
        let row = serde_json::json!({
            "cell": 3, "values": [0.5, 0.01], "method_index": 1,
            "method": {"id": "dla", "alpha": 0.4, "label": "DLA^0.4"},
            "status": "failed", "error": "step 7 at t = 0.06: diverged, \"too large\"",
            "steps": 6, "cpu_ms": null, "newton_iterations": 12,
            "verdicts": {"energy": {"kind": "drift", "max": 1.5e-3, "early": 1e-4, "late": 1e-3, "ratio": 10.0}},
            "gaps": {"constraint": {"since": 2.5, "reason": "no_crossing", "message": "…"}},
            "observables": {"x": 0.25, "speed": null},
            "simulate": {"system": "cvt", "step": 0.01}
        });
        let columns = Columns {
            axes: vec!["params.epsilon".into(), "step".into()],
            integrals: vec!["energy".into(), "constraint".into()],
            observables: vec!["x".into(), "speed".into()],
        };
        let text = write(&columns, [row].into_iter());
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "cell,params.epsilon,step,method_index,method,status,error,steps,cpu_ms,newton_iterations,\
             energy.kind,energy.max,energy.early,energy.late,energy.ratio,energy.gap_since,\
             constraint.kind,constraint.max,constraint.early,constraint.late,constraint.ratio,\
             constraint.gap_since,observables.x,observables.speed,simulate"
        );
        assert_eq!(
            lines[1],
            "3,0.5,0.01,1,DLA^0.4,failed,\"step 7 at t = 0.06: diverged, \"\"too large\"\"\",6,,12,\
             drift,0.0015,0.0001,0.001,10.0,,,,,,,2.5,0.25,,\"{\"\"step\"\":0.01,\"\"system\"\":\"\"cvt\"\"}\""
        );
    }
}
