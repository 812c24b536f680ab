//! [`Sweep`]: a sweep request checked into its cells, each with its `/simulate` body, its
//! scene resolved and its methods, ready to compute. What is wrong whatever the cell (an
//! unknown system, a bad path, too many cells or steps) is the request's error, with its
//! field; what an axis's value made wrong (an initial velocity off the constraints for this
//! ε, a step longer than t_end, an α out of range) is that cell's, reported in its rows.
//!
//! What needs no compiling is checked first (cells, steps, the answer's least size); then the
//! cells' scenes are resolved, a system given as formulas compiled once: where an axis sweeps
//! its parameters they are inputs of its code, bound per cell
//! ([`CompiledSystems::parameters_as_inputs`]). The check stops when `stop` says so (its
//! client left, or its time is up).

use crate::compute::{
    Delivery, check_answer_bytes, method, methods, observables_of, points, steps_of, steps_text,
};
use crate::config::Config;
use crate::error::AppError;
use crate::request::{MethodRequest, SimulateRequest, SweepRequest, SystemField};
use crate::sweep::axis::{Axis, Target, has_param};
use crate::views::{AxisView, CRITERION, MethodView, SweepHead};
use nhlab_core::formula::Limits;
use nhlab_core::measure::latitude::LatitudeAxis;
use nhlab_core::measure::observables::Observables;
use nhlab_core::{CompiledSystems, InputError, Method, PreparedScene, Scene, Short};
use std::sync::Arc;

/// Where a sweep's latitude axes come from (a server's cache, or computed).
pub type AxisSource<'a> = &'a (dyn Fn(&Scene) -> Result<LatitudeAxis, InputError> + Sync);

/// Whether a check must stop, and why (the error it ends with); checked between cells.
pub type Stop<'a> = &'a (dyn Fn() -> Option<AppError> + Sync);

/// Most axes per sweep.
pub const MAX_AXES: usize = 3;

/// A checked sweep.
#[derive(Debug)]
pub struct Sweep {
    /// What is swept, as the answer reports it.
    pub head: SweepHead,
    /// The axes.
    pub axes: Vec<Axis>,
    /// Buckets per series.
    pub points: usize,
    /// The integrals as the request named them (all the system has when `None`).
    pub integrals: Option<Vec<String>>,
    /// The cells, by index.
    pub cells: Vec<Cell>,
    /// The observables taken at t_end, as given, and the limits their formulas are compiled
    /// with (in each cell: its parameters are folded in).
    pub observables: Option<(Vec<(String, String)>, Limits)>,
    /// Steps all the runs take together, sub-steps counted.
    pub total_steps: u64,
    /// The request's scene as a `/simulate` body (no methods), and its initial state where
    /// it gives none (the preset's).
    base: (SimulateRequest, Vec<f64>, Vec<f64>),
}

/// One cell: its values, its scene and its methods (its body is made again when needed:
/// a system given as formulas may take kilobytes, which ten thousand cells need not hold).
#[derive(Debug)]
pub struct Cell {
    /// Its value on each axis.
    pub values: Vec<f64>,
    /// The scene, or why the cell's values make it invalid (`field: reason`).
    pub scene: Result<Scene, String>,
    /// Each method as requested for this cell, and as resolved (or why not): one list that
    /// every cell shares when no axis sets a method's parameter.
    pub methods: Arc<[(MethodRequest, Result<Method, String>)]>,
}

impl Cell {
    /// About how many bytes the cell holds: its place in the sweep's list, and each block
    /// it owns as the allocator counts it ([`block`]). Not counted: a method list the cells
    /// share (a kilobyte or so, once), and the compiled code of a system given as formulas,
    /// which the cells share too unless an axis sets its parameters (each cell then compiles
    /// its own: the check's cost, before any answer).
    pub fn heap_bytes(&self) -> u64 {
        let floats = |n: usize| block(8 * n);
        let string = |s: &String| block(s.capacity());
        let scene = match &self.scene {
            // q and v twice: also as the system's code holds them.
            Ok(s) => {
                floats(s.params.capacity()) + 2 * (floats(s.q.capacity()) + floats(s.v.capacity()))
            }
            Err(e) => string(e),
        };
        let each = self.methods.iter().map(|(request, resolved)| {
            let params = block(request.params.capacity() * size_of::<(String, f64)>())
                + request.params.iter().map(|(name, _)| string(name)).sum::<u64>();
            let error = resolved.as_ref().err().map_or(0, string);
            string(&request.id) + params + request.composition.as_ref().map_or(0, string) + error
        });
        // A list the cells share is not the cell's.
        let methods = if Arc::strong_count(&self.methods) > 1 {
            0
        } else {
            block(16 + self.methods.len() * size_of::<(MethodRequest, Result<Method, String>)>())
                + each.sum::<u64>()
        };
        size_of::<Cell>() as u64 + floats(self.values.capacity()) + scene + methods
    }
}

/// What a block of `bytes` takes from the allocator: a word of header, rounded up to 16 bytes,
/// 32 at least (glibc's malloc); none for nothing.
fn block(bytes: usize) -> u64 {
    if bytes == 0 { 0 } else { (bytes as u64 + 8).next_multiple_of(16).max(32) }
}

impl Sweep {
    /// Checks `req` against `config` for an answer delivered as `delivery`; the first valid
    /// cell's scene is prepared (with its latitude axis from `axis`) to check the integrals.
    pub fn check(
        req: &SweepRequest,
        config: &Config,
        delivery: Delivery,
        axis: AxisSource,
        stop: Stop,
    ) -> Result<Self, AppError> {
        let given = match &req.axes {
            None => return Err(AppError::invalid("axes", "axes is required: 1 to 3 axes")),
            Some(a) if a.is_empty() || a.len() > MAX_AXES => {
                return Err(AppError::invalid(
                    "axes",
                    format!("a sweep has 1 to {MAX_AXES} axes, got {}", a.len()),
                ));
            }
            Some(a) => a,
        };
        let axes = given
            .iter()
            .enumerate()
            .map(|(k, a)| Axis::check(k, a, config.max_sweep_cells))
            .collect::<Result<Vec<_>, _>>()?;
        if let Some(k) =
            (1..axes.len()).find(|&k| axes[..k].iter().any(|a| a.target.overlaps(&axes[k].target)))
        {
            return Err(AppError::invalid(
                format!("axes[{k}].path"),
                format!("{} sets what an axis before it sets; sweep each value once", axes[k].path),
            ));
        }
        let cells: f64 = axes.iter().map(|a| a.values.len() as f64).product();
        if cells > config.max_sweep_cells as f64 {
            return Err(AppError::invalid(
                "axes",
                format!(
                    "{} cells (the product of the axes' lengths) exceed the limit of {} per \
                     sweep (max_sweep_cells)",
                    Short(cells),
                    config.max_sweep_cells
                ),
            ));
        }
        let points = points(req.points, config)?;
        let base_methods = methods(req.methods.as_deref(), config)?;
        let requests: Vec<MethodRequest> = match &req.methods {
            Some(m) => m.clone(),
            None => base_methods.iter().map(request_of).collect(),
        };
        check_targets(&axes, req, &requests)?;
        let (q0, v0) = initial_state(req);
        for (k, a) in axes.iter().enumerate() {
            let (len, name) = match a.target {
                Target::Q(i) => (q0.len(), ("q", i)),
                Target::V(i) => (v0.len(), ("v", i)),
                _ => continue,
            };
            if name.1 >= len {
                let why = if len == 0 {
                    format!("give {} in the scene to sweep its components", name.0)
                } else {
                    format!("{} has {len} components, {0}[0] to {0}[{}]", name.0, len - 1)
                };
                return Err(AppError::invalid(format!("axes[{k}].path"), why));
            }
        }
        let body = req.to_simulate(None, req.points);
        let method_axes = axes.iter().any(|a| matches!(a.target, Target::Method { .. }));
        // Without a method axis every cell runs the request's methods: one list for all.
        let shared: Arc<[_]> =
            requests.iter().cloned().zip(base_methods.iter().map(|m| Ok(*m))).collect();
        let n = cells as usize;
        let cell = |c: usize| {
            let values = cell_values(&axes, c);
            let (mut body, mut requests) = (body.clone(), requests.clone());
            for (a, &x) in axes.iter().zip(&values) {
                a.apply(x, &mut body, &mut requests, &q0, &v0);
            }
            let methods: Arc<[(MethodRequest, Result<Method, String>)]> = if method_axes {
                requests
                    .into_iter()
                    .enumerate()
                    .map(|(i, m)| {
                        let resolved = method(i, &m)
                            .map_err(|e| format!("{}: {}", e.path.unwrap_or_default(), e.message));
                        (m, resolved)
                    })
                    .collect()
            } else {
                shared.clone()
            };
            (values, body, methods)
        };
        // First what needs no compiling: the steps of every run.
        let mut steps = StepCount::new(config, delivery);
        for c in 0..n {
            let (values, body, methods) = cell(c);
            if let Some((step, t_end)) = Scene::step_and_t_end(&body.scene_request()) {
                steps.add(&axes, &values, step, t_end, &methods)?;
            }
        }
        let total_steps = steps.total()?;
        if delivery != Delivery::Stream {
            // At least one integral per row: the answer's least size, known before compiling.
            let rows = (n * base_methods.len()) as u64;
            let least = rows.saturating_mul(row_bytes_with(1, axes.len(), 0));
            check_answer_bytes(least, config, " (its rows)")?;
        }
        // Then the scenes: a system given as formulas compiled once.
        let sweeps_params = axes.iter().any(|a| matches!(a.target, Target::Param(_)));
        let mut compiled = match &req.system {
            SystemField::Formulas(_) | SystemField::General(_) if sweeps_params => {
                CompiledSystems::parameters_as_inputs()
            }
            _ => CompiledSystems::default(),
        };
        let mut out = Vec::with_capacity(n);
        for c in 0..n {
            if let Some(e) = stop() {
                return Err(e);
            }
            let (values, body, methods) = cell(c);
            let scene =
                match Scene::resolve_cached(&body.scene_request(), &config.formulas, &mut compiled)
                {
                    Ok(scene) => Ok(scene),
                    Err(e) => {
                        let e = AppError::from(e);
                        let path = e.path.clone().unwrap_or_default();
                        if !axes.iter().any(|a| a.may_cause(&path)) {
                            return Err(e);
                        }
                        Err(format!("{path}: {}", e.message))
                    }
                };
            out.push(Cell { values, scene, methods });
        }
        // What is wrong in every cell alike is the request's, not the axes': a v off the
        // constraints whatever ε.
        let errors: Vec<&String> = out.iter().filter_map(|c| c.scene.as_ref().err()).collect();
        if errors.len() == out.len() && errors.windows(2).all(|w| w[0] == w[1]) {
            let (path, message) = errors[0].split_once(": ").unwrap_or(("", errors[0]));
            return Err(AppError::invalid(path, message));
        }
        let runs = out.iter().filter_map(|c| Some((c.scene.as_ref().ok()?, &c.methods)));
        let runs = runs.flat_map(|(scene, methods)| {
            methods
                .iter()
                .enumerate()
                .filter_map(move |(i, m)| Some((i, scene, m.1.as_ref().ok()?)))
        });
        crate::sweep::price::check(runs, config)?;
        let integrals = req.integrals.clone();
        let measured = match out.iter().find_map(|c| c.scene.as_ref().ok()) {
            Some(scene) => {
                let prepared = prepare(scene, integrals.as_deref(), axis)?;
                // Errors at `observables.NAME`, checked on the first valid cell.
                observables_of(req.observables.as_ref(), &prepared, config)?;
                prepared.integrals.iter().map(|&i| prepared.integral_name(i)).collect()
            }
            None => integrals.clone().unwrap_or_default(),
        };
        let head = SweepHead {
            axes: axes
                .iter()
                .map(|a| AxisView { path: a.path.clone(), values: a.values.clone() })
                .collect(),
            methods: base_methods.iter().map(MethodView::of).collect(),
            integrals: measured,
            observables: req
                .observables
                .as_ref()
                .map_or_else(Vec::new, |o| o.0.iter().map(|(n, _)| n.clone()).collect()),
            cells: n,
            criterion: CRITERION.to_owned(),
        };
        let base = (body, q0, v0);
        let observables = req.observables.as_ref().map(|o| (o.0.clone(), config.formulas.formula));
        let sweep =
            Self { head, axes, points, integrals, cells: out, observables, total_steps, base };
        if delivery != Delivery::Stream {
            let what = " (its rows as text and its checked cells)";
            check_answer_bytes(sweep.held_bytes(delivery), config, what)?;
        }
        Ok(sweep)
    }

    /// The observables asked for, compiled for a cell's scene (its parameters folded in), or
    /// why they do not compile there (`field: reason`); none when none were asked for.
    pub fn observables_for(
        &self,
        prepared: &PreparedScene,
    ) -> Option<Result<Arc<Observables>, String>> {
        let (given, limits) = self.observables.as_ref()?;
        let coordinates = prepared.scene.system.coordinate_names();
        let params = prepared.scene.named_params();
        Some(Observables::compile(given, &coordinates, &params, limits).map(Arc::new).map_err(
            |e| {
                let e = AppError::from(e);
                format!("{}: {}", e.path.unwrap_or_default(), e.message)
            },
        ))
    }

    /// The `/simulate` body of cell `c` (without methods), its values in place.
    pub fn body(&self, c: usize) -> SimulateRequest {
        let (base, q0, v0) = &self.base;
        let mut body = base.clone();
        for (a, &x) in self.axes.iter().zip(&self.cells[c].values) {
            a.apply(x, &mut body, &mut [], q0, v0);
        }
        body
    }

    /// What the sweep holds at the peak of its answer: its checked cells, and the text of
    /// its rows ([`Sweep::answer_bytes`]) for a JSON or CSV answer, written as the cells
    /// complete; a stream holds a cell's rows at a time.
    pub fn held_bytes(&self, delivery: Delivery) -> u64 {
        let text = match delivery {
            Delivery::Stream => self.head.methods.len() as u64 * self.row_bytes(),
            Delivery::Json | Delivery::JsonOnly => self.answer_bytes(),
        };
        text.saturating_add((self.cells.len() as u64).saturating_mul(self.cell_bytes()))
    }

    /// About how many bytes the JSON answer takes (its CSV takes less): rows × row bytes.
    pub fn answer_bytes(&self) -> u64 {
        let rows = (self.cells.len() * self.head.methods.len()) as u64;
        rows.saturating_mul(self.row_bytes())
    }

    /// About how many bytes a checked cell holds: its scene and each method's request and
    /// resolution, as the first cell holds them.
    pub fn cell_bytes(&self) -> u64 {
        self.cells.first().map_or(0, Cell::heap_bytes)
    }

    /// About how many bytes a row takes as JSON.
    pub fn row_bytes(&self) -> u64 {
        let cell = &self.cells[0];
        let (request, method) = &cell.methods[0];
        let echo = self.echo(0, request, method.as_ref().ok());
        let body = serde_json::to_vec(&echo).map_or(1000, |b| b.len()) as u64;
        let observables = 30 * self.head.observables.len() as u64;
        row_bytes_with(self.head.integrals.len(), cell.values.len(), body) + observables
    }
}

/// About how many bytes a row of `integrals` verdicts over `axes` axes takes as JSON, with
/// an echoed `/simulate` body of `body` bytes.
fn row_bytes_with(integrals: usize, axes: usize, body: u64) -> u64 {
    300 + 130 * integrals as u64 + 20 * axes as u64 + body
}

/// Prepares a cell's scene for the integrals asked for, errors at `integrals[i]`.
pub fn prepare(
    scene: &Scene,
    integrals: Option<&[String]>,
    axis: AxisSource,
) -> Result<PreparedScene, AppError> {
    scene.clone().prepare_with_latitude(integrals, axis).map_err(|e| {
        let name = match &e {
            InputError::UnknownIntegral { name, .. } => Some(name),
            InputError::IntegralUnavailable { integral, .. } => Some(integral),
            _ => None,
        };
        let index = name.and_then(|n| integrals?.iter().position(|x| x == n));
        let mut err = AppError::from(e);
        if let Some(i) = index {
            err.path = Some(format!("integrals[{i}]"));
        }
        err
    })
}

/// The values of cell `c`: the last axis varies fastest.
pub fn cell_values(axes: &[Axis], mut c: usize) -> Vec<f64> {
    let mut values = vec![0.0; axes.len()];
    for (k, a) in axes.iter().enumerate().rev() {
        let n = a.values.len();
        values[k] = a.values[c % n];
        c /= n;
    }
    values
}

/// A method as a request gives it.
pub fn request_of(m: &Method) -> MethodRequest {
    let params = m.params().into_iter().map(|(n, v)| (n.to_owned(), v)).collect();
    let prk = match &m.base {
        nhlab_core::BaseMethod::Prk(p) => Some(p),
        _ => None,
    };
    MethodRequest {
        composition: m.composition.map(|c| c.id().to_owned()),
        tableau: prk.map(crate::views::TableauEcho::choice),
        constraint: prk.map(|p| p.constraint.id().to_owned()),
        ..MethodRequest::new(m.info().id, params)
    }
}

/// The scene's initial state where it gives none: its preset's (empty when unknown).
fn initial_state(req: &SweepRequest) -> (Vec<f64>, Vec<f64>) {
    let preset = match &req.system {
        SystemField::Id(id) => nhlab_core::system(id).ok().and_then(|entry| {
            let presets = entry.info().presets;
            match &req.preset {
                None => presets.first(),
                Some(p) => presets.iter().find(|x| x.id == p),
            }
        }),
        SystemField::Formulas(_) | SystemField::General(_) => None,
    };
    let q = req.q.clone().or_else(|| preset.map(|p| p.q.to_vec())).unwrap_or_default();
    let v = req.v.clone().or_else(|| preset.map(|p| p.v.to_vec())).unwrap_or_default();
    (q, v)
}

/// Every axis on a parameter names one the system (or a targeted method) has.
fn check_targets(
    axes: &[Axis],
    req: &SweepRequest,
    methods: &[MethodRequest],
) -> Result<(), AppError> {
    let system_params: Option<Vec<String>> = match &req.system {
        SystemField::Id(id) => nhlab_core::system(id)
            .ok()
            .map(|e| e.info().params.iter().map(|p| p.name.to_owned()).collect()),
        SystemField::Formulas(f) => Some(f.parameters.0.iter().map(|p| p.0.clone()).collect()),
        SystemField::General(g) => Some(g.parameters.0.iter().map(|p| p.0.clone()).collect()),
    };
    for (k, a) in axes.iter().enumerate() {
        let at = format!("axes[{k}].path");
        match &a.target {
            Target::Param(name) => {
                if let Some(names) = &system_params
                    && !names.contains(name)
                {
                    let valid = if names.is_empty() { "none".into() } else { names.join(", ") };
                    return Err(AppError::invalid(
                        at,
                        format!("the system has no parameter `{name}` (its parameters: {valid})"),
                    ));
                }
            }
            Target::Method { index: Some(i), name } => {
                let Some(m) = methods.get(*i) else {
                    return Err(AppError::invalid(
                        at,
                        format!(
                            "there are {} methods, methods[0] to methods[{}]",
                            methods.len(),
                            methods.len().saturating_sub(1)
                        ),
                    ));
                };
                if !has_param(&m.id, name) {
                    return Err(AppError::invalid(
                        at,
                        format!("method {} has no parameter `{name}`", m.id),
                    ));
                }
            }
            Target::Method { index: None, name }
                if !methods.iter().any(|m| has_param(&m.id, name)) =>
            {
                return Err(AppError::invalid(
                    at,
                    format!("none of the methods has a parameter `{name}`"),
                ));
            }
            _ => {}
        }
    }
    Ok(())
}

/// The steps of a sweep's runs, counted cell by cell: a run over the step limit of its
/// delivery is refused at once, and so is a total over `max_sweep_steps`.
struct StepCount<'a> {
    config: &'a Config,
    delivery: Delivery,
    limit: u64,
    /// Exact, and as a float for the message where the exact sum would not fit.
    total: u64,
    about: f64,
}

impl<'a> StepCount<'a> {
    fn new(config: &'a Config, delivery: Delivery) -> Self {
        let limit = match delivery {
            Delivery::Stream => config.max_steps_stream,
            Delivery::Json | Delivery::JsonOnly => config.max_steps_json,
        };
        Self { config, delivery, limit, total: 0, about: 0.0 }
    }

    /// Counts the runs of one cell (a step that is not positive is the cell's error, found
    /// when its scene is resolved).
    fn add(
        &mut self,
        axes: &[Axis],
        values: &[f64],
        step: f64,
        t_end: f64,
        methods: &[(MethodRequest, Result<Method, String>)],
    ) -> Result<(), AppError> {
        if !(step > 0.0 && t_end >= step && t_end.is_finite()) {
            return Ok(());
        }
        for (_, m) in methods {
            let Ok(m) = m else { continue };
            let steps = steps_of(step, t_end).saturating_mul(m.stages() as u64);
            if steps > self.limit {
                let at: Vec<String> = axes
                    .iter()
                    .zip(values)
                    .map(|(a, x)| format!("{} = {}", a.path, Short(*x)))
                    .collect();
                return Err(AppError::invalid(
                    "axes",
                    format!(
                        "the run of {} at {} takes {} steps, over the limit of {} \
                         steps per run (max_steps_{}); narrow the axes or shorten t_end",
                        m.label(),
                        at.join(", "),
                        steps_text(step, t_end, m.stages()),
                        self.limit,
                        if self.delivery == Delivery::Stream { "stream" } else { "json" },
                    ),
                ));
            }
            self.total = self.total.saturating_add(steps);
            self.about += m.stages() as f64 * t_end / step;
        }
        Ok(())
    }

    /// The total, or the error when it is over `max_sweep_steps`.
    fn total(&self) -> Result<u64, AppError> {
        if self.total > self.config.max_sweep_steps {
            return Err(AppError::invalid(
                "axes",
                format!(
                    "the sweep would take {} steps in all (cells × methods × steps per run), \
                     over the limit of {} (max_sweep_steps); narrow the axes, shorten t_end or \
                     lengthen the step, or split it into shards (nhlab sweep --shard)",
                    Short(self.about.max(self.total as f64)),
                    Short(self.config.max_sweep_steps as f64)
                ),
            ));
        }
        Ok(self.total)
    }
}
