//! Shards: `nhlab sweep SPEC.json --shard I/N` computes the cells `c` with `c mod N = I`
//! (strided, so that each shard gets a share of every region of the grid, the expensive
//! corners included) and writes them to a shard file: a header line ([`ShardHeader`]: the
//! spec, the shard, what is swept), then one JSON row per line, each cell's rows together.
//! The rows are written by the same serializer as `POST /sweep`'s, so `--merge` joins shard
//! files into the very bytes of its JSON answer (its timing columns aside).
//!
//! `--resume` reads a shard file that stopped midway, keeps its whole cells (a cell cut off
//! in the middle, or a last line half written, is dropped) and computes only the others.

use crate::compute::{Caches, Cancel, Delivery};
use crate::config::Config;
use crate::error::AppError;
use crate::json_object::read_object;
use crate::request::SweepRequest;
use crate::sweep::Sweep;
use crate::sweep::csv;
use crate::views::SweepCell;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use serde_json::value::RawValue;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::atomic::AtomicUsize;
use std::sync::mpsc;

/// The version of the shard file format, in its header.
pub const FORMAT: u32 = 1;

/// What can go wrong outside the sweep's own checks.
#[derive(Debug, thiserror::Error)]
pub enum ShardError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The spec is not a valid sweep (the field and why, as `POST /sweep` says it).
    #[error("{file}: {}{}", .error.path.as_ref().map_or(String::new(), |p| format!("{p}: ")), .error.message)]
    Spec {
        /// The spec file.
        file: String,
        /// The error.
        error: AppError,
    },
    /// A shard file is not what it should be.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The shard files do not make one whole sweep.
    #[error("{0}")]
    Incomplete(String),
}

/// Shard `index` of `count` (`I/N`, 0 ≤ I < N): as SLURM's `$SLURM_ARRAY_TASK_ID` of an
/// array `0-(N-1)` and Kubernetes' `$JOB_COMPLETION_INDEX` number them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// I.
    pub index: usize,
    /// N.
    pub count: usize,
}

impl Shard {
    /// The whole sweep.
    pub const WHOLE: Self = Self { index: 0, count: 1 };

    /// Whether cell `c` is this shard's.
    pub fn has(&self, c: usize) -> bool {
        c % self.count == self.index
    }
}

impl FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let parsed = s
            .split_once('/')
            .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)));
        match parsed {
            Some((index, count)) if index < count => Ok(Self { index, count }),
            _ => Err(format!("a shard is I/N with 0 ≤ I < N (e.g. 0/4), got `{s}`")),
        }
    }
}

/// A shard file's first line.
#[derive(Debug, Serialize, Deserialize)]
pub struct ShardHeader {
    /// [`FORMAT`].
    pub nhlab_sweep: u32,
    /// Which shard.
    pub shard: Shard,
    /// The spec as given.
    pub spec: Value,
    /// What is swept, as `POST /sweep` writes it.
    pub head: Box<RawValue>,
}

/// How `nhlab sweep` computes.
#[derive(Debug, Clone)]
pub struct Options {
    /// The shard to compute.
    pub shard: Shard,
    /// Where to write (standard output when `None`).
    pub out: Option<PathBuf>,
    /// Keep the whole cells of `out` and compute the others.
    pub resume: bool,
    /// Worker threads.
    pub threads: usize,
}

/// What a shard run did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Report {
    /// Cells of the shard.
    pub cells: usize,
    /// Of which found whole in the file resumed.
    pub kept: usize,
}

/// The limits of a sweep computed on one's own machine: those of a request that do not
/// protect a shared server.
pub fn local_config() -> Config {
    Config {
        max_sweep_cells: 100_000_000,
        max_sweep_steps: u64::MAX,
        max_steps_stream: u64::MAX,
        max_run_seconds: f64::INFINITY,
        max_request_seconds: f64::INFINITY,
        ..Config::default()
    }
}

/// Reads and checks a spec (a `POST /sweep` body) from `text`; `file` names it in errors.
pub fn spec(text: &str, file: &str) -> Result<(Value, Sweep), ShardError> {
    let err = |error: AppError| ShardError::Spec { file: file.to_owned(), error };
    // Read as the server reads a body (same errors, same paths); the JSON value is kept only
    // for the shard files' header.
    let req: SweepRequest = read_object(text.as_bytes()).map_err(err)?;
    let value: Value = serde_json::from_str(text).map_err(|e| err(AppError::malformed(&e)))?;
    let caches = Caches::default();
    let axis = move |scene: &nhlab_core::Scene| caches.latitude(scene);
    let sweep =
        Sweep::check(&req, &local_config(), Delivery::Stream, &axis, &|| None).map_err(err)?;
    Ok((value, sweep))
}

/// Computes `opts.shard` of the sweep in `text` (from `file`), writing its shard file.
pub fn run(text: &str, file: &str, opts: &Options) -> Result<Report, ShardError> {
    let (spec_value, sweep) = spec(text, file)?;
    let head = serde_json::to_string(&sweep.head).map_err(|e| format_error(file, &e))?;
    let header = ShardHeader {
        nhlab_sweep: FORMAT,
        shard: opts.shard,
        spec: spec_value,
        head: RawValue::from_string(head).map_err(|e| format_error(file, &e))?,
    };
    let mine: Vec<usize> = (0..sweep.cells.len()).filter(|&c| opts.shard.has(c)).collect();
    let methods = sweep.head.methods.len();
    let first_line = serde_json::to_string(&header).map_err(|e| format_error(file, &e))? + "\n";
    let (mut sink, kept): (Box<dyn Write>, Vec<usize>) = match &opts.out {
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(first_line.as_bytes())
                .map_err(|source| ShardError::Io { path: "-".into(), source })?;
            (Box::new(out), Vec::new())
        }
        Some(path) => {
            let io = |source| ShardError::Io { path: path.clone(), source };
            if opts.resume && has_header(path) {
                let kept = keep_whole(path, &header, methods)?;
                let f = std::fs::OpenOptions::new().append(true).open(path).map_err(io)?;
                (Box::new(f), kept)
            } else {
                let mut f = File::create(path).map_err(io)?;
                f.write_all(first_line.as_bytes()).map_err(io)?;
                (Box::new(f), Vec::new())
            }
        }
    };
    let todo: Vec<usize> =
        mine.iter().copied().filter(|c| kept.binary_search(c).is_err()).collect();
    let out_path = opts.out.clone().unwrap_or_else(|| "-".into());
    compute(&sweep, &todo, opts.threads, &Cancel::default(), |cell| {
        let mut text = String::new();
        for row in &cell.rows {
            text += &serde_json::to_string(row).map_err(|e| format_error(file, &e))?;
            text.push('\n');
        }
        sink.write_all(text.as_bytes())
            .and_then(|()| sink.flush())
            .map_err(|source| ShardError::Io { path: out_path.clone(), source })
    })?;
    Ok(Report { cells: mine.len(), kept: kept.len() })
}

/// Computes `cells` of `sweep` on `threads` workers, handing each cell to `write` as it
/// completes (on this thread). Setting `cancel` (from another thread) stops the runs in
/// flight and the cells not started; neither is handed to `write`.
pub fn compute(
    sweep: &Sweep,
    cells: &[usize],
    threads: usize,
    cancel: &Cancel,
    mut write: impl FnMut(SweepCell) -> Result<(), ShardError>,
) -> Result<(), ShardError> {
    let caches = Caches::default();
    let axis = |scene: &nhlab_core::Scene| caches.latitude(scene);
    let next = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        let (tx, rx) = mpsc::sync_channel::<SweepCell>(64);
        for _ in 0..threads.clamp(1, cells.len().max(1)) {
            let tx = tx.clone();
            let (next, cancel, axis) = (&next, &cancel, &axis);
            scope.spawn(move || {
                // One's own machine: no time limit.
                sweep.work(cells, next, (cancel, None), axis, &mut |cell| tx.send(cell).is_ok())
            });
        }
        drop(tx);
        for cell in rx {
            if let Err(e) = write(cell) {
                cancel.cancel();
                return Err(e);
            }
        }
        Ok(())
    })
}

fn format_error(file: &str, e: &serde_json::Error) -> ShardError {
    ShardError::Format { path: file.into(), message: e.to_string() }
}

/// Whether `path` holds at least a whole header line (a shard killed right after creating
/// its file holds less: it starts over).
fn has_header(path: &Path) -> bool {
    File::open(path)
        .ok()
        .and_then(|f| BufReader::new(f).lines().next()?.ok())
        .is_some_and(|line| serde_json::from_str::<ShardHeader>(&line).is_ok())
}

/// One parsed row line: its cell and method, and its bytes.
struct RowLine {
    cell: usize,
    method_index: usize,
    raw: Box<RawValue>,
}

#[derive(Deserialize)]
struct RowKey {
    cell: usize,
    method_index: usize,
}

/// Reads a shard file: its header and rows (a last line cut off is left out).
fn read(path: &Path) -> Result<(ShardHeader, Vec<RowLine>), ShardError> {
    let io = |source| ShardError::Io { path: path.to_owned(), source };
    let bad = |message: String| ShardError::Format { path: path.to_owned(), message };
    let mut lines = BufReader::new(File::open(path).map_err(io)?).lines();
    let first = lines.next().ok_or_else(|| bad("empty: not a shard file".into()))?.map_err(io)?;
    let header: ShardHeader = serde_json::from_str(&first)
        .map_err(|e| bad(format!("line 1 is not a shard header ({e})")))?;
    if header.nhlab_sweep != FORMAT {
        return Err(bad(format!(
            "shard format {} (this nhlab reads {FORMAT})",
            header.nhlab_sweep
        )));
    }
    let mut rows = Vec::new();
    let mut lines = lines.enumerate().peekable();
    while let Some((n, line)) = lines.next() {
        let line = line.map_err(io)?;
        let parsed = serde_json::from_str::<Box<RawValue>>(&line).ok().and_then(|raw| {
            let key: RowKey = serde_json::from_str(raw.get()).ok()?;
            Some(RowLine { cell: key.cell, method_index: key.method_index, raw })
        });
        match parsed {
            Some(row) => rows.push(row),
            // A last line half written by a shard that was stopped.
            None if lines.peek().is_none() => break,
            None => return Err(bad(format!("line {} is not a row", n + 2))),
        }
    }
    Ok((header, rows))
}

/// Groups rows by cell, keeping the cells with all their `methods` rows in order.
fn whole_cells(rows: Vec<RowLine>, methods: usize) -> BTreeMap<usize, Vec<RowLine>> {
    let mut cells: BTreeMap<usize, Vec<RowLine>> = BTreeMap::new();
    for row in rows {
        cells.entry(row.cell).or_default().push(row);
    }
    cells.retain(|_, rows| {
        rows.len() == methods && rows.iter().enumerate().all(|(i, r)| r.method_index == i)
    });
    cells
}

/// For `--resume`: checks that `path` is a shard file of this sweep and shard, rewrites it
/// with only its whole cells, and returns them.
fn keep_whole(path: &Path, header: &ShardHeader, methods: usize) -> Result<Vec<usize>, ShardError> {
    let (found, rows) = read(path)?;
    if found.spec != header.spec || found.shard != header.shard {
        return Err(ShardError::Format {
            path: path.to_owned(),
            message: format!(
                "holds shard {}/{} of another sweep or shard than {}/{} of this spec; \
                 leave out --resume to start it over",
                found.shard.index, found.shard.count, header.shard.index, header.shard.count
            ),
        });
    }
    let cells = whole_cells(rows, methods);
    let io = |source| ShardError::Io { path: path.to_owned(), source };
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".resume.tmp");
    let tmp = PathBuf::from(tmp);
    let mut text =
        serde_json::to_string(header).map_err(|e| format_error(&path.display().to_string(), &e))?;
    text.push('\n');
    for rows in cells.values() {
        for r in rows {
            text += r.raw.get();
            text.push('\n');
        }
    }
    std::fs::write(&tmp, text).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)?;
    Ok(cells.into_keys().collect())
}

/// How merged rows are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MergeFormat {
    /// `POST /sweep`'s JSON answer.
    Json,
    /// Its CSV answer.
    Csv,
}

/// Joins shard files into the answer `POST /sweep` gives for their spec: every cell exactly
/// once, of one spec.
pub fn merge(paths: &[PathBuf], format: MergeFormat) -> Result<String, ShardError> {
    let mut head: Option<(ShardHeader, PathBuf)> = None;
    let mut cells: BTreeMap<usize, (Vec<RowLine>, PathBuf)> = BTreeMap::new();
    for path in paths {
        let (header, rows) = read(path)?;
        if let Some((first, first_path)) = &head
            && first.spec != header.spec
        {
            return Err(ShardError::Incomplete(format!(
                "{} and {} are shards of different sweeps (their specs differ)",
                first_path.display(),
                path.display()
            )));
        }
        let methods = head_of(&header, path)?.methods.len();
        for (c, rows) in whole_cells(rows, methods) {
            if let Some((_, other)) = cells.get(&c) {
                return Err(ShardError::Incomplete(format!(
                    "cell {c} is in both {} and {}; give each shard once",
                    other.display(),
                    path.display()
                )));
            }
            cells.insert(c, (rows, path.clone()));
        }
        if head.is_none() {
            head = Some((header, path.clone()));
        }
    }
    let Some((header, path)) = head else {
        return Err(ShardError::Incomplete("no shard files given".into()));
    };
    let h = head_of(&header, &path)?;
    if let Some((c, (_, file))) = cells.range(h.cells..).next() {
        return Err(ShardError::Incomplete(format!(
            "{} holds cell {c}, beyond the sweep's {} cells",
            file.display(),
            h.cells
        )));
    }
    let missing: Vec<usize> = (0..h.cells).filter(|c| !cells.contains_key(c)).collect();
    if !missing.is_empty() {
        let shards: std::collections::BTreeSet<String> = missing
            .iter()
            .map(|c| format!("{}/{}", c % header.shard.count, header.shard.count))
            .collect();
        return Err(ShardError::Incomplete(format!(
            "{} of {} cells are missing (cells {}{}), from shard{} {}; run or --resume them \
             and merge again",
            missing.len(),
            h.cells,
            missing.iter().take(5).map(|c| c.to_string()).collect::<Vec<_>>().join(", "),
            if missing.len() > 5 { ", …" } else { "" },
            if shards.len() == 1 { "" } else { "s" },
            shards.into_iter().collect::<Vec<_>>().join(", ")
        )));
    }
    let rows = cells.values().flat_map(|(rows, _)| rows.iter().map(|r| r.raw.get()));
    Ok(match format {
        MergeFormat::Json => {
            let head = header.head.get();
            let mut out = String::with_capacity(head.len() + 16);
            out += &head[..head.len() - 1];
            out += ",\"rows\":[";
            for (k, row) in rows.enumerate() {
                if k > 0 {
                    out.push(',');
                }
                out += row;
            }
            out += "]}";
            out
        }
        MergeFormat::Csv => {
            let columns = csv::Columns {
                axes: h.axes.into_iter().map(|a| a.path).collect(),
                integrals: h.integrals,
                observables: h.observables,
            };
            csv::write(&columns, rows.map(|r| serde_json::from_str(r).unwrap_or(Value::Null)))
        }
    })
}

/// The parts of a header's head that a merge needs.
#[derive(Deserialize)]
struct HeadFields {
    axes: Vec<crate::views::AxisView>,
    methods: Vec<Value>,
    integrals: Vec<String>,
    #[serde(default)]
    observables: Vec<String>,
    cells: usize,
}

fn head_of(header: &ShardHeader, path: &Path) -> Result<HeadFields, ShardError> {
    serde_json::from_str(header.head.get()).map_err(|e| ShardError::Format {
        path: path.to_owned(),
        message: format!("its header's head is not a sweep's ({e})"),
    })
}
