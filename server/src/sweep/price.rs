//! A sweep's work priced before admission: its cells share the system, so each method is
//! priced once, on the first cell where it runs (ns per step of the method on the system),
//! and multiplied by the steps it takes over all the cells (each cell's t_end / step, a
//! composition's sub-steps counted); the sum against `max_request_seconds`
//! ([`check_price`]).

use crate::compute::{Priced, check_price};
use crate::config::Config;
use crate::error::AppError;
use nhlab_core::catalogue::cost::{RunCost, step_ns};
use nhlab_core::{Method, Scene};

/// Refuses (422 at `axes`) a sweep whose `runs` (each a method's index in the cell, the
/// cell's scene and the method) would take more CPU than `max_request_seconds`; its
/// estimate in seconds otherwise.
pub fn check<'a>(
    runs: impl Iterator<Item = (usize, &'a Scene, &'a Method)>,
    config: &Config,
) -> Result<f64, AppError> {
    // Per method index: its first run, the runs and their steps in all.
    let mut by_method: Vec<Option<(&Scene, &Method, f64, f64)>> = Vec::new();
    for (i, scene, m) in runs {
        if by_method.len() <= i {
            by_method.resize(i + 1, None);
        }
        let steps = scene.t_end / scene.step * m.stages() as f64;
        match &mut by_method[i] {
            Some((_, _, count, total)) => (*count, *total) = (*count + 1.0, *total + steps),
            None => by_method[i] = Some((scene, m, 1.0, steps)),
        }
    }
    let priced: Vec<Priced> = by_method
        .into_iter()
        .flatten()
        .map(|(scene, m, count, steps)| {
            let cost = RunCost { ns_per_step: step_ns(&scene.system, m), steps: steps / count };
            Priced::new(m.label(), count, cost)
        })
        .collect();
    let advice = "narrow the axes, shorten t_end or lengthen the step, or split it into shards \
                  (nhlab sweep --shard)";
    check_price(&priced, config, "axes", advice)
}
