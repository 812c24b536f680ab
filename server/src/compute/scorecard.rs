//! A `/scorecard` request checked and priced before admission ([`plans`]): each scene as
//! `/simulate` checks it (its errors under `scenes[i]`), the methods and `points` once for
//! all, the series one scene's runs hold at once within the answer budget, and the runs and
//! property measurements of every scene within `max_request_seconds`.

use super::{
    Caches, Delivery, KEPT_BYTES_PER_POINT, Plan, Priced, check_answer_bytes, check_price,
};
use crate::config::Config;
use crate::error::AppError;
use crate::request::{MethodRequest, SceneSpec, ScorecardRequest};
use nhlab_core::catalogue::cost::run_cost_of;
use nhlab_core::catalogue::registry::LITERATURE_SCENES;
use nhlab_core::{Method, PAPER_SCENES};

/// Most scenes per scorecard.
pub const MAX_SCENES: usize = 16;

/// Steps that measuring a method's properties on a scene takes (round trips from four
/// points, the coupling checks, the manifold check's 200), rounded up: priced with its runs.
pub const PROPERTY_STEPS: f64 = 400.0;

/// Every registered method, the paper's five first ([`Method::all`]).
fn all_methods() -> Vec<MethodRequest> {
    Method::all()
        .iter()
        .map(|m| {
            let params = m.params().into_iter().map(|(n, v)| (n.to_owned(), v)).collect();
            MethodRequest::new(m.info().id, params)
        })
        .collect()
}

/// The checked scenes, and the bytes their runs will hold at once: the series of one
/// scene's runs, kept for their verdicts (the scenes run one after another, and a scene's
/// series are dropped once judged; what the answer keeps of them, the verdicts, is small).
pub fn plans(
    req: &ScorecardRequest,
    config: &Config,
    caches: &Caches,
) -> Result<(Vec<Plan>, u64), AppError> {
    let scenes = match &req.scenes {
        None => PAPER_SCENES
            .iter()
            .chain(&LITERATURE_SCENES)
            .map(|(system, preset)| SceneSpec {
                system: (*system).into(),
                preset: Some((*preset).to_owned()),
                ..SceneSpec::default()
            })
            .collect(),
        Some(s) if s.is_empty() => {
            return Err(AppError::invalid(
                "scenes",
                "scenes must not be empty; leave it out for the paper's six experiments",
            ));
        }
        Some(s) if s.len() > MAX_SCENES => {
            return Err(AppError::invalid(
                "scenes",
                format!("{} scenes exceed the limit of {MAX_SCENES} per scorecard", s.len()),
            ));
        }
        Some(s) => s.clone(),
    };
    let methods = req.methods.clone().unwrap_or_else(all_methods);
    let plans = scenes
        .into_iter()
        .enumerate()
        .map(|(i, scene)| {
            let sim = scene.to_simulate(Some(methods.clone()), req.points);
            Plan::resolve_all(&sim, config, caches, Delivery::JsonOnly).map_err(|mut e| {
                // Methods and points are the scorecard's own fields; the rest is the scene's.
                if let Some(path) = &e.path
                    && !path.starts_with("methods")
                    && path != "points"
                {
                    e.path = Some(format!("scenes[{i}].{path}"));
                }
                e
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let held = plans.iter().map(|p| p.held_bytes(KEPT_BYTES_PER_POINT)).max().unwrap_or(0);
    let what = " (a scene's runs' series, kept for their verdicts: series × points × bytes \
                per point)";
    check_answer_bytes(held, config, what)?;
    let mut priced = Vec::new();
    for plan in &plans {
        priced.extend(plan.priced());
        let system = &plan.prepared.scene.system;
        for (m, why) in plan.methods.iter().zip(&plan.not_applicable) {
            if why.is_none() {
                let cost = run_cost_of(system, m, PROPERTY_STEPS);
                priced.push(Priced::new(format!("{}'s properties", m.label()), 1.0, cost));
            }
        }
    }
    check_price(&priced, config, "scenes", "shorten t_end, use fewer scenes or methods")?;
    Ok((plans, held))
}
