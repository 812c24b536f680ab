//! [`SystemsResponse`]: the answer of `GET /systems`, everything a client needs to build a
//! request: the systems with their parameters, integrals and presets (the paper's
//! experiments), the methods with theirs, the default methods, the paper's experiments and the
//! server's limits.

use crate::config::Config;
use crate::request::{FormulaSystem, GeneralSystem};
use crate::views::{MethodView, StoredTableauView};
use nhlab_core::catalogue::custom::SystemSpec;
use nhlab_core::catalogue::registry::{LITERATURE_SCENES, PAPER_SECTION, PaperSection};
use nhlab_core::methods::prk::stored::stored;
use nhlab_core::model::custom::Structure;
use nhlab_core::model::system::Form;
use nhlab_core::{
    Composition, FormulaSpec, GeneralSpec, Method, PAPER_SCENES, ParamSpec, Preset, SYSTEMS, Scene,
    SceneRequest, SystemEntry, method_infos,
};
use serde::Serialize;
use std::collections::BTreeMap;
use std::sync::OnceLock;
use utoipa::ToSchema;

/// The answer of `GET /systems`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SystemsResponse {
    /// Every system.
    pub systems: Vec<SystemView>,
    /// Every method.
    pub methods: Vec<MethodInfoView>,
    /// The methods run when a request names none (the paper's five).
    pub default_methods: Vec<MethodView>,
    /// The symmetric compositions a symmetric method may be taken in (a method's
    /// `composition`).
    pub compositions: Vec<CompositionView>,
    /// The stored tableaux a `prk` method may name (`{"id": "prk", "tableau": "gauss2"}`).
    pub tableaux: Vec<StoredTableauView>,
    /// The paper's six experiments (the scorecard's default scenes), in the paper's order.
    pub paper_scenes: Vec<PaperScene>,
    /// The literature's test problems beyond the paper's (the scorecard's further scenes).
    pub literature_scenes: Vec<PaperScene>,
    /// The Paper view's figure beyond the paper: Poincaré sections beside the reference's.
    pub paper_section: PaperSectionView,
    /// The server's limits.
    pub limits: LimitsView,
}

/// A symmetric composition `Φ_{γ_s h} ∘ … ∘ Φ_{γ_1 h}` of a symmetric method of order 2.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct CompositionView {
    /// Id, as a method's `composition` (`p4s3`: order 4, 3 stages).
    pub id: String,
    /// Human name.
    pub name: String,
    /// Order of the composed method.
    pub order: u32,
    /// Sub-steps per step.
    pub stages: usize,
    /// The sub-steps' fractions γ of the step, in the order they are taken.
    pub coefficients: Vec<f64>,
    /// Where the coefficients come from.
    pub reference: String,
}

/// One of the paper's experiments: a system and one of its presets.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct PaperScene {
    /// System id.
    pub system: String,
    /// Preset id.
    pub preset: String,
}

/// The Paper view's figure beyond the paper: a scene, its methods (the reference among them),
/// the section asked for and the integrals whose verdicts the caption reports.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct PaperSectionView {
    /// System id.
    pub system: String,
    /// Preset id.
    pub preset: String,
    /// The methods run.
    pub methods: Vec<MethodView>,
    /// The integrals whose verdicts the caption reports.
    pub integrals: Vec<String>,
    /// The request's `section`: `surface`, `direction` and `plot`.
    #[schema(value_type = Object)]
    pub section: serde_json::Value,
}

impl PaperSectionView {
    fn of(s: &PaperSection) -> Self {
        Self {
            system: s.scene.0.into(),
            preset: s.scene.1.into(),
            methods: s.methods().iter().map(MethodView::of).collect(),
            integrals: s.integrals.iter().map(|&i| i.to_owned()).collect(),
            section: serde_json::json!({
                "surface": s.surface, "direction": s.direction, "plot": s.plot
            }),
        }
    }
}

/// A system.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SystemView {
    /// Id, as in requests.
    pub id: String,
    /// Human name.
    pub name: String,
    /// What it is.
    pub description: String,
    /// Where it comes from (the papers, or the software, whose test problem it is).
    pub source: String,
    /// Number of coordinates (length of q and v).
    pub dof: usize,
    /// Number of constraints.
    pub constraints: usize,
    /// Its parameters.
    pub params: Vec<ParamView>,
    /// The integrals it has.
    pub integrals: Vec<String>,
    /// Its presets; the first is the default.
    pub presets: Vec<PresetView>,
    /// A system of the paper's class written in the paper's form (passenger, driver, U,
    /// V_d), its parameters at their defaults: a request may send it as `system` (with q and
    /// v) and get the same numbers. Null for the others.
    pub formulas: Option<FormulaSystem>,
    /// The system in the general form (coordinates, M, V, A, invariants), its parameters at
    /// their defaults: a request may send it as `system` (with q and v); a starting point for
    /// a system of one's own.
    pub general: GeneralSystem,
    /// Whether it is in the paper's class (`docs/model.md` §1), as nhlab finds it at its
    /// default parameters.
    pub paper_class: PaperClassView,
    /// The methods that apply to it (ids).
    pub methods: Vec<String>,
    /// Whether its exact solution is known (work–precision measures against it rather than a
    /// numerical reference).
    pub exact: bool,
}

/// Whether a system is in the paper's class, and as what.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct PaperClassView {
    /// In the class: the class's steps run, with E, h (and the latitude where defined).
    pub member: bool,
    /// The driver ζ's name, where it is.
    pub driver: Option<String>,
    /// Why it is not, where it is not.
    pub why_not: Option<String>,
}

impl PaperClassView {
    /// What a scene's system is found to be.
    pub fn of(scene: &Scene) -> Self {
        let member = scene.system.in_paper_class();
        let (driver, why_not) = match scene.system.formulas() {
            Some(f) => {
                let driver = match (&f.structure, &*f.spec) {
                    (Structure::Class { driver, .. }, SystemSpec::General(g)) => {
                        g.coordinates.get(*driver).cloned()
                    }
                    (Structure::Class { .. }, SystemSpec::Coupled(c)) => Some(c.driver.clone()),
                    (Structure::General(_), _) => None,
                };
                (driver, f.not_class.clone())
            }
            None => {
                let info = scene.system.built_in().map(SystemEntry::info);
                if member {
                    let last = info.and_then(|i| match i.form {
                        Form::Coupled(f) => Some(f.driver.to_owned()),
                        Form::General(_) => None,
                    });
                    (last, None)
                } else {
                    (None, info.and_then(|i| outside_the_class(i.id)))
                }
            }
        };
        Self { member, driver, why_not }
    }
}

/// Why a built-in compiled into nhlab outside the paper's class is outside it: its general
/// form, at its default parameters, looked at as a system given as formulas would be (once).
fn outside_the_class(id: &str) -> Option<String> {
    static WHY: OnceLock<Vec<(&'static str, Option<String>)>> = OnceLock::new();
    let why = WHY.get_or_init(|| {
        SYSTEMS
            .iter()
            .filter(|e| e.native.as_ref().is_some_and(|c| c.general))
            .map(|e| {
                let info = e.info();
                let defaults: Vec<f64> = info.params.iter().map(|p| p.default).collect();
                let limits = nhlab_core::CustomLimits::default();
                let found = GeneralSpec::of_built_in(info, &defaults)
                    .and_then(|g| nhlab_core::CustomSystem::compile_general(&g, &[], &limits));
                (info.id, found.ok().and_then(|f| f.not_class))
            })
            .collect()
    });
    why.iter().find(|(i, _)| *i == id).and_then(|(_, w)| w.clone())
}

/// A parameter of a system or a method.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ParamView {
    /// Name, as in requests.
    pub name: String,
    /// Value when not given.
    pub default: f64,
    /// Lower bound (null: unbounded).
    pub min: Option<f64>,
    /// Upper bound (null: unbounded).
    pub max: Option<f64>,
    /// Whether `min` itself is excluded.
    pub min_open: bool,
    /// Whether `max` itself is excluded.
    pub max_open: bool,
    /// What it means.
    pub description: String,
}

/// A preset: a named scene.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct PresetView {
    /// Id, as in requests.
    pub id: String,
    /// Human label.
    pub label: String,
    /// Parameter values it sets (the others take their defaults).
    pub params: BTreeMap<String, f64>,
    /// Initial configuration.
    pub q: Vec<f64>,
    /// Initial velocity.
    pub v: Vec<f64>,
    /// Step size.
    pub step: f64,
    /// Final time.
    pub t_end: f64,
    /// Whether its scene is in the paper's class (its parameters may take the system out of
    /// it: the system's `paper_class` is at the defaults); the class-only methods apply only
    /// where it is.
    pub paper_class: bool,
}

/// A method.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct MethodInfoView {
    /// Id, as in requests.
    pub id: String,
    /// Human name.
    pub name: String,
    /// Its parameters.
    pub params: Vec<ParamView>,
    /// Order of convergence with default parameters.
    pub order: u32,
    /// Where it comes from.
    pub reference: String,
    /// Whether a step solves a nonlinear system.
    pub implicit: bool,
    /// Whether it may take a `composition`: its step is symmetric (DLA^α at α = 0.5 only).
    pub composable: bool,
    /// The order its compositions reach where below the scheme's order (measured: LF, DD and
    /// DD-AVF stop at 4; `docs/high-order.md`); absent where they reach it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub composed_order_limit: Option<u32>,
    /// Whether it is a measuring instrument rather than a method under study: `reference`,
    /// the Dop853 reference solve taken one step at a time (a run of it puts the exact
    /// solution beside the methods'; `/work-precision` measures against it already). Never
    /// among the defaults.
    pub instrument: bool,
    /// Whether it is given as a tableau and a constraint (`prk`): its order and symmetry are
    /// then those of the `tableaux` entry's `constraints`, and `order` and `composable` here
    /// are its default's.
    pub by_tableau: bool,
    /// Where the step is symmetric (so composable) at one value of a parameter only (DLA^α at
    /// α = 0.5): that value and the order elsewhere; absent where any values do.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub symmetric_at: Option<SymmetricAtView>,
}

/// A parameter value at which alone a method is symmetric, and its order elsewhere.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct SymmetricAtView {
    /// The parameter.
    pub param: String,
    /// Its value there.
    pub value: f64,
    /// The method's order at any other value (no composition then).
    pub order_elsewhere: u32,
}

/// The limits a request must respect.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct LimitsView {
    /// Most steps per run for a JSON response.
    pub max_steps_json: u64,
    /// Most steps per run for a stream.
    pub max_steps_stream: u64,
    /// Most `points` per series.
    pub max_points: u64,
    /// Most methods per request.
    pub max_methods: usize,
    /// Largest request body, in bytes.
    pub max_body_bytes: usize,
    /// Most simulations computing at once (more get 503 with `Retry-After`).
    pub max_simulations: usize,
    /// Most characters per formula of a system given as formulas.
    pub formula_chars: usize,
    /// Deepest nesting in a formula.
    pub formula_depth: usize,
    /// Most parameters of a system given as formulas.
    pub formula_parameters: usize,
    /// Most cells per sweep.
    pub max_sweep_cells: u64,
    /// Most steps one sweep takes in all.
    pub max_sweep_steps: u64,
}

fn bound(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl ParamView {
    fn of(p: &ParamSpec) -> Self {
        Self {
            name: p.name.into(),
            default: p.default,
            min: bound(p.min),
            max: bound(p.max),
            min_open: p.min_open,
            max_open: p.max_open,
            description: p.description.into(),
        }
    }
}

impl PresetView {
    fn of(system: &str, p: &Preset) -> Self {
        let req =
            SceneRequest { system: system.into(), preset: Some(p.id.into()), ..Default::default() };
        // Every built-in's presets resolve (core's `tests/it/inputs.rs`).
        let scene = Scene::resolve(&req).expect("a built-in's preset");
        Self {
            paper_class: scene.system.in_paper_class(),
            id: p.id.into(),
            label: p.label.into(),
            params: p.params.iter().map(|&(n, v)| (n.to_owned(), v)).collect(),
            q: p.q.to_vec(),
            v: p.v.to_vec(),
            step: p.step,
            t_end: p.t_end,
        }
    }
}

impl SystemView {
    fn of(entry: &'static SystemEntry) -> Self {
        let info = entry.info();
        let defaults: Vec<f64> = info.params.iter().map(|p| p.default).collect();
        // Every built-in's general form compiles at its defaults (`tests/systems.rs`), and its
        // default scene resolves (core's `tests/it/inputs.rs`).
        let general = GeneralSpec::of_built_in(info, &defaults).expect("a built-in's form");
        let req = SceneRequest { system: info.id.into(), ..Default::default() };
        let scene = Scene::resolve(&req).expect("a built-in's default scene");
        let paper_class = PaperClassView::of(&scene);
        let in_class = paper_class.member;
        let prepared = scene.clone().prepare(None).expect("a built-in's integrals");
        Self {
            id: info.id.into(),
            name: info.name.into(),
            description: info.description.into(),
            source: info.source.into(),
            dof: general.coordinates.len(),
            constraints: general.constraints.len(),
            params: info.params.iter().map(ParamView::of).collect(),
            integrals: scene
                .system
                .integrals()
                .iter()
                .map(|&i| prepared.integral_name(i))
                .collect(),
            presets: info.presets.iter().map(|p| PresetView::of(info.id, p)).collect(),
            formulas: FormulaSpec::of(info).as_ref().map(FormulaSystem::of),
            general: GeneralSystem::of(&general),
            paper_class,
            methods: method_infos()
                .into_iter()
                .filter(|m| !m.external && (in_class || m.class_only.is_none()))
                .map(|m| m.id.to_owned())
                .collect(),
            exact: info.exact.is_some(),
        }
    }

    /// Every built-in's view, computed once (the formula built-ins compile for it).
    fn all() -> &'static [SystemView] {
        static ALL: OnceLock<Vec<SystemView>> = OnceLock::new();
        ALL.get_or_init(|| SYSTEMS.iter().map(SystemView::of).collect())
    }
}

impl SystemsResponse {
    /// The listing, with the limits of `config`.
    pub fn new(config: &Config) -> Self {
        let composable = nhlab_core::methods::composable();
        Self {
            systems: SystemView::all().to_vec(),
            // A method written in Python exists only in the Python package's process.
            methods: method_infos()
                .into_iter()
                .filter(|m| !m.external)
                .map(|m| MethodInfoView {
                    id: m.id.into(),
                    name: m.name.into(),
                    params: m.params.iter().map(ParamView::of).collect(),
                    order: m.order,
                    reference: m.reference.into(),
                    implicit: m.implicit,
                    composable: composable.contains(&m.id),
                    composed_order_limit: m.composed_order_limit,
                    instrument: m.instrument,
                    by_tableau: m.by_tableau,
                    symmetric_at: m.symmetric_at.map(|s| SymmetricAtView {
                        param: s.param.into(),
                        value: s.value,
                        order_elsewhere: s.order_elsewhere,
                    }),
                })
                .collect(),
            default_methods: Method::paper_five().iter().map(MethodView::of).collect(),
            compositions: Composition::ALL
                .iter()
                .map(|c| CompositionView {
                    id: c.id().into(),
                    name: c.name().into(),
                    order: c.order(),
                    stages: c.stages(),
                    coefficients: c.coefficients().to_vec(),
                    reference: c.reference().into(),
                })
                .collect(),
            tableaux: stored().iter().map(StoredTableauView::of).collect(),
            paper_scenes: PAPER_SCENES
                .iter()
                .map(|(system, preset)| PaperScene {
                    system: (*system).into(),
                    preset: (*preset).into(),
                })
                .collect(),
            literature_scenes: LITERATURE_SCENES
                .iter()
                .map(|(system, preset)| PaperScene {
                    system: (*system).into(),
                    preset: (*preset).into(),
                })
                .collect(),
            paper_section: PaperSectionView::of(&PAPER_SECTION),
            limits: LimitsView {
                max_steps_json: config.max_steps_json,
                max_steps_stream: config.max_steps_stream,
                max_points: config.max_points,
                max_methods: config.max_methods,
                max_body_bytes: config.max_body_bytes,
                max_simulations: config.max_simulations,
                formula_chars: config.formulas.formula.max_chars,
                formula_depth: config.formulas.formula.max_depth,
                formula_parameters: config.formulas.max_parameters,
                max_sweep_cells: config.max_sweep_cells,
                max_sweep_steps: config.max_sweep_steps,
            },
        }
    }
}
