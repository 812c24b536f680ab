//! [`Plan`]: a `/simulate` request resolved and checked against the core and the limits
//! (steps, answer size, CPU time estimated: [`check_price`]), ready to run. Every error names
//! the field at fault.

use crate::compute::{Caches, JSON_BYTES_PER_POINT, Priced, answer_bytes, check_price, mib};
use crate::config::Config;
use crate::error::AppError;
use crate::request::{MethodRequest, ObservablesRequest, SectionRequest, SimulateRequest};
use crate::views::SceneView;
use nhlab_core::catalogue::cost::run_cost;
use nhlab_core::measure::observables::Observables;
use nhlab_core::measure::section::{Direction, Section};
use nhlab_core::{InputError, Method, MethodSpec, PreparedScene, RunConfig, Scene, Short};
use std::time::Duration;

/// Bytes an observable's sampled value holds: 8 as a number, ~24 as JSON text.
pub const OBSERVABLE_BYTES_PER_VALUE: u64 = 32;

/// What a request over `max_request_seconds` may do.
pub const ADVICE: &str = "shorten t_end, lengthen the step or use fewer methods";
use std::sync::Arc;

/// How the result goes back: the limits differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delivery {
    /// One JSON response at the end.
    Json,
    /// Server-sent events as the runs go.
    Stream,
    /// One JSON response, from an endpoint that cannot stream (`/scorecard`,
    /// `/work-precision`): the JSON limit, and no advice to ask for a stream.
    JsonOnly,
}

/// A checked request.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The scene, shared by the runs.
    pub prepared: Arc<PreparedScene>,
    /// The methods, one run each.
    pub methods: Vec<Method>,
    /// Buckets per series.
    pub points: usize,
    /// The resolved scene as reported.
    pub scene: SceneView,
    /// Per method: why it has no step for the system, where it has none (a run of it is
    /// refused, or reported as not applicable by the scorecard).
    pub not_applicable: Vec<Option<String>>,
    /// The observables each run samples at `points` times, if any were asked for.
    pub observables: Option<Arc<Observables>>,
    /// The Poincaré section each run records, if one was asked for.
    pub section: Option<Arc<SectionPlan>>,
}

/// A checked Poincaré section: the surface, the plotted quantities (their columns named by
/// their text) and the most crossings a run keeps.
#[derive(Debug)]
pub struct SectionPlan {
    /// The surface and the plotted quantities.
    pub section: Section,
    /// Most crossings kept per run.
    pub max_crossings: usize,
}

impl Plan {
    /// Resolves and checks `req` against the limits of `config`; the latitude axis comes from
    /// `caches` (computed and kept there on a miss). A method that has no step for the
    /// system is refused at `methods[i]` (at `methods` for the defaults).
    pub fn resolve(
        req: &SimulateRequest,
        config: &Config,
        caches: &Caches,
        delivery: Delivery,
    ) -> Result<Self, AppError> {
        let plan = Self::resolve_all(req, config, caches, delivery)?;
        if let Some((i, why)) =
            plan.not_applicable.iter().enumerate().find_map(|(i, w)| Some((i, w.as_ref()?)))
        {
            let at = if req.methods.is_some() { format!("methods[{i}]") } else { "methods".into() };
            return Err(AppError::invalid(at, why.clone()));
        }
        Ok(plan)
    }

    /// [`Plan::resolve`], keeping the methods that have no step for the system (with why,
    /// in `not_applicable`): the scorecard reports them so.
    pub fn resolve_all(
        req: &SimulateRequest,
        config: &Config,
        caches: &Caches,
        delivery: Delivery,
    ) -> Result<Self, AppError> {
        let axis = |scene: &Scene| caches.latitude(scene);
        let scene = Scene::resolve_within(&req.scene_request(), &config.formulas)?;
        check_steps(&scene, config, delivery, None)?;
        let methods = methods(req.methods.as_deref(), config)?;
        // A composed method takes its stages' sub-steps per step: what the limit bounds.
        let composed = methods.iter().filter(|m| m.stages() > 1).max_by_key(|m| m.stages());
        if composed.is_some() {
            check_steps(&scene, config, delivery, composed)?;
        }
        let points = points(req.points, config)?;
        // Priced before the latitude axis is solved; the endpoints that cannot stream price
        // all their plans together.
        if delivery != Delivery::JsonOnly {
            let priced: Vec<Priced> = methods.iter().map(|m| priced(&scene, m, 1.0)).collect();
            check_price(&priced, config, "t_end", ADVICE)?;
        }
        let prepared = match &req.integrals {
            None => scene.prepare_with_latitude(None, axis)?,
            Some(names) if names.is_empty() => {
                return Err(AppError::invalid(
                    "integrals",
                    "integrals must not be empty; leave it out to measure all the system has",
                ));
            }
            Some(names) => {
                if let Some(i) = (1..names.len()).find(|&i| names[..i].contains(&names[i])) {
                    return Err(AppError::invalid(
                        format!("integrals[{i}]"),
                        format!("{} is listed twice; list each integral once", names[i]),
                    ));
                }
                scene
                    .prepare_with_latitude(Some(names), axis)
                    .map_err(|e| integral_error(e, names))?
            }
        };
        let scene = SceneView::of(&prepared, &methods, points);
        let not_applicable =
            methods.iter().map(|m| prepared.check_method(m).err().map(|e| e.to_string())).collect();
        let observables = observables_of(req.observables.as_ref(), &prepared, config)?;
        let section = match &req.section {
            None => None,
            Some(given) => Some(Arc::new(section_plan(given, req, &prepared, config)?)),
        };
        let plan = Self {
            prepared: Arc::new(prepared),
            methods,
            points,
            scene,
            not_applicable,
            observables,
            section,
        };
        let bytes_per_point = match delivery {
            // A stream keeps the buckets too, and a short run's last events hold them all as
            // JSON text, waiting for the client: as much as a JSON answer.
            Delivery::Json | Delivery::Stream => Some(JSON_BYTES_PER_POINT),
            // The endpoint checks the sum over its plans.
            Delivery::JsonOnly => None,
        };
        if let Some(per_point) = bytes_per_point {
            let what = " (series × points × bytes per point)";
            check_answer_bytes(plan.held_bytes(per_point), config, what)?;
        }
        Ok(plan)
    }

    /// What its runs will cost: one run per method that applies.
    pub fn priced(&self) -> Vec<Priced> {
        let scene = &self.prepared.scene;
        self.methods
            .iter()
            .zip(&self.not_applicable)
            .filter(|(_, why)| why.is_none())
            .map(|(m, _)| priced(scene, m, 1.0))
            .collect()
    }

    /// What the runs of this plan hold at the peak of their answer, at `bytes_per_point`:
    /// one series per method and integral, each of `points` buckets (fewer if the run has
    /// fewer steps).
    pub fn held_bytes(&self, bytes_per_point: u64) -> u64 {
        let series = (self.methods.len() * self.prepared.integrals.len()) as u64;
        let points = (self.points as u64).min(self.scene.steps.saturating_add(1));
        answer_bytes(series, points, bytes_per_point).saturating_add(self.observable_bytes())
    }

    /// What the runs' observables hold: per run, a column of times and one per observable,
    /// `points` values each, as numbers and then as JSON text (about 24 bytes a value).
    pub fn observable_bytes(&self) -> u64 {
        let runs = self.methods.len() as u64;
        let sampled = self.observables.as_ref().map_or(0, |observables| {
            let columns = (observables.names().len() + 1) as u64;
            let points = (self.points as u64).min(self.scene.steps.saturating_add(1));
            columns.saturating_mul(points)
        });
        // A section's columns, at their most crossings.
        let crossed = self.section.as_ref().map_or(0, |s| {
            ((s.section.plot.names().len() + 1) as u64).saturating_mul(s.max_crossings as u64)
        });
        runs.saturating_mul(sampled.saturating_add(crossed))
            .saturating_mul(OBSERVABLE_BYTES_PER_VALUE)
    }

    /// How each run of this plan reports: `points` buckets, its observables sampled at as
    /// many times, paced by the clock, and ended past `limit`.
    pub fn run_config(&self, limit: Option<Duration>) -> RunConfig {
        let mut cfg = run_config(self.points, limit);
        if self.observables.is_some() {
            cfg.samples = self.points;
        }
        cfg.every_step = self.section.is_some();
        cfg
    }
}

/// Checks and compiles a request's `observables` for its scene's system (errors at
/// `observables.NAME`); none when none are asked for.
pub fn observables_of(
    given: Option<&ObservablesRequest>,
    prepared: &PreparedScene,
    config: &Config,
) -> Result<Option<Arc<Observables>>, AppError> {
    let Some(given) = given else { return Ok(None) };
    if given.0.is_empty() {
        return Err(AppError::invalid(
            "observables",
            "observables must not be empty; leave it out to sample none",
        ));
    }
    let coordinates = prepared.scene.system.coordinate_names();
    let params = prepared.scene.named_params();
    let limits = &config.formulas.formula;
    Ok(Some(Arc::new(Observables::compile(&given.0, &coordinates, &params, limits)?)))
}

/// Checks and compiles a section: the surface (errors at `section.surface`), each plotted
/// quantity an observable's name or a formula (at `section.plot[i]`), the direction and the
/// most crossings.
fn section_plan(
    given: &SectionRequest,
    req: &SimulateRequest,
    prepared: &PreparedScene,
    config: &Config,
) -> Result<SectionPlan, AppError> {
    let coordinates = prepared.scene.system.coordinate_names();
    let params = prepared.scene.named_params();
    let names = (coordinates.as_slice(), params.as_slice(), &config.formulas.formula);
    let surface = vec![("surface".to_owned(), given.surface.clone())];
    let surface =
        Observables::compile_at(&surface, "section", &|_, _| "section.surface".into(), names)?;
    if given.plot.is_empty() {
        return Err(AppError::invalid("section.plot", "plot must name at least one quantity"));
    }
    let observables = req.observables.as_ref().map_or(&[][..], |o| o.0.as_slice());
    let plot: Vec<(String, String)> = given
        .plot
        .iter()
        .map(|p| {
            let formula = observables.iter().find(|(name, _)| name == p).map_or(p, |(_, f)| f);
            (p.clone(), formula.clone())
        })
        .collect();
    if let Some(i) = (1..plot.len()).find(|&i| plot[..i].iter().any(|(n, _)| *n == plot[i].0)) {
        return Err(AppError::invalid(
            format!("section.plot[{i}]"),
            format!("{} is listed twice; list each quantity once", plot[i].0),
        ));
    }
    let plot = Observables::compile_at(
        &plot,
        "section.plot",
        &|i, _| format!("section.plot[{i}]"),
        names,
    )?;
    let direction = match given.direction.as_deref() {
        None | Some("up") => Direction::Up,
        Some("down") => Direction::Down,
        Some("both") => Direction::Both,
        Some(other) => {
            return Err(AppError::invalid(
                "section.direction",
                format!("direction must be up, down or both, got {other:?}"),
            ));
        }
    };
    let limit = config.max_crossings;
    let max_crossings = match given.max_crossings {
        None => limit,
        Some(n) if n >= 1 && (n as u64) <= limit => n as u64,
        Some(n) => {
            return Err(AppError::invalid(
                "section.max_crossings",
                format!("max_crossings must be between 1 and {limit} (max_crossings), got {n}"),
            ));
        }
    };
    let max_crossings = usize::try_from(max_crossings).unwrap_or(usize::MAX);
    Ok(SectionPlan { section: Section { surface, plot, direction }, max_crossings })
}

/// Most steps between two looks at the cancellation flag (and the clock, for progress):
/// microseconds of a built-in's steps; fewer where they would take longer than a few
/// milliseconds ([`run_config`]).
pub const PROGRESS_EVERY: u64 = 1024;

/// How every run of the server reports: `points` buckets per series, progress every
/// [`PROGRESS_EVERY`] steps or paced by the clock where those take longer than a few
/// milliseconds (a look at the cancellation flag at least that often), and the time limit
/// `limit` ([`time_limit`]), if any.
pub fn run_config(points: usize, limit: Option<Duration>) -> RunConfig {
    RunConfig {
        points,
        progress_every: PROGRESS_EVERY,
        paced: true,
        time_limit: limit,
        samples: 0,
        every_step: false,
    }
}

/// `runs` runs of `m` on `scene`, priced.
pub fn priced(scene: &Scene, m: &Method, runs: f64) -> Priced {
    Priced::new(m.label(), runs, run_cost(scene, m))
}

/// Refuses a request whose answer would hold more than `max_answer_bytes` (422 at `points`,
/// the field that scales it most simply); `what` says what the estimate counts.
pub fn check_answer_bytes(bytes: u64, config: &Config, what: &str) -> Result<(), AppError> {
    if bytes <= config.max_answer_bytes {
        return Ok(());
    }
    Err(AppError::invalid(
        "points",
        format!(
            "the answer{what} would hold about {}, over the limit of {} per request \
             (max_answer_bytes); ask for fewer points, methods, integrals, scenes or cells",
            mib(bytes),
            mib(config.max_answer_bytes)
        ),
    ))
}

/// Refuses a run of more than the limit's steps, counting the sub-steps of `composed`, the
/// composed method with the most stages, if any.
fn check_steps(
    scene: &Scene,
    config: &Config,
    delivery: Delivery,
    composed: Option<&Method>,
) -> Result<(), AppError> {
    let stages = composed.map_or(1, Method::stages);
    let steps = scene.steps().saturating_mul(stages as u64);
    let (limit, how) = match delivery {
        Delivery::Json if config.max_steps_stream > config.max_steps_json => (
            config.max_steps_json,
            format!(
                "a JSON response; a stream (Accept: text/event-stream) allows {}",
                config.max_steps_stream
            ),
        ),
        Delivery::Json | Delivery::JsonOnly => {
            (config.max_steps_json, "a JSON response".to_owned())
        }
        Delivery::Stream => (config.max_steps_stream, "a stream".to_owned()),
    };
    if steps > limit {
        return Err(AppError::invalid(
            "t_end",
            format!(
                "{}t_end / step = {} / {} = {} steps per run exceeds the limit of {limit} \
                 steps for {how}; shorten t_end or lengthen step",
                composed.map_or(String::new(), |m| format!(
                    "{} sub-steps of {} × ",
                    stages,
                    m.label()
                )),
                Short(scene.t_end),
                Short(scene.step),
                steps_text(scene.step, scene.t_end, stages),
            ),
        ));
    }
    Ok(())
}

/// The steps a run from `step` to `t_end` takes with `stages` sub-steps per step, as a message writes them:
/// exactly where they are counted exactly, about so (`about 3.0e303`) where their count would not
/// fit an integer.
pub fn steps_text(step: f64, t_end: f64, stages: usize) -> String {
    let steps = steps_of(step, t_end).saturating_mul(stages as u64);
    if steps < 1_000_000_000_000_000 {
        steps.to_string()
    } else {
        format!("about {:.1e}", stages as f64 * t_end / step)
    }
}

/// The steps of a run from `step` to `t_end`, as [`Scene::steps`] counts them (saturating).
pub fn steps_of(step: f64, t_end: f64) -> u64 {
    (t_end / step + 1e-9).floor() as u64
}

/// The methods of a request (the paper's five when none are given), within the limit.
pub fn methods(given: Option<&[MethodRequest]>, config: &Config) -> Result<Vec<Method>, AppError> {
    let Some(given) = given else {
        return Ok(Method::paper_five().to_vec());
    };
    if given.is_empty() {
        return Err(AppError::invalid(
            "methods",
            "methods must not be empty; leave it out to run the paper's five",
        ));
    }
    if given.len() > config.max_methods {
        return Err(AppError::invalid(
            "methods",
            format!(
                "{} methods exceed the limit of {} per request",
                given.len(),
                config.max_methods
            ),
        ));
    }
    given.iter().enumerate().map(|(i, m)| method(i, m)).collect()
}

/// Method `i` of a request, its errors at `methods[i]` (and within its `params` where it
/// gave them there).
pub fn method(i: usize, m: &MethodRequest) -> Result<Method, AppError> {
    let spec = MethodSpec {
        id: m.id.clone(),
        params: m.params.clone(),
        composition: m.composition.clone(),
        tableau: m.tableau.clone(),
        constraint: m.constraint.clone(),
    };
    Method::from_spec(&spec).map_err(|e| {
        // A parameter's error points into `params` where it was given there.
        let in_params = m.nested
            && !matches!(
                e,
                InputError::UnknownMethod { .. }
                    | InputError::Composition { .. }
                    | InputError::Tableau { .. }
            );
        let e = if in_params { e.within("params") } else { e };
        AppError::from(e.within(&format!("methods[{i}]")))
    })
}

/// Buckets per series: `given`, or 1000; between 1 and the limit.
pub fn points(given: Option<i64>, config: &Config) -> Result<usize, AppError> {
    let points = given.unwrap_or(1000);
    if points < 1 || points as u64 > config.max_points {
        return Err(AppError::invalid(
            "points",
            format!("points must be between 1 and {}, got {points}", config.max_points),
        ));
    }
    usize::try_from(points).map_err(|_| AppError::invalid("points", "points is too large"))
}

/// Points an integral error at the offending entry of the list.
fn integral_error(e: InputError, names: &[String]) -> AppError {
    let name = match &e {
        InputError::UnknownIntegral { name, .. } => Some(name),
        InputError::IntegralUnavailable { integral, .. } => Some(integral),
        _ => None,
    };
    let index = name.and_then(|n| names.iter().position(|x| x == n));
    let mut err = AppError::from(e);
    if let Some(i) = index {
        err.path = Some(format!("integrals[{i}]"));
    }
    err
}
