//! Scenes: what a user asks for ([`SceneRequest`]), resolved against the system's presets
//! and checked field by field ([`Scene`]), then prepared for a set of integrals
//! ([`PreparedScene`], which computes the latitude's monodromy axis once for all methods).
//!
//! Resolution: the preset (the system's first when none is named) fills params, q, v, step
//! and t_end; explicit fields override it. The number of steps is `⌊t_end/h + 10⁻⁹⌋`.

use super::custom::{CustomSystem, SystemSpec};
use super::registry::{ReferenceState, RunInput, Start, SystemCode, SystemEntry, system};
use crate::measure::latitude::LatitudeAxis;
use crate::measure::simulate::{Observer, RunConfig, RunOutcome};
use crate::model::custom::{CustomLimits, FormulaSpec, GeneralSpec, Parameters};
use crate::model::params::resolve_params;
use crate::{Bucket, Gap, InputError, Integral, Method, Short};
use std::ops::ControlFlow;
use std::sync::Arc;

/// The system a scene asks for: a built-in by id, or one given as formulas.
#[derive(Debug, Clone, PartialEq)]
pub enum SystemRequest {
    /// A built-in system's id.
    Id(String),
    /// A system of the paper's class given in its form (`docs/model.md` §10).
    Formulas(FormulaSpec),
    /// A system given in the general form (`docs/model.md` §10).
    General(GeneralSpec),
}

impl From<&str> for SystemRequest {
    fn from(id: &str) -> Self {
        Self::Id(id.into())
    }
}

impl Default for SystemRequest {
    fn default() -> Self {
        Self::Id(String::new())
    }
}

/// A scene's system, resolved.
#[derive(Debug, Clone)]
pub enum SceneSystem {
    /// A built-in compiled into nhlab.
    BuiltIn(&'static SystemEntry),
    /// A system given as formulas, compiled: a user's, or a built-in given as formulas.
    Custom(Arc<CustomSystem>),
}

impl SceneSystem {
    /// Its code.
    pub fn code(&self) -> &'static SystemCode {
        match self {
            Self::BuiltIn(entry) => entry.native.as_ref().expect("a native built-in has code"),
            Self::Custom(c) => c.code,
        }
    }
    /// The built-in's id, or the name of a system given as formulas.
    pub fn id(&self) -> &str {
        match self.built_in() {
            Some(entry) => entry.info().id,
            None => self.custom().map_or("", |c| c.spec.name()),
        }
    }
    /// The built-in, if it is one.
    pub fn built_in(&self) -> Option<&'static SystemEntry> {
        match self {
            Self::BuiltIn(entry) => Some(entry),
            Self::Custom(c) => c.built_in,
        }
    }
    /// The system a user gave as formulas, if it is one (not a built-in).
    pub fn custom(&self) -> Option<&CustomSystem> {
        match self {
            Self::Custom(c) if c.built_in.is_none() => Some(c),
            _ => None,
        }
    }
    /// Its compilation, for any system given as formulas (a built-in's too).
    pub fn formulas(&self) -> Option<&CustomSystem> {
        match self {
            Self::BuiltIn(_) => None,
            Self::Custom(c) => Some(c),
        }
    }
    /// Its parameters' names, in order.
    pub fn param_names(&self) -> Vec<&str> {
        match (self.built_in(), self.custom()) {
            (Some(entry), _) => entry.info().params.iter().map(|p| p.name).collect(),
            (None, Some(c)) => c.spec.parameters().iter().map(|p| p.0.as_str()).collect(),
            (None, None) => Vec::new(),
        }
    }
    /// The integrals it has.
    pub fn integrals(&self) -> &[Integral] {
        match self {
            Self::BuiltIn(entry) => entry.info().integrals,
            Self::Custom(c) => &c.integrals,
        }
    }
    /// The names of its invariants, in order.
    pub fn invariant_names(&self) -> &[String] {
        self.formulas().and_then(|c| c.invariants.as_deref()).map_or(&[], |i| i.names())
    }
    /// The API name of one of its integrals (an invariant's is the system's name for it).
    pub fn integral_name(&self, integral: Integral) -> String {
        match integral {
            Integral::Invariant(k) => self
                .invariant_names()
                .get(k as usize)
                .cloned()
                .unwrap_or_else(|| format!("invariant{k}")),
            _ => integral.id().to_owned(),
        }
    }
    /// Whether it runs as the paper's class (the class's steps), found or built in.
    pub fn in_paper_class(&self) -> bool {
        !self.code().general
    }
    /// Its coordinates' names, in the user's order (a built-in's as its general form names
    /// them); observables and velocities (`x_dot`) are named after them.
    pub fn coordinate_names(&self) -> Vec<String> {
        let spec = match (self.custom(), self.built_in()) {
            (Some(c), _) => Some((*c.spec).clone()),
            (None, Some(entry)) => {
                let info = entry.info();
                let defaults: Vec<f64> = info.params.iter().map(|p| p.default).collect();
                GeneralSpec::of_built_in(info, &defaults).ok().map(SystemSpec::General)
            }
            (None, None) => None,
        };
        match spec {
            Some(SystemSpec::General(g)) => g.coordinates,
            Some(SystemSpec::Coupled(c)) => {
                c.passenger.iter().cloned().chain(std::iter::once(c.driver)).collect()
            }
            None => (0..self.dof()).map(|i| format!("q{i}")).collect(),
        }
    }
    /// Its number of coordinates, as given.
    pub fn dof(&self) -> usize {
        self.formulas().map_or(self.code().dof, |c| c.dof)
    }
    /// What identifies the system's equations, for caches: the id, or the whole formula
    /// form (parameters are a scene's own).
    pub fn key(&self) -> String {
        match self.custom() {
            None => self.id().into(),
            Some(c) => format!("{:?}", c.spec),
        }
    }
}

/// A scene as a user gives it: only `system` is required.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneRequest {
    /// The system.
    pub system: SystemRequest,
    /// Preset id; the system's first preset when absent.
    pub preset: Option<String>,
    /// Parameter overrides, by name.
    pub params: Vec<(String, f64)>,
    /// Initial configuration override.
    pub q: Option<Vec<f64>>,
    /// Initial velocity override.
    pub v: Option<Vec<f64>>,
    /// Step override.
    pub step: Option<f64>,
    /// Final time override.
    pub t_end: Option<f64>,
}

/// Systems given as formulas, compiled, for one system at a time
/// ([`Scene::resolve_cached`]): a sweep resolves many scenes of one system.
///
/// By default a system is compiled once per set of parameter values, the values folded into
/// its code. [`CompiledSystems::parameters_as_inputs`] compiles a system given by a request
/// once, its parameters inputs of the code, and binds that compilation to each set of values
/// (microseconds, where compiling a large formula takes a good fraction of a second). Built-ins
/// given as formulas, whose formulas may change with a parameter, are always compiled per set.
#[derive(Debug, Default)]
pub struct CompiledSystems {
    /// What the systems kept are compiled from: a spec, or a built-in's id.
    source: Option<Source>,
    /// How a request's own system takes its parameters.
    parameters: Parameters,
    /// Where the parameters are inputs: the one compilation, bound to its first values.
    template: Option<Arc<CustomSystem>>,
    systems: std::collections::HashMap<Vec<(String, u64)>, Arc<CustomSystem>>,
}

/// What a compiled system comes from.
#[derive(Debug, Clone, PartialEq)]
enum Source {
    Spec(SystemSpec),
    BuiltIn(&'static str),
}

impl CompiledSystems {
    /// Most systems kept: beyond, compiling is no longer the cost worth saving.
    pub const CAPACITY: usize = 4096;

    /// Compiles a request's own system once, its parameters inputs of the code (see the
    /// type's doc).
    pub fn parameters_as_inputs() -> Self {
        Self { parameters: Parameters::Inputs, ..Self::default() }
    }

    fn get_or_compile(
        &mut self,
        source: Source,
        parameters: &[(String, f64)],
        limits: &CustomLimits,
        compile: impl FnOnce(Parameters) -> Result<CustomSystem, InputError>,
    ) -> Result<Arc<CustomSystem>, InputError> {
        if self.source.as_ref() != Some(&source) {
            self.source = Some(source.clone());
            self.systems.clear();
            self.template = None;
        }
        if self.parameters == Parameters::Inputs && matches!(source, Source::Spec(_)) {
            return match &self.template {
                Some(template) => Ok(Arc::new(template.bind(parameters, limits)?)),
                None => {
                    let system = Arc::new(compile(Parameters::Inputs)?);
                    self.template = Some(system.clone());
                    Ok(system)
                }
            };
        }
        // Bits, not values: -0 and 0 may compile differently, and NaN is refused anyway.
        let key: Vec<(String, u64)> =
            parameters.iter().map(|(n, v)| (n.clone(), v.to_bits())).collect();
        if let Some(found) = self.systems.get(&key) {
            return Ok(found.clone());
        }
        let custom = Arc::new(compile(Parameters::Folded)?);
        if self.systems.len() < Self::CAPACITY {
            self.systems.insert(key, custom.clone());
        }
        Ok(custom)
    }
}

/// A resolved, checked scene.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The system.
    pub system: SceneSystem,
    /// The preset it started from (none for a system given as formulas).
    pub preset: Option<&'static str>,
    /// Parameter values, in the order of the system's `params`.
    pub params: Vec<f64>,
    /// Initial configuration.
    pub q: Vec<f64>,
    /// Initial velocity.
    pub v: Vec<f64>,
    /// Step size.
    pub step: f64,
    /// Final time.
    pub t_end: f64,
    /// q and v as the system's code holds them (reordered or padded for some systems given
    /// as formulas).
    internal: (Vec<f64>, Vec<f64>),
}

fn finite(field: impl Into<String>, value: f64) -> Result<f64, InputError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(InputError::NonFinite { field: field.into(), value })
    }
}

/// The largest magnitude of a component of the initial state: far enough below
/// [`DIVERGED`](crate::measure::simulate::DIVERGED), where a run stops as diverged, that a state of
/// such components is not already beyond it (which would fail the first step with the
/// advice to shorten it).
pub const MAX_INITIAL: f64 = 1e90;

fn vector(field: &str, values: &[f64], dof: usize) -> Result<Vec<f64>, InputError> {
    if values.len() != dof {
        return Err(InputError::WrongLength {
            field: field.into(),
            expected: dof,
            got: values.len(),
        });
    }
    for (i, &x) in values.iter().enumerate() {
        let field = format!("{field}[{i}]");
        if finite(&field, x)?.abs() > MAX_INITIAL {
            return Err(InputError::TooLarge { field, value: x, limit: MAX_INITIAL });
        }
    }
    Ok(values.to_vec())
}

impl Scene {
    /// Default step and final time of a system given as formulas, which has no presets.
    pub const CUSTOM_STEP: f64 = 0.1;
    /// See [`Scene::CUSTOM_STEP`].
    pub const CUSTOM_T_END: f64 = 100.0;

    /// The step and final time `req` asks for (its own, else its preset's, else the defaults
    /// of a system given as formulas), without compiling anything: `None` where the system or
    /// preset is unknown (resolving says why).
    pub fn step_and_t_end(req: &SceneRequest) -> Option<(f64, f64)> {
        let (step, t_end) = match &req.system {
            SystemRequest::Id(id) => {
                let presets = system(id).ok()?.info().presets;
                let preset = match &req.preset {
                    None => presets.first()?,
                    Some(p) => presets.iter().find(|x| x.id == p)?,
                };
                (preset.step, preset.t_end)
            }
            SystemRequest::Formulas(_) | SystemRequest::General(_) => {
                (Self::CUSTOM_STEP, Self::CUSTOM_T_END)
            }
        };
        Some((req.step.unwrap_or(step), req.t_end.unwrap_or(t_end)))
    }

    /// Resolves and checks a request, a system given as formulas within the default limits.
    pub fn resolve(req: &SceneRequest) -> Result<Self, InputError> {
        Self::resolve_within(req, &CustomLimits::default())
    }

    /// Resolves and checks a request, a system given as formulas within `limits`.
    pub fn resolve_within(req: &SceneRequest, limits: &CustomLimits) -> Result<Self, InputError> {
        Self::resolve_cached(req, limits, &mut CompiledSystems::default())
    }

    /// [`resolve_within`](Self::resolve_within), a system given as formulas taken from
    /// `compiled` when it was compiled there with the same parameters: a sweep resolves many
    /// scenes of one system, and compiles it once per set of parameter values.
    pub fn resolve_cached(
        req: &SceneRequest,
        limits: &CustomLimits,
        compiled: &mut CompiledSystems,
    ) -> Result<Self, InputError> {
        let entry = match &req.system {
            SystemRequest::Id(id) => system(id)?,
            SystemRequest::Formulas(spec) => {
                let source = Source::Spec(SystemSpec::Coupled(spec.clone()));
                let custom = compiled.get_or_compile(source, &req.params, limits, |p| {
                    CustomSystem::compile_with(spec, &req.params, limits, p)
                })?;
                return Self::resolve_custom(req, custom);
            }
            SystemRequest::General(spec) => {
                let source = Source::Spec(SystemSpec::General(spec.clone()));
                let custom = compiled.get_or_compile(source, &req.params, limits, |p| {
                    CustomSystem::compile_general_with(spec, &req.params, limits, p)
                })?;
                return Self::resolve_custom(req, custom);
            }
        };
        let info = entry.info();
        let preset = match &req.preset {
            None => &info.presets[0],
            Some(id) => info.presets.iter().find(|p| p.id == id).ok_or_else(|| {
                InputError::UnknownPreset {
                    id: id.clone(),
                    system: info.id.into(),
                    valid: info.presets.iter().map(|p| p.id).collect::<Vec<_>>().join(", "),
                }
            })?,
        };
        let given = preset.params.iter().map(|&(n, v)| (n, v, false));
        let overrides = req.params.iter().map(|(n, v)| (n.as_str(), *v, true));
        let owner = format!("system {}", info.id);
        let params = resolve_params(info.params, given.chain(overrides), "params.", &owner)?;
        let system = match &entry.native {
            Some(_) => SceneSystem::BuiltIn(entry),
            None => {
                let named: Vec<(String, f64)> = info
                    .params
                    .iter()
                    .map(|p| p.name.to_string())
                    .zip(params.iter().copied())
                    .collect();
                SceneSystem::Custom(compiled.get_or_compile(
                    Source::BuiltIn(info.id),
                    &named,
                    limits,
                    |_| CustomSystem::built_in(entry, &params, limits),
                )?)
            }
        };
        let dof = system.dof();
        let q = vector("q", req.q.as_deref().unwrap_or(preset.q), dof)?;
        let v = vector("v", req.v.as_deref().unwrap_or(preset.v), dof)?;
        let step = finite("step", req.step.unwrap_or(preset.step))?;
        if step <= 0.0 {
            return Err(InputError::NonPositiveStep { step });
        }
        let t_end = finite("t_end", req.t_end.unwrap_or(preset.t_end))?;
        if t_end < step {
            return Err(InputError::TEndTooShort { t_end, step });
        }
        let internal = internal(&system, &q, &v);
        let scene = Self { system, preset: Some(preset.id), params, q, v, step, t_end, internal };
        scene.consistent()
    }

    fn resolve_custom(req: &SceneRequest, custom: Arc<CustomSystem>) -> Result<Self, InputError> {
        if req.preset.is_some() {
            return Err(InputError::CustomSystem {
                field: "preset".into(),
                message: "a system given as formulas has no presets: give q and v (and step, \
                          t_end) instead"
                    .into(),
            });
        }
        let dof = custom.dof;
        let required = |field: &str, given: &Option<Vec<f64>>| {
            given.clone().ok_or_else(|| InputError::CustomSystem {
                field: field.into(),
                message: format!(
                    "{field} is required for a system given as formulas: {dof} numbers, one per \
                     coordinate in the order given (the passengers then the driver in the \
                     paper's form)"
                ),
            })
        };
        let q = vector("q", &required("q", &req.q)?, dof)?;
        let v = vector("v", &required("v", &req.v)?, dof)?;
        custom.check_start(&q)?;
        let step = finite("step", req.step.unwrap_or(Self::CUSTOM_STEP))?;
        if step <= 0.0 {
            return Err(InputError::NonPositiveStep { step });
        }
        let t_end = finite("t_end", req.t_end.unwrap_or(Self::CUSTOM_T_END))?;
        if t_end < step {
            return Err(InputError::TEndTooShort { t_end, step });
        }
        let params = custom.values.clone();
        let system = SceneSystem::Custom(custom);
        let internal = internal(&system, &q, &v);
        Self { system, preset: None, params, q, v, step, t_end, internal }.consistent()
    }

    /// The scene, if its start passes the checks every system's does: A(q₀) finite and of
    /// full rank (its smallest singular value above `10⁻¹⁰ · max(1, largest)`), and the
    /// initial velocity on the constraints (`|A(q₀) v₀| ≤ 10⁻⁹`; the message gives the nearest
    /// velocity that is, in the metric of M).
    fn consistent(self) -> Result<Self, InputError> {
        let c = (self.system.code().constraint)(self.start());
        let field = if self.system.custom().is_some() { "system.constraints" } else { "q" };
        for r in 0..c.a.nrows() {
            for j in 0..c.a.ncols() {
                let x = c.a[(r, j)];
                if !x.is_finite() {
                    let at = match self.system.custom() {
                        Some(f) if j < f.order.len() => {
                            format!("system.constraints[{r}][{}]", f.order[j])
                        }
                        _ => field.into(),
                    };
                    return Err(InputError::CustomSystem {
                        field: at,
                        message: format!("this entry of A is {} at the initial state", Short(x)),
                    });
                }
            }
        }
        let sv = c.a.singular_values();
        let (min, max) = (sv.min(), sv.max());
        if min.is_nan() || min <= 1e-10 * max.max(1.0) {
            return Err(InputError::CustomSystem {
                field: field.into(),
                message: format!(
                    "A(q) loses rank at the initial q: its smallest singular value is {min:.3e} \
                     (largest {max:.3e}); the constraint rows must be independent there"
                ),
            });
        }
        let v = nalgebra::DVector::from_column_slice(&self.internal.1);
        let av = &c.a * &v;
        let residual = av.norm();
        // A NaN residual (overflowing q or v) is inconsistent too.
        if residual.is_nan() || residual > 1e-9 {
            let m_inv = c.mass.clone().try_inverse().unwrap_or_else(|| c.mass.clone());
            let m_at = &m_inv * c.a.transpose();
            let nearest = match (&c.a * &m_at).lu().solve(&av) {
                Some(mu) => &v - &m_at * mu,
                None => v.clone(),
            };
            let nearest = match self.system.formulas() {
                Some(f) => f.to_user(nearest.as_slice()),
                None => nearest.as_slice().to_vec(),
            };
            return Err(InputError::InconsistentVelocity { residual, nearest });
        }
        Ok(self)
    }

    /// `N = ⌊t_end/h + 10⁻⁹⌋`: t_end = 3000, h = 0.1 is 30,000 steps.
    pub fn steps(&self) -> u64 {
        (self.t_end / self.step + 1e-9).floor() as u64
    }

    /// The system's parameters and the initial state, as its code holds them.
    pub fn start(&self) -> Start<'_> {
        Start {
            params: &self.params,
            q: &self.internal.0,
            v: &self.internal.1,
            formulas: self.system.formulas().map(|c| &c.structure),
            invariants: self.system.formulas().and_then(|c| c.invariants.as_ref()),
        }
    }

    /// The exact solution at t_end, where the system has one (`SystemInfo::exact`).
    pub fn exact(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        let exact = self.system.built_in()?.info().exact?;
        Some(exact(&self.params, &self.q, &self.v, self.t_end))
    }

    /// Parameter names with their values.
    pub fn named_params(&self) -> Vec<(&str, f64)> {
        self.system.param_names().into_iter().zip(self.params.iter().copied()).collect()
    }

    /// Measures the reversibility and fibration preservation of `method` from this scene's
    /// start with its step (see [`crate::measure::properties`]).
    pub fn properties(
        &self,
        method: &Method,
    ) -> Result<crate::measure::properties::Properties, crate::StepFailure> {
        self.properties_until(method, &|| false)
    }

    /// [`properties`](Self::properties), ended with [`StepFailure::Stopped`](crate::StepFailure)
    /// once `stop()` turns true (looked at before every step).
    pub fn properties_until(
        &self,
        method: &Method,
        stop: &dyn Fn() -> bool,
    ) -> Result<crate::measure::properties::Properties, crate::StepFailure> {
        (self.system.code().properties)(self.start(), self.step, method, stop)
    }

    /// The Dop853 reference solution at t_end (see [`crate::measure::reference`]).
    pub fn reference(
        &self,
        tol: f64,
    ) -> Result<ReferenceState, crate::measure::reference::ReferenceError> {
        self.reference_until(tol, &|| false)
    }

    /// [`reference`](Self::reference), cancelled when `stop()` turns true (looked at about
    /// every [`AIM`](crate::measure::pace::AIM)).
    pub fn reference_until(
        &self,
        tol: f64,
        stop: &dyn Fn() -> bool,
    ) -> Result<ReferenceState, crate::measure::reference::ReferenceError> {
        let mut r = (self.system.code().reference)(self.start(), self.t_end, tol, stop)?;
        if let Some(f) = self.system.formulas() {
            (r.q, r.v) = (f.to_user(&r.q), f.to_user(&r.v));
        }
        Ok(r)
    }

    /// Checks `integrals` against the system (all it has when `None`) and computes the
    /// latitude's axis when the latitude is among them.
    pub fn prepare(self, integrals: Option<&[String]>) -> Result<PreparedScene, InputError> {
        self.prepare_with_latitude(integrals, Scene::latitude_axis)
    }

    /// The latitude's monodromy axis from this scene's start (see [`crate::measure::latitude`]); it
    /// depends on the system, its parameters, q and v only, not on the step or t_end.
    pub fn latitude_axis(&self) -> Result<LatitudeAxis, InputError> {
        (self.system.code().latitude)(self.start())
    }

    /// [`prepare`](Self::prepare), the axis (when the latitude is measured) obtained from
    /// `axis` rather than computed here: a server keeps axes across requests in a cache.
    pub fn prepare_with_latitude(
        self,
        integrals: Option<&[String]>,
        axis: impl FnOnce(&Scene) -> Result<LatitudeAxis, InputError>,
    ) -> Result<PreparedScene, InputError> {
        let available = self.system.integrals();
        let asked = integrals.is_some();
        let name_of = |i: &Integral| self.system.integral_name(*i);
        let mut integrals = match integrals {
            None => available.to_vec(),
            Some(names) => {
                let mut out = Vec::new();
                for name in names {
                    let invariant = self.system.invariant_names().iter().position(|n| n == name);
                    let i = Integral::from_id(name)
                        .or(invariant.map(|k| Integral::Invariant(k as u8)))
                        .ok_or_else(|| InputError::UnknownIntegral {
                            name: name.clone(),
                            valid: Integral::ALL
                                .iter()
                                .map(|i| i.id().to_owned())
                                .chain(self.system.invariant_names().iter().cloned())
                                .collect::<Vec<_>>()
                                .join(", "),
                        })?;
                    if !available.contains(&i) {
                        let why = match i {
                            Integral::Latitude if self.system.in_paper_class() => {
                                " (the latitude is defined for two passengers, one constraint and U = |x|²/2 + const, docs/model.md §5)"
                            }
                            Integral::Latitude
                            | Integral::PassengerEnergy
                            | Integral::DriverEnergy => {
                                " (the passenger's and the driver's energies and the latitude are defined on the paper's class only, docs/model.md §1)"
                            }
                            _ => "",
                        };
                        return Err(InputError::IntegralUnavailable {
                            integral: name.clone(),
                            system: self.system.id().into(),
                            available: available.iter().map(name_of).collect::<Vec<_>>().join(", ")
                                + why,
                        });
                    }
                    if !out.contains(&i) {
                        out.push(i);
                    }
                }
                out
            }
        };
        let latitude = match integrals.contains(&Integral::Latitude).then(|| axis(&self)) {
            None => None,
            Some(Ok(axis)) => Some(axis),
            // Asked for by name, an undefined latitude is the request's error; among "all the
            // system has" it is left out (the scene's integrals say so).
            Some(Err(InputError::LatitudeUndefined { .. })) if !asked => {
                integrals.retain(|&i| i != Integral::Latitude);
                None
            }
            Some(Err(e)) => return Err(e),
        };
        Ok(PreparedScene { scene: self, integrals, latitude })
    }
}

/// A scene ready to run: integrals checked, latitude axis computed once.
#[derive(Debug, Clone)]
pub struct PreparedScene {
    /// The scene.
    pub scene: Scene,
    /// The integrals to measure.
    pub integrals: Vec<Integral>,
    /// The monodromy axis, when the latitude is measured.
    pub latitude: Option<LatitudeAxis>,
}

impl PreparedScene {
    /// The API name of one of its integrals.
    pub fn integral_name(&self, integral: Integral) -> String {
        self.scene.system.integral_name(integral)
    }

    /// Whether `method` has a step for the scene's system: every method on the paper's class,
    /// every method but those the class alone has on the general one (field `id`).
    pub fn check_method(&self, method: &Method) -> Result<(), InputError> {
        match method.info().class_only {
            Some(why) if !self.scene.system.in_paper_class() => {
                let system = &self.scene.system;
                let not_class = system
                    .formulas()
                    .and_then(|f| f.not_class.as_deref())
                    .map_or(String::new(), |w| format!(": {w}"));
                Err(InputError::NotApplicable {
                    field: "id".into(),
                    message: format!(
                        "{} applies only to systems of the paper's class: {why}; {} is not in \
                         it{not_class}",
                        method.label(),
                        system.id()
                    ),
                })
            }
            _ => Ok(()),
        }
    }

    /// Runs one method, streaming to `observer` (the final state in the user's order).
    pub fn run(&self, method: &Method, cfg: &RunConfig, observer: &mut dyn Observer) -> RunOutcome {
        let scene = &self.scene;
        let input = RunInput {
            start: scene.start(),
            step: scene.step,
            steps: scene.steps(),
            integrals: &self.integrals,
            latitude: self.latitude,
        };
        let run = scene.system.code().run;
        match scene.system.formulas() {
            None => run(&input, method, cfg, observer),
            Some(f) => {
                let (q, v) = (vec![0.0; f.dof], vec![0.0; f.dof]);
                run(&input, method, cfg, &mut UserOrder { observer, system: f, q, v })
            }
        }
    }
}

/// The internal q and v of a system's code from the user's.
fn internal(system: &SceneSystem, q: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
    match system.formulas() {
        Some(f) => (f.to_internal(q), f.to_internal(v)),
        None => (q.to_vec(), v.to_vec()),
    }
}

/// An observer of a run of a system given as formulas: the final state back in the user's
/// order (the code may hold it reordered or padded).
struct UserOrder<'a> {
    observer: &'a mut dyn Observer,
    system: &'a CustomSystem,
    /// The state of `state`, in the user's order.
    q: Vec<f64>,
    v: Vec<f64>,
}

impl Observer for UserOrder<'_> {
    fn initial(&mut self, integral: Integral, value: f64) {
        self.observer.initial(integral, value);
    }
    fn points(&mut self, integral: Integral, bucket: Bucket) {
        self.observer.points(integral, bucket);
    }
    fn gap(&mut self, integral: Integral, gap: Gap) {
        self.observer.gap(integral, gap);
    }
    fn finish(&mut self, q: &[f64], v: &[f64]) {
        self.observer.finish(&self.system.to_user(q), &self.system.to_user(v));
    }
    fn sample(&mut self, t: f64, q: &[f64], v: &[f64]) {
        self.observer.sample(t, &self.system.to_user(q), &self.system.to_user(v));
    }
    fn state(&mut self, t: f64, q: &[f64], v: &[f64]) {
        // Every step: into buffers kept for the run, not allocated per step.
        self.system.to_user_into(q, &mut self.q);
        self.system.to_user_into(v, &mut self.v);
        self.observer.state(t, &self.q, &self.v);
    }
    fn progress(&mut self, steps_done: u64, t: f64) -> ControlFlow<()> {
        self.observer.progress(steps_done, t)
    }
}
