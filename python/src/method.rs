//! Methods written in Python (`nhlab.Method`, `docs/own-methods.md`): the Rust half. A method
//! object is registered with nhlab's core ([`nhlab_core::methods::external`]) under a handle
//! that a request names as `{"id": "python", "handle": k}`; the run loop then calls its
//! `step(system, q, v, h, memory)` like a built-in's step, holding the interpreter's lock for
//! the call only.
//!
//! `system` is one [`PySystem`] object for every step: it reads the system of the step being
//! taken on this thread (a pointer set for the call's duration, [`Entered`]), so it costs
//! nothing to hand over, and refuses to work outside a step. `memory` is a shallow copy of the
//! dict the step before left (see [`nhlab_core::methods::External`] for the keys), so two
//! branches from one point each start from what was there; the newest [`KEPT_PER_RUN`] of
//! each of the [`KEPT_RUNS`] most recently stepped runs are kept.

use nhlab_core::methods::external::{self, ExternalStep, SystemView};
use numpy::{AllowTypeChange, PyArray1, PyArrayLike1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple};
use std::cell::Cell;
use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

/// The system of the step being taken on this thread, if one is.
type Current = Option<*const (dyn SystemView + 'static)>;

thread_local! {
    static CURRENT: Cell<Current> = const { Cell::new(None) };
}

/// While alive, `system` is the one this thread's Python code sees; dropping it (on any exit
/// from the step) restores what was there before.
struct Entered(Current);

impl Entered {
    fn enter(sys: &dyn SystemView) -> Self {
        // SAFETY: the pointer is readable only while this guard lives, and the guard lives
        // inside the step that borrows `sys` (it is created and dropped in `PyStep::step`),
        // so it never outlives the referent; only the lifetime is erased, not the type.
        let ptr: *const (dyn SystemView + 'static) =
            unsafe { std::mem::transmute::<*const dyn SystemView, _>(sys as *const _) };
        Self(CURRENT.with(|c| c.replace(Some(ptr))))
    }
}

impl Drop for Entered {
    fn drop(&mut self) {
        CURRENT.with(|c| c.set(self.0));
    }
}

/// A Python thread state kept on a thread that steps methods written in Python, with the
/// interpreter's lock released: acquiring the lock for a step is then a switch of the
/// current thread state, where without it each step would create and destroy one (about
/// ten microseconds). Freed when the thread ends.
struct Resident(*mut pyo3::ffi::PyThreadState);

impl Resident {
    fn new() -> Self {
        // SAFETY: called on a thread without a Python thread state (checked), so not holding
        // the interpreter's lock. `PyGILState_Ensure` makes this thread's state and takes the
        // lock, and
        // `PyEval_SaveThread` releases the lock, keeping the state (its count stays 1, so
        // later Ensure/Release pairs switch to it instead of making and freeing one).
        unsafe {
            if pyo3::ffi::Py_IsInitialized() == 0
                || !pyo3::ffi::PyGILState_GetThisThreadState().is_null()
            {
                return Self(std::ptr::null_mut());
            }
            let _ = pyo3::ffi::PyGILState_Ensure();
            Self(pyo3::ffi::PyEval_SaveThread())
        }
    }
}

/// Set by an `atexit` hook when the interpreter begins to shut down: from then on a thread
/// that ends leaves its thread state alone (taking the lock while Python shuts down would end
/// the thread inside a Rust destructor and abort the process; the stable ABI cannot ask).
pub static FINALIZING: AtomicBool = AtomicBool::new(false);

impl Drop for Resident {
    fn drop(&mut self) {
        if self.0.is_null() || FINALIZING.load(Ordering::Acquire) {
            return;
        }
        // SAFETY: the state made in `new`, on this thread, which holds no lock between steps;
        // taking the lock with it and releasing the count of 1 frees it.
        unsafe {
            pyo3::ffi::PyEval_RestoreThread(self.0);
            pyo3::ffi::PyGILState_Release(pyo3::ffi::PyGILState_STATE::PyGILState_UNLOCKED);
        }
    }
}

/// `_finalizing()`: registered with `atexit`, see [`FINALIZING`].
#[pyfunction]
pub fn _finalizing() {
    FINALIZING.store(true, Ordering::Release);
}

thread_local! {
    static RESIDENT: Resident = Resident::new();
}

/// The system of the step being taken on this thread.
fn with_system<T>(f: impl FnOnce(&dyn SystemView) -> PyResult<T>) -> PyResult<T> {
    let Some(ptr) = CURRENT.with(Cell::get) else {
        return Err(PyRuntimeError::new_err(
            "the system is usable only inside the method's step (and on the step's thread)",
        ));
    };
    // SAFETY: set by `Entered` for the duration of a step on this thread (see there).
    f(unsafe { &*ptr })
}

/// `q` as a vector of `n` floats, or a `ValueError` naming `what`.
fn floats(x: &Bound<'_, PyAny>, n: usize, what: &str) -> PyResult<Vec<f64>> {
    let array: PyArrayLike1<'_, f64, AllowTypeChange> = x
        .extract()
        .map_err(|_| PyValueError::new_err(format!("{what} must be a 1-d array of {n} numbers")))?;
    if array.len() != n {
        return Err(PyValueError::new_err(format!(
            "{what} has {} entries; the system has {n} coordinates",
            array.len()
        )));
    }
    Ok(array.as_array().iter().copied().collect())
}

/// A numpy array of `shape` (a vector or a matrix, row by row) that `fill` writes.
fn array<'py>(
    py: Python<'py>,
    shape: &[usize],
    fill: impl FnOnce(&mut [f64]),
) -> PyResult<Bound<'py, PyAny>> {
    let mut out = vec![0.0; shape.iter().product()];
    fill(&mut out);
    let flat = PyArray1::from_vec(py, out);
    Ok(match *shape {
        [rows, cols] => flat.reshape([rows, cols])?.into_any(),
        _ => flat.into_any(),
    })
}

/// [`array`] for a `fill` that solves with `A M⁻¹ Aᵀ`, false where it is singular.
fn solved<'py>(
    py: Python<'py>,
    shape: &[usize],
    fill: impl FnOnce(&mut [f64]) -> bool,
) -> PyResult<Bound<'py, PyAny>> {
    let mut regular = false;
    let out = array(py, shape, |out| regular = fill(out))?;
    if regular { Ok(out) } else { Err(PyValueError::new_err("A M⁻¹ Aᵀ is singular at q")) }
}

/// The system a method's step sees (`docs/own-methods.md`): M, V, A and their derivatives
/// as calls on numpy arrays, the paper's pieces for a system of its class, its invariants,
/// and the helpers.
#[pyclass(frozen, name = "System", module = "nhlab")]
pub struct PySystem;

#[pymethods]
#[allow(non_snake_case, reason = "the mathematics' names: M, V, A, U")]
impl PySystem {
    /// Coordinates N.
    #[getter]
    fn n(&self) -> PyResult<usize> {
        with_system(|s| Ok(s.sizes().0))
    }
    /// Constraints R (rows of A).
    #[getter]
    fn r(&self) -> PyResult<usize> {
        with_system(|s| Ok(s.sizes().1))
    }
    /// Whether the system is of the paper's class (its pieces available, ζ last).
    #[getter]
    fn in_paper_class(&self) -> PyResult<bool> {
        with_system(|s| Ok(s.class().is_some()))
    }
    /// The index of the driver ζ in q (the last), for a system of the paper's class.
    #[getter]
    fn zeta_index(&self) -> PyResult<usize> {
        with_system(|s| class(s).map(|_| s.sizes().0 - 1))
    }
    /// The mass matrix M.
    fn M<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| array(py, &[s.sizes().0; 2], |out| s.mass(out)))
    }
    /// M⁻¹.
    fn M_inv<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| array(py, &[s.sizes().0; 2], |out| s.mass_inverse(out)))
    }
    /// V(q).
    fn V(&self, q: &Bound<'_, PyAny>) -> PyResult<f64> {
        with_system(|s| Ok(s.potential(&floats(q, s.sizes().0, "q")?)))
    }
    /// ∇V(q).
    fn grad_V<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let q = floats(q, s.sizes().0, "q")?;
            array(py, &[q.len()], |out| s.gradient(&q, out))
        })
    }
    /// ∇²V(q).
    fn hess_V<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let q = floats(q, s.sizes().0, "q")?;
            array(py, &[q.len(); 2], |out| s.hessian(&q, out))
        })
    }
    /// A(q), R×N.
    fn A<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let (n, r) = s.sizes();
            let q = floats(q, n, "q")?;
            array(py, &[r, n], |out| s.constraint(&q, out))
        })
    }
    /// ∂(A(q) v)/∂q, R×N: its product with w is the derivative of A(q)v along w.
    fn jac_Av<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let (n, r) = s.sizes();
            let (q, v) = (floats(q, n, "q")?, floats(v, n, "v")?);
            array(py, &[r, n], |out| s.constraint_jacobian(&q, &v, out))
        })
    }
    /// The derivative of A(q) v along w: (∂(A(q) v)/∂q) w, R.
    fn dA<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        w: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let (n, r) = s.sizes();
            let (q, v, w) = (floats(q, n, "q")?, floats(v, n, "v")?, floats(w, n, "w")?);
            let mut jac = vec![0.0; r * n];
            s.constraint_jacobian(&q, &v, &mut jac);
            array(py, &[r], |out| {
                for (slot, row) in out.iter_mut().zip(jac.chunks(n)) {
                    *slot = row.iter().zip(&w).map(|(a, b)| a * b).sum();
                }
            })
        })
    }
    /// H(q, q̇) = ½ q̇ᵀM q̇ + V(q).
    fn energy(&self, q: &Bound<'_, PyAny>, v: &Bound<'_, PyAny>) -> PyResult<f64> {
        with_system(|s| {
            let n = s.sizes().0;
            Ok(s.energy(&floats(q, n, "q")?, &floats(v, n, "v")?))
        })
    }
    /// The names of the system's invariants, the keys of [`invariants`](Self::invariants):
    /// for the paper's class `passenger_energy` and `driver_energy`, then those it declares.
    #[getter]
    fn invariant_names(&self) -> PyResult<Vec<String>> {
        with_system(|s| Ok(s.invariant_names().into_iter().map(str::to_owned).collect()))
    }
    /// The system's invariants at (q, q̇), a dict by name: for the paper's class the passenger
    /// and driver energies E and h, then the invariants it declares (empty where it has none).
    fn invariants<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        with_system(|s| {
            let n = s.sizes().0;
            let (q, v) = (floats(q, n, "q")?, floats(v, n, "v")?);
            let names = s.invariant_names();
            let mut values = vec![f64::NAN; names.len()];
            s.invariants(&q, &v, &mut values);
            let dict = PyDict::new(py);
            for (name, value) in names.into_iter().zip(values) {
                dict.set_item(name, value)?;
            }
            Ok(dict)
        })
    }
    /// The M-orthogonal projection of v onto the constraints at q, v − M⁻¹Aᵀ(AM⁻¹Aᵀ)⁻¹A v.
    fn project<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let n = s.sizes().0;
            let (q, v) = (floats(q, n, "q")?, floats(v, n, "v")?);
            solved(py, &[n], |out| s.project(&q, &v, out))
        })
    }
    /// The continuous multiplier λ at (q, q̇), R: what every run's state starts with.
    fn multiplier<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let (n, r) = s.sizes();
            let (q, v) = (floats(q, n, "q")?, floats(v, n, "v")?);
            solved(py, &[r], |out| s.multiplier(&q, &v, out))
        })
    }
    /// U(x), the passenger's potential (q given whole; the paper's class).
    fn U(&self, q: &Bound<'_, PyAny>) -> PyResult<f64> {
        with_system(|s| Ok(class(s)?.passenger_potential(&floats(q, s.sizes().0, "q")?)))
    }
    /// ∇U (zero ζ component; the paper's class).
    fn grad_U<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let (pieces, q) = (class(s)?, floats(q, s.sizes().0, "q")?);
            array(py, &[q.len()], |out| pieces.passenger_gradient(&q, out))
        })
    }
    /// V_d(ζ) and its first two derivatives, a tuple (the paper's class).
    fn V_d(&self, zeta: f64) -> PyResult<(f64, f64, f64)> {
        with_system(|s| {
            let [v, d1, d2] = class(s)?.driver_potential(zeta);
            Ok((v, d1, d2))
        })
    }
    /// A(ζ), R×N with a zero ζ column (the paper's class).
    fn A_x<'py>(&self, py: Python<'py>, zeta: f64) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let ((n, r), pieces) = (s.sizes(), class(s)?);
            array(py, &[r, n], |out| pieces.constraint_at(zeta, out))
        })
    }
    /// dA/dζ, R×N (the paper's class).
    fn dA_x<'py>(&self, py: Python<'py>, zeta: f64) -> PyResult<Bound<'py, PyAny>> {
        with_system(|s| {
            let ((n, r), pieces) = (s.sizes(), class(s)?);
            array(py, &[r, n], |out| pieces.constraint_d(zeta, out))
        })
    }
    /// Newton's method on `residual(x) = 0` with its `jacobian(x)` from `x0`
    /// (`nhlab.newton`).
    #[pyo3(signature = (residual, jacobian, x0, tol = 1e-14, max_iter = 50))]
    fn newton<'py>(
        &self,
        py: Python<'py>,
        residual: &Bound<'py, PyAny>,
        jacobian: &Bound<'py, PyAny>,
        x0: &Bound<'py, PyAny>,
        tol: f64,
        max_iter: u32,
    ) -> PyResult<Bound<'py, PyAny>> {
        static NEWTON: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
        let newton = NEWTON.import(py, "nhlab._own", "newton")?;
        newton.call1((residual, jacobian, x0, tol, max_iter))
    }
}

fn class(s: &dyn SystemView) -> PyResult<&dyn nhlab_core::methods::external::ClassView> {
    s.class().ok_or_else(|| {
        PyValueError::new_err("the system is not of the paper's class: it has no U, V_d or A_x")
    })
}

/// How many steps' memory dicts are kept per run (the newest): enough for the branches of
/// the property checks, which step a few times from one point.
const KEPT_PER_RUN: usize = 64;

/// How many runs' memories are kept (the most recently stepped): far more than run at once.
const KEPT_RUNS: usize = 256;

/// A method's memory dicts by key, each with its run (the key of the run's first step).
#[derive(Default)]
struct Memories {
    by_key: HashMap<u64, (u64, Py<PyDict>)>,
    /// Each run's keys, oldest first, and when it last stepped.
    runs: HashMap<u64, (VecDeque<u64>, u64)>,
    clock: u64,
}

impl Memories {
    /// Keeps `dict` under `to` for `run`; returns what no longer fits, to be dropped once
    /// the lock is released.
    fn keep(&mut self, run: u64, to: u64, dict: Py<PyDict>) -> Vec<Py<PyDict>> {
        self.clock += 1;
        let mut dropped = Vec::new();
        self.by_key.insert(to, (run, dict));
        let (keys, used) = self.runs.entry(run).or_default();
        keys.push_back(to);
        *used = self.clock;
        while keys.len() > KEPT_PER_RUN {
            if let Some(old) = keys.pop_front() {
                dropped.extend(self.by_key.remove(&old).map(|(_, d)| d));
            }
        }
        if self.runs.len() > KEPT_RUNS {
            let oldest = self.runs.iter().min_by_key(|(_, (_, used))| *used).map(|(r, _)| *r);
            if let Some((keys, _)) = oldest.and_then(|r| self.runs.remove(&r)) {
                dropped.extend(keys.iter().filter_map(|k| self.by_key.remove(k)).map(|(_, d)| d));
            }
        }
        dropped
    }
}

/// A registered `nhlab.Method`.
struct PyStep {
    method: Py<PyAny>,
    name: String,
    order: u32,
    symmetric: bool,
    system: Py<PySystem>,
    memories: Mutex<Memories>,
}

impl PyStep {
    /// A copy of the dict left under `from` (a new dict for key 0, a new run), kept under
    /// `to`. No lock is held while Python code runs (a copy or a dropped dict may run a
    /// finaliser, which may step this method on another thread).
    fn memory<'py>(&self, py: Python<'py>, (from, to): (u64, u64)) -> PyResult<Bound<'py, PyDict>> {
        let before = match from {
            0 => None,
            key => {
                let memories = self.memories.lock().unwrap_or_else(PoisonError::into_inner);
                let kept = memories.by_key.get(&key).map(|(run, d)| (*run, d.clone_ref(py)));
                Some(kept.ok_or_else(|| {
                    PyRuntimeError::new_err(format!(
                        "the memory the previous step left is no longer kept (a method keeps \
                         the newest {KEPT_PER_RUN} steps' of each of its {KEPT_RUNS} most \
                         recently stepped runs)"
                    ))
                })?)
            }
        };
        let (run, dict) = match before {
            Some((run, before)) => (run, before.bind(py).copy()?),
            None => (to, PyDict::new(py)),
        };
        let dropped = {
            let mut memories = self.memories.lock().unwrap_or_else(PoisonError::into_inner);
            memories.keep(run, to, dict.clone().unbind())
        };
        drop(dropped);
        Ok(dict)
    }

    fn call(
        &self,
        py: Python<'_>,
        q: &mut [f64],
        v: &mut [f64],
        h: f64,
        keys: (u64, u64),
    ) -> PyResult<()> {
        let n = q.len();
        let args = (
            self.system.bind(py),
            PyArray1::from_slice(py, q),
            PyArray1::from_slice(py, v),
            h,
            self.memory(py, keys)?,
        );
        let answer = self.method.bind(py).call_method1(pyo3::intern!(py, "step"), args)?;
        let pair = answer
            .cast::<PyTuple>()
            .ok()
            .filter(|t| t.len() == 2)
            .ok_or_else(|| PyValueError::new_err("step must return a pair (q1, v1)"))?;
        let q1 = floats(&pair.get_item(0)?, n, "the q1 returned")?;
        let v1 = floats(&pair.get_item(1)?, n, "the v1 returned")?;
        q.copy_from_slice(&q1);
        v.copy_from_slice(&v1);
        Ok(())
    }
}

impl ExternalStep for PyStep {
    fn name(&self) -> &str {
        &self.name
    }
    fn order(&self) -> u32 {
        self.order
    }
    fn symmetric(&self) -> bool {
        self.symmetric
    }
    fn step(
        &self,
        sys: &dyn SystemView,
        keys: (u64, u64),
        q: &mut [f64],
        v: &mut [f64],
        h: f64,
    ) -> Result<(), String> {
        RESIDENT.with(|_| ());
        Python::attach(|py| {
            let _entered = Entered::enter(sys);
            self.call(py, q, v, h, keys).map_err(|e| {
                let kind =
                    e.get_type(py).name().map_or_else(|_| "Exception".into(), |n| n.to_string());
                format!("{kind}: {}", e.value(py))
            })
        })
    }
}

/// `register(method, name, order, symmetric) -> handle`: registers a method object (its
/// `step` is called) under a new handle.
#[pyfunction]
pub fn register(
    py: Python<'_>,
    method: Py<PyAny>,
    name: String,
    order: u32,
    symmetric: bool,
) -> PyResult<u32> {
    let system = Py::new(py, PySystem)?;
    let memories = Mutex::default();
    let step = PyStep { method, name, order, symmetric, system, memories };
    Ok(external::register(Arc::new(step)))
}

/// `unregister(handle)`: forgets the method registered under `handle` and its runs' memories.
#[pyfunction]
pub fn unregister(handle: u32) {
    external::unregister(handle);
}
