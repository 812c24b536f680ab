//! Scenes: what a user asks for ([`SceneRequest`]), resolved against the system's presets
//! and checked field by field ([`Scene`]), then prepared for a set of integrals
//! ([`PreparedScene`], which computes the latitude's monodromy axis once for all methods).
//!
//! Resolution: the preset (the system's first when none is named) fills params, q, v, step
//! and t_end; explicit fields override it. The number of steps is `⌊t_end/h + 10⁻⁹⌋`.

use super::custom::CustomSystem;
use super::params::resolve_params;
use super::registry::{ReferenceState, RunInput, Start, SystemCode, SystemEntry, system};
use crate::measure::latitude::LatitudeAxis;
use crate::measure::simulate::{Observer, RunConfig, RunOutcome};
use crate::model::custom::{CustomLimits, FormulaSpec};
use crate::{InputError, Integral, Method};
use std::sync::Arc;

/// The system a scene asks for: a built-in by id, or one given as formulas.
#[derive(Debug, Clone, PartialEq)]
pub enum SystemRequest {
    /// A built-in system's id.
    Id(String),
    /// A system given as formulas (`docs/model.md` §7).
    Formulas(FormulaSpec),
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
    /// A built-in.
    BuiltIn(&'static SystemEntry),
    /// A system given as formulas, compiled.
    Custom(Arc<CustomSystem>),
}

impl SceneSystem {
    /// Its code.
    pub fn code(&self) -> &'static SystemCode {
        match self {
            Self::BuiltIn(entry) => &entry.code,
            Self::Custom(c) => c.code,
        }
    }
    /// The built-in's id, or the name of a system given as formulas.
    pub fn id(&self) -> &str {
        match self {
            Self::BuiltIn(entry) => entry.info().id,
            Self::Custom(c) => &c.spec.name,
        }
    }
    /// The built-in, if it is one.
    pub fn built_in(&self) -> Option<&'static SystemEntry> {
        match self {
            Self::BuiltIn(entry) => Some(entry),
            Self::Custom(_) => None,
        }
    }
    /// The system given as formulas, if it is one.
    pub fn custom(&self) -> Option<&CustomSystem> {
        match self {
            Self::BuiltIn(_) => None,
            Self::Custom(c) => Some(c),
        }
    }
    /// Its parameters' names, in order.
    pub fn param_names(&self) -> Vec<&str> {
        match self {
            Self::BuiltIn(entry) => entry.info().params.iter().map(|p| p.name).collect(),
            Self::Custom(c) => c.spec.parameters.iter().map(|p| p.0.as_str()).collect(),
        }
    }
    /// The integrals it has.
    pub fn integrals(&self) -> &[Integral] {
        match self {
            Self::BuiltIn(entry) => entry.info().integrals,
            Self::Custom(c) => &c.integrals,
        }
    }
    /// What identifies the system's equations, for caches: the id, or the whole formula
    /// form (parameters are a scene's own).
    pub fn key(&self) -> String {
        match self {
            Self::BuiltIn(entry) => entry.info().id.into(),
            Self::Custom(c) => format!("{:?}", c.spec),
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

/// Systems given as formulas, compiled, by their parameter values, for one set of formulas
/// at a time ([`Scene::resolve_cached`]).
#[derive(Debug, Default)]
pub struct CompiledSystems {
    spec: Option<FormulaSpec>,
    systems: std::collections::HashMap<Vec<(String, u64)>, Arc<CustomSystem>>,
}

impl CompiledSystems {
    /// Most systems kept: beyond, compiling is no longer the cost worth saving.
    pub const CAPACITY: usize = 4096;

    fn get_or_compile(
        &mut self,
        spec: &FormulaSpec,
        overrides: &[(String, f64)],
        limits: &CustomLimits,
    ) -> Result<Arc<CustomSystem>, InputError> {
        if self.spec.as_ref() != Some(spec) {
            self.spec = Some(spec.clone());
            self.systems.clear();
        }
        // Bits, not values: -0 and 0 may compile differently, and NaN is refused anyway.
        let key: Vec<(String, u64)> =
            overrides.iter().map(|(n, v)| (n.clone(), v.to_bits())).collect();
        if let Some(found) = self.systems.get(&key) {
            return Ok(found.clone());
        }
        let custom = Arc::new(CustomSystem::compile(spec, overrides, limits)?);
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
                return Self::resolve_custom(req, spec, limits, compiled);
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
        let q = vector("q", req.q.as_deref().unwrap_or(preset.q), entry.dof)?;
        let v = vector("v", req.v.as_deref().unwrap_or(preset.v), entry.dof)?;
        let step = finite("step", req.step.unwrap_or(preset.step))?;
        if step <= 0.0 {
            return Err(InputError::NonPositiveStep { step });
        }
        let t_end = finite("t_end", req.t_end.unwrap_or(preset.t_end))?;
        if t_end < step {
            return Err(InputError::TEndTooShort { t_end, step });
        }
        let scene = Self {
            system: SceneSystem::BuiltIn(entry),
            preset: Some(preset.id),
            params,
            q,
            v,
            step,
            t_end,
        };
        scene.consistent()
    }

    fn resolve_custom(
        req: &SceneRequest,
        spec: &FormulaSpec,
        limits: &CustomLimits,
        compiled: &mut CompiledSystems,
    ) -> Result<Self, InputError> {
        if req.preset.is_some() {
            return Err(InputError::CustomSystem {
                field: "preset".into(),
                message: "a system given as formulas has no presets: give q and v (and step, \
                          t_end) instead"
                    .into(),
            });
        }
        let custom = compiled.get_or_compile(spec, &req.params, limits)?;
        let dof = custom.code.dof;
        let required = |field: &str, given: &Option<Vec<f64>>| {
            given.clone().ok_or_else(|| InputError::CustomSystem {
                field: field.into(),
                message: format!(
                    "{field} is required for a system given as formulas: {dof} numbers, the \
                     passenger coordinates then the driver"
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
        let params = custom.compiled.values.clone();
        let system = SceneSystem::Custom(custom);
        Self { system, preset: None, params, q, v, step, t_end }.consistent()
    }

    /// The scene, if its initial velocity satisfies the constraints.
    fn consistent(self) -> Result<Self, InputError> {
        let residual = (self.system.code().residual)(self.start());
        // A NaN residual (overflowing q or v) is inconsistent too.
        if residual.is_nan() || residual > 1e-9 {
            return Err(InputError::InconsistentVelocity { residual });
        }
        Ok(self)
    }

    /// `N = ⌊t_end/h + 10⁻⁹⌋`: t_end = 3000, h = 0.1 is 30,000 steps.
    pub fn steps(&self) -> u64 {
        (self.t_end / self.step + 1e-9).floor() as u64
    }

    /// The system's parameters and the initial state.
    pub fn start(&self) -> Start<'_> {
        Start {
            params: &self.params,
            q: &self.q,
            v: &self.v,
            custom: self.system.custom().map(|c| &c.compiled),
        }
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
        (self.system.code().properties)(self.start(), self.step, method)
    }

    /// The Dop853 reference solution at t_end (see [`crate::measure::reference`]).
    pub fn reference(
        &self,
        tol: f64,
    ) -> Result<ReferenceState, crate::measure::reference::ReferenceError> {
        self.reference_until(tol, &|| false)
    }

    /// [`reference`](Self::reference), cancelled when `stop()` turns true (looked at every
    /// [`STOP_EVERY`](crate::measure::reference::STOP_EVERY) steps).
    pub fn reference_until(
        &self,
        tol: f64,
        stop: &dyn Fn() -> bool,
    ) -> Result<ReferenceState, crate::measure::reference::ReferenceError> {
        (self.system.code().reference)(self.start(), self.t_end, tol, stop)
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
        let mut integrals = match integrals {
            None => available.to_vec(),
            Some(names) => {
                let mut out = Vec::new();
                for name in names {
                    let i = Integral::from_id(name).ok_or_else(|| InputError::UnknownIntegral {
                        name: name.clone(),
                        valid: Integral::valid_ids(),
                    })?;
                    if !available.contains(&i) {
                        let why = match &self.system {
                            SceneSystem::Custom(_) if i == Integral::Latitude => {
                                " (the latitude is defined for two passengers, one constraint and U = |x|²/2 + const, docs/model.md §5)"
                            }
                            _ => "",
                        };
                        return Err(InputError::IntegralUnavailable {
                            integral: name.clone(),
                            system: self.system.id().into(),
                            available: available
                                .iter()
                                .map(|i| i.id())
                                .collect::<Vec<_>>()
                                .join(", ")
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
    /// Runs one method, streaming to `observer`.
    pub fn run(&self, method: &Method, cfg: &RunConfig, observer: &mut dyn Observer) -> RunOutcome {
        let scene = &self.scene;
        let input = RunInput {
            start: scene.start(),
            step: scene.step,
            steps: scene.steps(),
            integrals: &self.integrals,
            latitude: self.latitude,
        };
        (scene.system.code().run)(&input, method, cfg, observer)
    }
}
