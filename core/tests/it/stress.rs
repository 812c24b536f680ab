//! Stability under stress: for every method × system, sweep the step upward and
//! record the largest h for which the run stays finite, Newton converges and every energy
//! error (H, E and h) stays below the stated bound `max |I − I(0)| ≤ 0.1 · max(1, |I(0)|)`. Every run, however
//! large its step, must end — `ok` or `failed` with a message naming the step — never panic
//! or hang (each run is at most 4000 steps). Prints the table of docs/stability.md:
//! `cargo test --release -p nhlab-core --test it stress:: -- --nocapture`

use nhlab_core::{
    Collect, Integral, Method, MethodSpec, RunConfig, SYSTEMS, Scene, SceneRequest, method_infos,
};
use std::panic::{AssertUnwindSafe, catch_unwind};

const T_END: f64 = 200.0;
const BOUND: f64 = 0.1;

fn steps() -> Vec<f64> {
    (0..=16).map(|k| 0.05 * 2f64.powf(k as f64 / 2.0)).collect() // 0.05 … 12.8
}

#[test]
fn step_sweep_every_method_every_system() {
    println!("| system | method | largest stable h | first failure above it |");
    println!("|---|---|---|---|");
    let methods: Vec<Method> = method_infos()
        .iter()
        .filter(|info| !info.external)
        .flat_map(|info| {
            let base = MethodSpec::new(info.id);
            if info.id == "dla" {
                vec![base.clone().with("alpha", 0.5), base.with("alpha", 0.4)]
            } else {
                vec![base]
            }
        })
        .map(|spec| Method::from_spec(&spec).unwrap())
        .collect();
    for entry in SYSTEMS {
        for m in &methods {
            let mut stable = None;
            let mut first_failure = None;
            for h in steps() {
                let req = SceneRequest {
                    system: entry.info().id.into(),
                    step: Some(h),
                    t_end: Some(T_END.max(h)),
                    ..Default::default()
                };
                let scene = Scene::resolve(&req).unwrap();
                let energies: Vec<String> =
                    [Integral::Energy, Integral::PassengerEnergy, Integral::DriverEnergy]
                        .into_iter()
                        .filter(|i| scene.system.integrals().contains(i))
                        .map(|i| i.id().to_owned())
                        .collect();
                let scene = scene.prepare(Some(&energies)).unwrap();
                if scene.check_method(m).is_err() {
                    continue;
                }
                let mut c = Collect::default();
                let out = catch_unwind(AssertUnwindSafe(|| {
                    scene.run(m, &RunConfig { points: 10, ..Default::default() }, &mut c)
                }))
                .unwrap_or_else(|_| panic!("{} {} h = {h}: panicked", entry.info().id, m.label()));
                // The worst energy error relative to its bound, and which integral it was.
                let (mut err, mut worst) = (0.0, Integral::Energy);
                for (i, s) in &c.series {
                    let max = s.iter().map(|b| b.max).fold(0.0, f64::max);
                    assert!(
                        max.is_finite(),
                        "{} {} h = {h}: non-finite error",
                        entry.info().id,
                        m.label()
                    );
                    let rel = max / c.initial[i].abs().max(1.0);
                    if rel > err {
                        (err, worst) = (rel, *i);
                    }
                }
                let verdict = match &out.error {
                    Some(e) => {
                        let msg = e.to_string();
                        assert!(
                            msg.contains("step ") && msg.contains("t = "),
                            "untyped failure: {msg}"
                        );
                        Some(format!("h = {h:.3}: {msg}"))
                    }
                    None if err > BOUND => {
                        Some(format!("h = {h:.3}: ok but {worst} error {err:.2e} × max(1, |I(0)|)"))
                    }
                    None => None,
                };
                match verdict {
                    None if first_failure.is_none() => stable = Some(h),
                    Some(v) if first_failure.is_none() => first_failure = Some(v),
                    _ => {}
                }
            }
            println!(
                "| {} | {} | {} | {} |",
                entry.info().id,
                m.label(),
                stable.map_or("none ≥ 0.05".into(), |h| format!("{h:.3}")),
                first_failure.unwrap_or_else(|| "none up to h = 12.8".into())
            );
        }
    }
}
