//! Scenes: what a user asks for ([`SceneRequest`]), resolved against the system's presets
//! and checked field by field ([`Scene`]), then prepared for a set of integrals
//! ([`PreparedScene`], which computes the latitude's monodromy axis once for all methods).
//!
//! Resolution: the preset (the system's first when none is named) fills params, q, v, step
//! and t_end; explicit fields override it. The number of steps is `⌊t_end/h + 10⁻⁹⌋`.

use super::params::resolve_params;
use super::registry::{ReferenceState, RunInput, Start, SystemEntry, system};
use crate::measure::latitude::LatitudeAxis;
use crate::measure::simulate::{Observer, RunConfig, RunOutcome};
use crate::{InputError, Integral, Method};

/// A scene as a user gives it: only `system` is required.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneRequest {
    /// System id.
    pub system: String,
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

/// A resolved, checked scene.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The system.
    pub system: &'static SystemEntry,
    /// The preset it started from.
    pub preset: &'static str,
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
    /// Resolves and checks a request.
    pub fn resolve(req: &SceneRequest) -> Result<Self, InputError> {
        let entry = system(&req.system)?;
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
        let scene = Self { system: entry, preset: preset.id, params, q, v, step, t_end };
        let residual = (entry.residual)(scene.start());
        // A NaN residual (overflowing q or v) is inconsistent too.
        if residual.is_nan() || residual > 1e-9 {
            return Err(InputError::InconsistentVelocity { residual });
        }
        Ok(scene)
    }

    /// `N = ⌊t_end/h + 10⁻⁹⌋`: t_end = 3000, h = 0.1 is 30,000 steps.
    pub fn steps(&self) -> u64 {
        (self.t_end / self.step + 1e-9).floor() as u64
    }

    /// The system's parameters and the initial state.
    pub fn start(&self) -> Start<'_> {
        Start { params: &self.params, q: &self.q, v: &self.v }
    }

    /// Parameter names with their values.
    pub fn named_params(&self) -> Vec<(&'static str, f64)> {
        self.system.info().params.iter().map(|p| p.name).zip(self.params.iter().copied()).collect()
    }

    /// Measures the reversibility and fibration preservation of `method` from this scene's
    /// start with its step (see [`crate::measure::properties`]).
    pub fn properties(
        &self,
        method: &Method,
    ) -> Result<crate::measure::properties::Properties, crate::StepFailure> {
        (self.system.properties)(self.start(), self.step, method)
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
        (self.system.reference)(self.start(), self.t_end, tol, stop)
    }

    /// Checks `integrals` against the system (all it has when `None`) and computes the
    /// latitude's axis when the latitude is among them.
    pub fn prepare(self, integrals: Option<&[String]>) -> Result<PreparedScene, InputError> {
        self.prepare_with_latitude(integrals, Scene::latitude_axis)
    }

    /// The latitude's monodromy axis from this scene's start (see [`crate::measure::latitude`]); it
    /// depends on the system, its parameters, q and v only, not on the step or t_end.
    pub fn latitude_axis(&self) -> Result<LatitudeAxis, InputError> {
        (self.system.latitude)(self.start())
    }

    /// [`prepare`](Self::prepare), the axis (when the latitude is measured) obtained from
    /// `axis` rather than computed here: a server keeps axes across requests in a cache.
    pub fn prepare_with_latitude(
        self,
        integrals: Option<&[String]>,
        axis: impl FnOnce(&Scene) -> Result<LatitudeAxis, InputError>,
    ) -> Result<PreparedScene, InputError> {
        let info = self.system.info();
        let integrals = match integrals {
            None => info.integrals.to_vec(),
            Some(names) => {
                let mut out = Vec::new();
                for name in names {
                    let i = Integral::from_id(name).ok_or_else(|| InputError::UnknownIntegral {
                        name: name.clone(),
                        valid: Integral::valid_ids(),
                    })?;
                    if !info.integrals.contains(&i) {
                        return Err(InputError::IntegralUnavailable {
                            integral: name.clone(),
                            system: info.id.into(),
                            available: info
                                .integrals
                                .iter()
                                .map(|i| i.id())
                                .collect::<Vec<_>>()
                                .join(", "),
                        });
                    }
                    if !out.contains(&i) {
                        out.push(i);
                    }
                }
                out
            }
        };
        let latitude =
            if integrals.contains(&Integral::Latitude) { Some(axis(&self)?) } else { None };
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
        (scene.system.run)(&input, method, cfg, observer)
    }
}
