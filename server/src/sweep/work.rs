//! Computing a sweep's cells: [`Sweep::compute`] runs every method of one cell and makes its
//! rows; [`Sweep::work`] is a worker's loop, taking the next cell of a shared list until none
//! is left or the sweep is cancelled. The server runs one worker per core on its blocking
//! pool; `nhlab sweep` one per thread it is given. Either way a cell's rows depend on the
//! cell alone, so the same request gives the same rows, whatever the workers and the order.

use crate::compute::{Cancel, ThreadClock, run_config};
use crate::observers::{IntegralNames, JsonCollector};
use crate::request::{MethodRequest, SystemField};
use crate::sweep::plan::{AxisSource, Sweep, prepare};
use crate::views::{
    MethodView, ObservablesView, RowStatus, SimulateEcho, SweepCell, SweepRow, ValuesView,
};
use nhlab_core::solver::newton;
use nhlab_core::{Method, RunError, Scene};
use serde_json::Value;
use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

impl Sweep {
    /// A worker: computes the cells `order[k]` for the `k`s it takes from `next`, handing each
    /// to `out` (which returns false to stop), until `order` is done or `cancel` is set. Each
    /// run ends as failed past `time_limit`, if there is one.
    pub fn work(
        &self,
        order: &[usize],
        next: &AtomicUsize,
        (cancel, time_limit): (&Cancel, Option<Duration>),
        axis: AxisSource,
        out: &mut dyn FnMut(SweepCell) -> bool,
    ) {
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            if k >= order.len() || cancel.is_cancelled() {
                return;
            }
            let Some(cell) = self.compute(order[k], (cancel, time_limit), axis) else { return };
            if !out(cell) {
                return;
            }
        }
    }

    /// The rows of cell `c`, or `None` if the sweep was cancelled meanwhile; each run ends as
    /// failed past `time_limit`, if there is one.
    pub fn compute(
        &self,
        c: usize,
        (cancel, time_limit): (&Cancel, Option<Duration>),
        axis: AxisSource,
    ) -> Option<SweepCell> {
        let cell = &self.cells[c];
        let prepared = match &cell.scene {
            Ok(scene) => prepare(scene, self.integrals.as_deref(), axis)
                .map_err(|e| format!("{}: {}", e.path.unwrap_or_default(), e.message)),
            Err(e) => Err(e.clone()),
        };
        // The observables, compiled with the cell's parameters: sampled once, at t_end.
        let (prepared, observables) = match prepared {
            Ok(p) => match self.observables_for(&p).transpose() {
                Ok(observables) => (Ok(p), observables),
                Err(e) => (Err(e), None),
            },
            Err(e) => (Err(e), None),
        };
        let mut cfg = run_config(self.points, time_limit);
        cfg.samples = usize::from(observables.is_some());
        let at_end = |sampled: Option<ObservablesView>| {
            let names = &self.head.observables;
            (!names.is_empty()).then(|| {
                let last = sampled.filter(|s| s.t.len() == 1);
                ValuesView(match last {
                    Some(s) => s.columns.into_iter().map(|(n, c)| (n, c[0])).collect(),
                    None => names.iter().map(|n| (n.clone(), f64::NAN)).collect(),
                })
            })
        };
        let mut rows = Vec::with_capacity(cell.methods.len());
        for (i, (request, method)) in cell.methods.iter().enumerate() {
            let view = method.as_ref().map_or_else(|_| view_of(request), MethodView::of);
            let mut row = SweepRow {
                cell: c,
                values: cell.values.clone(),
                method_index: i,
                method: view,
                status: RowStatus::Invalid,
                error: None,
                steps: 0,
                cpu_ms: None,
                newton_iterations: None,
                verdicts: BTreeMap::new(),
                gaps: BTreeMap::new(),
                observables: at_end(None),
                simulate: self.echo(c, request, method.as_ref().ok()),
            };
            match (&prepared, method) {
                (Err(e), _) | (_, Err(e)) => row.error = Some(e.clone()),
                (Ok(prepared), Ok(method)) => {
                    let names = IntegralNames::of(prepared);
                    let mut collector = JsonCollector::new(&[], names, cancel.clone());
                    if let Some(observables) = &observables {
                        collector = collector.sampling_at_end(observables.clone());
                    }
                    let clock = ThreadClock::start();
                    newton::take_iterations();
                    let outcome = catch_unwind(AssertUnwindSafe(|| {
                        prepared.run(method, &cfg, &mut collector)
                    }));
                    let iterations = newton::take_iterations();
                    row.cpu_ms = clock.elapsed_ms();
                    match outcome {
                        Ok(outcome) => {
                            if let Some(RunError::Cancelled { .. }) = outcome.error {
                                return None;
                            }
                            row.status = match outcome.error {
                                None => RowStatus::Ok,
                                Some(_) => RowStatus::Failed,
                            };
                            row.error = outcome.error.map(|e| e.to_string());
                            row.steps = outcome.steps;
                            row.newton_iterations = method.info().implicit.then_some(iterations);
                            row.observables = at_end(collector.take_observables());
                            row.verdicts = collector.verdicts.all();
                            row.gaps = collector.verdicts.gaps();
                        }
                        Err(_) => {
                            tracing::error!(cell = c, method = i, "a sweep's run panicked");
                            row.status = RowStatus::Failed;
                            row.error = Some("internal error: the simulation panicked".into());
                        }
                    }
                }
            }
            rows.push(row);
        }
        Some(SweepCell { cell: c, values: cell.values.clone(), rows })
    }

    /// The `/simulate` body of one row: the cell's scene as resolved (or as given, when it
    /// is invalid) and the one method.
    pub(crate) fn echo(
        &self,
        c: usize,
        request: &MethodRequest,
        method: Option<&Method>,
    ) -> SimulateEcho {
        let method = match method {
            Some(m) => method_body(&crate::sweep::plan::request_of(m)),
            None => method_body(request),
        };
        let integrals = self.integrals.clone();
        match &self.cells[c].scene {
            Ok(scene) => resolved(scene, integrals, method, self.points),
            Err(_) => {
                let body = self.body(c);
                SimulateEcho {
                    system: body.system,
                    preset: body.preset,
                    params: body.params.iter().flat_map(|p| p.0.iter().cloned()).collect(),
                    q: body.q,
                    v: body.v,
                    step: body.step,
                    t_end: body.t_end,
                    integrals,
                    methods: vec![method],
                    points: self.points,
                }
            }
        }
    }
}

/// The body of a resolved `scene`: every value in place.
fn resolved(
    scene: &Scene,
    integrals: Option<Vec<String>>,
    method: BTreeMap<String, Value>,
    points: usize,
) -> SimulateEcho {
    SimulateEcho {
        system: match scene.system.custom() {
            None => SystemField::Id(scene.system.id().to_owned()),
            Some(c) => SystemField::of(&c.spec_at_values()),
        },
        preset: scene.preset.map(str::to_owned),
        params: scene.named_params().into_iter().map(|(n, v)| (n.to_owned(), v)).collect(),
        q: Some(scene.q.clone()),
        v: Some(scene.v.clone()),
        step: Some(scene.step),
        t_end: Some(scene.t_end),
        integrals,
        methods: vec![method],
        points,
    }
}

/// A method request as a `/simulate` body gives it: `{"id": …, "alpha": …, "composition": …}`.
fn method_body(m: &MethodRequest) -> BTreeMap<String, Value> {
    let mut out = BTreeMap::from([("id".to_owned(), Value::from(m.id.clone()))]);
    for (name, value) in &m.params {
        out.insert(name.clone(), Value::from(*value));
    }
    if let Some(c) = &m.composition {
        out.insert("composition".into(), Value::from(c.clone()));
    }
    if let Some(t) = &m.tableau {
        out.insert("tableau".into(), crate::request::tableau_value(t));
    }
    if let Some(c) = &m.constraint {
        out.insert("constraint".into(), Value::from(c.clone()));
    }
    out
}

/// The view of a method that did not resolve: as requested.
fn view_of(m: &MethodRequest) -> MethodView {
    MethodView {
        id: m.id.clone(),
        params: m.params.iter().cloned().collect(),
        composition: m.composition.clone(),
        tableau: m.tableau.as_ref().map(crate::views::TableauEcho::requested),
        constraint: m.constraint.clone(),
        label: m.id.clone(),
    }
}
