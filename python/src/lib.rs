//! `nhlab._nhlab`: the Rust half of the Python package. It serves nhlab's HTTP API inside the
//! Python process, without a socket: a request is handed to the same router `nhlab` serves
//! ([`nhlab_server::app`]) and its answer returned as (status, content type, body), so the
//! Python functions give exactly the numbers, the errors and the paths of the HTTP API. The
//! interpreter's lock is released while a request computes, so Python threads run in parallel,
//! and Ctrl-C stops the computation and raises `KeyboardInterrupt`.
//!
//! Methods written in Python are registered with the core and stepped by its run loop
//! ([`method`]).
//!
//! For sweeps on a Dask cluster, [`shard`] computes one shard's rows on the calling thread's
//! process, as `nhlab sweep --shard I/N` does.

mod method;

use axum::body::Body;
use axum::http::{Method, Request, header};
use nhlab_server::compute::Cancel;
use nhlab_server::sweep::shards;
use nhlab_server::{AppState, Config, app};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::sync::{Arc, Mutex, mpsc};
use std::time::Duration;
use tower::ServiceExt;

/// The answer's size cap: what the server's own limits let through, with room.
const MAX_ANSWER: usize = 1 << 30;

/// How often a waiting call looks for signals (Ctrl-C).
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// The runtime and the router of one process.
type Served = Arc<(tokio::runtime::Runtime, axum::Router)>;

/// The runtime and the app, made on first use (importing the module costs nothing), and made
/// again in a child process: a fork keeps the runtime but not its threads.
fn served() -> Served {
    static SERVED: Mutex<Option<(u32, Served)>> = Mutex::new(None);
    let mut served = SERVED.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let pid = std::process::id();
    if let Some((owner, s)) = served.as_ref()
        && *owner == pid
    {
        return s.clone();
    }
    // In-process, the caller's threads are the clients: enough simulation slots for a thread
    // pool's worth of concurrent calls. The CPU a call may take is the caller's own to spend
    // (Ctrl-C stops it), so no price or time cap; the other limits are the server's.
    let config = Config {
        max_simulations: 64,
        max_request_seconds: f64::INFINITY,
        max_run_seconds: f64::INFINITY,
        ..Config::default()
    };
    let cores = std::thread::available_parallelism().map_or(2, std::num::NonZeroUsize::get);
    let blocking = config.max_simulations * (config.max_methods.max(cores) + 2) + 4;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .max_blocking_threads(blocking)
        .enable_all()
        .build()
        .expect("a tokio runtime starts");
    let fresh = Arc::new((runtime, app(AppState::new(config))));
    // The parent's runtime, inherited without its threads, cannot be shut down here: leaked.
    if let Some((_, inherited)) = served.replace((pid, fresh.clone())) {
        std::mem::forget(inherited);
    }
    fresh
}

/// `request(method, path, body=None, accept=None) -> (status, content_type, body)`: one
/// request to the API, answered in-process.
#[pyfunction]
#[pyo3(signature = (method, path, body=None, accept=None))]
fn request(
    py: Python<'_>,
    method: &str,
    path: &str,
    body: Option<String>,
    accept: Option<String>,
) -> PyResult<(u16, String, String)> {
    let method = Method::from_bytes(method.as_bytes())
        .map_err(|e| PyRuntimeError::new_err(format!("method {method}: {e}")))?;
    let mut builder = Request::builder().method(method).uri(path).header(header::HOST, "localhost");
    if body.is_some() {
        builder = builder.header(header::CONTENT_TYPE, "application/json");
    }
    if let Some(accept) = &accept {
        builder = builder.header(header::ACCEPT, accept.as_str());
    }
    let request = builder
        .body(Body::from(body.unwrap_or_default()))
        .map_err(|e| PyRuntimeError::new_err(format!("request: {e}")))?;
    let served = served();
    let (runtime, router) = &*served;
    let router = router.clone();
    let (tx, rx) = mpsc::sync_channel(1);
    let task = runtime.spawn(async move {
        let _ = tx.send(answer(router, request).await);
    });
    // Dropping the task's future is the client leaving: the server stops its runs.
    wait(py, rx, || task.abort())
}

/// The router's answer to `request` as (status, content type, body).
async fn answer(router: axum::Router, request: Request<Body>) -> PyResult<(u16, String, String)> {
    let Ok(response) = router.oneshot(request).await;
    let status = response.status().as_u16();
    let kind = response
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .unwrap_or("")
        .to_owned();
    let bytes = axum::body::to_bytes(response.into_body(), MAX_ANSWER)
        .await
        .map_err(|e| PyRuntimeError::new_err(format!("reading the answer: {e}")))?;
    let text = String::from_utf8(bytes.to_vec())
        .map_err(|e| PyRuntimeError::new_err(format!("the answer is not UTF-8: {e}")))?;
    Ok((status, kind, text))
}

/// Waits for a result on `rx` without the interpreter's lock, looking for signals (Ctrl-C)
/// every [`SIGNAL_POLL`]: a signal's exception (`KeyboardInterrupt`) stops the work through
/// `stop` and is raised.
fn wait<T: Send>(
    py: Python<'_>,
    mut rx: mpsc::Receiver<PyResult<T>>,
    stop: impl FnOnce(),
) -> PyResult<T> {
    loop {
        let received;
        (rx, received) = py.detach(move || {
            let received = rx.recv_timeout(SIGNAL_POLL);
            (rx, received)
        });
        match received {
            Ok(result) => return result,
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if let Err(signal) = py.check_signals() {
                    stop();
                    return Err(signal);
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err("the request ended without an answer"));
            }
        }
    }
}

/// `shard(spec, index, count, threads) -> (head, rows)`: the rows (JSON text, one per row, by
/// cell then method) of cells `c` with `c mod count = index` of the sweep `spec` (a
/// `POST /sweep` body as JSON text), computed on `threads` threads, and the sweep's head.
/// A bad spec raises `ValueError` with the field and why.
#[pyfunction]
fn shard(
    py: Python<'_>,
    spec: &str,
    index: usize,
    count: usize,
    threads: usize,
) -> PyResult<(String, Vec<String>)> {
    if count == 0 || index >= count {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "a shard is index/count with 0 ≤ index < count, got {index}/{count}"
        )));
    }
    let (_, sweep) = py.detach(|| shards::spec(spec, "spec")).map_err(py_error)?;
    let head =
        serde_json::to_string(&sweep.head).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let cells: Vec<usize> = (0..sweep.cells.len()).filter(|c| c % count == index).collect();
    let cancel = Cancel::default();
    let stop = cancel.clone();
    let (tx, rx) = mpsc::sync_channel(1);
    // A thread of its own (not scoped), so that on a signal the call can give up the GIL
    // while it waits for the workers to see the cancel and return.
    let worker = std::thread::spawn(move || {
        let mut rows: Vec<(usize, Vec<String>)> = Vec::with_capacity(cells.len());
        let computed = shards::compute(&sweep, &cells, threads, &cancel, |cell| {
            let lines = cell.rows.iter().map(serde_json::to_string).collect::<Result<_, _>>();
            let lines = lines.map_err(|e| shards::ShardError::Incomplete(e.to_string()))?;
            rows.push((cell.cell, lines));
            Ok(())
        });
        let result = computed.map_err(|e| PyRuntimeError::new_err(e.to_string())).map(|()| {
            rows.sort_by_key(|(c, _)| *c);
            rows.into_iter().flat_map(|(_, r)| r).collect::<Vec<String>>()
        });
        let _ = tx.send(result);
    });
    let answer = wait(py, rx, || stop.cancel());
    py.detach(|| worker.join())
        .map_err(|_| PyRuntimeError::new_err("the sweep's worker panicked"))?;
    answer.map(|rows| (head, rows))
}

/// `check(spec) -> head`: the head of the sweep `spec` (its axes with their values, methods,
/// integrals, cells) once checked, no cell computed; a bad spec raises `ValueError`.
#[pyfunction]
fn check(py: Python<'_>, spec: &str) -> PyResult<String> {
    py.detach(|| {
        let (_, sweep) = shards::spec(spec, "spec").map_err(py_error)?;
        serde_json::to_string(&sweep.head).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    })
}

/// `axis_values(axis, k) -> values`: the values of axis `k` of a sweep (an `axes[k]` object
/// as JSON text), checked and spaced as `POST /sweep` computes them; a bad axis raises
/// `ValueError(message, path)`. What a sweep over a Python method's parameter spaces with.
#[pyfunction]
fn axis_values(axis: &str, k: usize) -> PyResult<Vec<f64>> {
    let invalid =
        |message: String, path: String| pyo3::exceptions::PyValueError::new_err((message, path));
    let given: nhlab_server::request::AxisRequest =
        serde_json::from_str(axis).map_err(|e| invalid(e.to_string(), format!("axes[{k}]")))?;
    let max = Config::default().max_sweep_cells;
    nhlab_server::sweep::Axis::check(k, &given, max).map(|a| a.values).map_err(|e| {
        let path = e.path.unwrap_or_else(|| format!("axes[{k}]"));
        invalid(e.message, path)
    })
}

/// A spec's error as `ValueError(message, path)`; anything else as `RuntimeError`.
fn py_error(e: shards::ShardError) -> PyErr {
    match e {
        shards::ShardError::Spec { error, .. } => {
            pyo3::exceptions::PyValueError::new_err((error.message, error.path))
        }
        other => PyRuntimeError::new_err(other.to_string()),
    }
}

/// The module.
#[pymodule]
fn _nhlab(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(request, m)?)?;
    m.add_function(wrap_pyfunction!(shard, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(axis_values, m)?)?;
    m.add_function(wrap_pyfunction!(method::register, m)?)?;
    m.add_function(wrap_pyfunction!(method::unregister, m)?)?;
    m.add_class::<method::PySystem>()?;
    let finalizing = wrap_pyfunction!(method::_finalizing, m)?;
    m.py().import("atexit")?.call_method1("register", (finalizing,))?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
