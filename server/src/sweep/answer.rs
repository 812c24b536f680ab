//! A sweep's JSON or CSV answer, written as its cells complete. Each worker encodes the rows
//! of the cell it has just computed ([`Encoder::cell`]: JSON objects, or CSV lines), and
//! [`AnswerBody`] appends the encoded cells to the answer in cell order, holding the few that
//! complete ahead of their turn. The rows never wait as structures: what a sweep holds at its
//! peak is its answer's text (and its checked cells), not the rows, their JSON values and
//! their text besides, which took four times the answer's size.
//!
//! The bytes are those of serializing the whole [`SweepResponse`](crate::views::SweepResponse)
//! (the head's fields, then `rows`), or of [`csv::write`] over its rows.

use crate::error::AppError;
use crate::sweep::csv;
use crate::views::{SweepCell, SweepHead};
use std::collections::BTreeMap;
use std::sync::Arc;

/// How a sweep's rows are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// One JSON document: the head's fields and `rows`.
    Json,
    /// CSV: a header line and a line per row.
    Csv,
}

/// Encodes a cell's rows; cheap to clone, one per worker.
#[derive(Debug, Clone)]
pub struct Encoder {
    format: Format,
    /// CSV's columns.
    columns: Arc<csv::Columns>,
}

impl Encoder {
    /// An encoder of the rows of the sweep `head` as `format`.
    pub fn new(head: &SweepHead, format: Format) -> Self {
        Self { format, columns: Arc::new(csv::Columns::of(head)) }
    }

    /// The text of `cell`'s rows: JSON objects separated by commas, or CSV lines.
    pub fn cell(&self, cell: &SweepCell) -> Result<Vec<u8>, AppError> {
        let error = |e: serde_json::Error| {
            AppError::internal(format!("internal error: writing a sweep's row: {e}"))
        };
        match self.format {
            Format::Json => {
                let mut out = Vec::new();
                for (k, row) in cell.rows.iter().enumerate() {
                    if k > 0 {
                        out.push(b',');
                    }
                    serde_json::to_writer(&mut out, row).map_err(error)?;
                }
                Ok(out)
            }
            Format::Csv => {
                let mut out = String::new();
                // One row's JSON value at a time: the columns are read from it as from a
                // merged shard file's rows.
                for row in &cell.rows {
                    let value = serde_json::to_value(row).map_err(error)?;
                    csv::write_row(&mut out, &self.columns, &value);
                }
                Ok(out.into_bytes())
            }
        }
    }
}

/// The answer being written: the head, then the cells in order as they arrive.
#[derive(Debug)]
pub struct AnswerBody {
    format: Format,
    body: Vec<u8>,
    /// The next cell to write.
    next: usize,
    /// Whether a row has been written (JSON rows are separated by commas).
    any: bool,
    /// Cells that completed before `next`, encoded.
    ahead: BTreeMap<usize, Vec<u8>>,
}

impl AnswerBody {
    /// An answer to the sweep `head` as `format`, with room for `capacity` bytes (memory
    /// that is only reserved, not touched, until written).
    pub fn new(head: &SweepHead, format: Format, capacity: usize) -> Result<Self, AppError> {
        let mut body = Vec::with_capacity(capacity);
        match format {
            Format::Json => {
                // The head as an object, its closing brace replaced by the rows.
                serde_json::to_writer(&mut body, head).map_err(|e| {
                    AppError::internal(format!("internal error: writing JSON: {e}"))
                })?;
                body.pop();
                body.extend_from_slice(b",\"rows\":[");
            }
            Format::Csv => {
                body.extend_from_slice(csv::header(&csv::Columns::of(head)).as_bytes());
            }
        }
        Ok(Self { format, body, next: 0, any: false, ahead: BTreeMap::new() })
    }

    /// Adds cell `c`'s encoded rows: written now if it is the next cell (with those that
    /// were waiting for it), kept until its turn otherwise.
    pub fn push(&mut self, c: usize, text: Vec<u8>) {
        if c != self.next {
            self.ahead.insert(c, text);
            return;
        }
        self.write(&text);
        self.next += 1;
        while let Some(text) = self.ahead.remove(&self.next) {
            self.write(&text);
            self.next += 1;
        }
    }

    fn write(&mut self, text: &[u8]) {
        if self.format == Format::Json && self.any && !text.is_empty() {
            self.body.push(b',');
        }
        self.any |= !text.is_empty();
        self.body.extend_from_slice(text);
    }

    /// The whole answer, once every one of the `cells` has been added; an error if one is
    /// missing (a worker stopped: the sweep was cancelled or a worker was lost).
    pub fn finish(mut self, cells: usize) -> Result<Vec<u8>, AppError> {
        if self.next != cells || !self.ahead.is_empty() {
            return Err(AppError::internal("internal error: a sweep's cell was not computed"));
        }
        if self.format == Format::Json {
            self.body.extend_from_slice(b"]}");
        }
        Ok(self.body)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::views::AxisView;

    fn head() -> SweepHead {
        SweepHead {
            axes: vec![AxisView { path: "step".into(), values: vec![0.1, 0.2, 0.3] }],
            methods: Vec::new(),
            integrals: vec!["energy".into()],
            observables: Vec::new(),
            cells: 3,
            criterion: "c".into(),
        }
    }

    #[test]
    fn cells_are_written_in_order_whatever_order_they_come_in() {
        let mut body = AnswerBody::new(&head(), Format::Json, 0).unwrap();
        body.push(2, b"{\"c\":2},{\"c\":2}".to_vec());
        body.push(0, b"{\"c\":0}".to_vec());
        assert_eq!(body.ahead.len(), 1, "cell 2 waits for cell 1");
        body.push(1, b"{\"c\":1}".to_vec());
        let text = String::from_utf8(body.finish(3).unwrap()).unwrap();
        let whole = serde_json::to_string(&head()).unwrap();
        let rows = r#""rows":[{"c":0},{"c":1},{"c":2},{"c":2}]}"#;
        assert_eq!(text, format!("{},{rows}", &whole[..whole.len() - 1]));
        serde_json::from_str::<serde_json::Value>(&text).expect("JSON");
    }

    #[test]
    fn a_missing_cell_is_an_error() {
        let mut body = AnswerBody::new(&head(), Format::Csv, 0).unwrap();
        body.push(0, b"0,...\n".to_vec());
        body.push(2, b"2,...\n".to_vec());
        assert!(body.finish(3).is_err());
        let mut body = AnswerBody::new(&head(), Format::Csv, 0).unwrap();
        body.push(0, b"0,...\n".to_vec());
        assert!(body.finish(3).is_err());
    }
}
