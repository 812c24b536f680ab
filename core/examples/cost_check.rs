//! The cost model ([`nhlab_core::catalogue::cost`]) against what runs cost: for every method
//! (and DLA∘p8s15, and `prk` with four stored tableaux) on every built-in's first preset and on heavy systems given as formulas
//! (a smooth U of ~1,800 characters in the paper's form, with its formulas as machine code
//! and interpreted, and the same V in the general form), the measured ns per step (a run's
//! CPU time over its steps, sub-steps counted: its thread's time on a core, from
//! /proc/thread-self/schedstat, so that a loaded machine measures the same) beside the
//! estimate. Prints one line per cell
//! and, last, the smallest estimate/measured ratio: below 1, the model is not conservative
//! there.
//!
//! `cargo run --release -p nhlab-core --example cost_check [SECONDS_PER_CELL]`
//!
//! `… cost_check overhead`: what pacing a run by the clock costs a built-in's step (the
//! server's runs are paced, the benchmarks' are not): 10⁷ steps of leap-frog and DLA^0.5 on
//! the knife edge, progress every 1024 steps, paced or not, interleaved, best of 7 rounds.

use nhlab_core::catalogue::cost::run_cost;
use nhlab_core::{
    Bucket, CustomLimits, FormulaSpec, GeneralSpec, Integral, Method, MethodSpec, Observer,
    RunConfig, SYSTEMS, Scene, SceneRequest, SystemRequest,
};

/// The calling thread's time on a core so far, in seconds (Linux).
fn cpu_seconds() -> f64 {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").unwrap_or_default();
    let ns: f64 = text.split_whitespace().next().and_then(|x| x.parse().ok()).unwrap_or(f64::NAN);
    ns * 1e-9
}

struct Sink;
impl Observer for Sink {
    fn points(&mut self, _: Integral, _: Bucket) {}
}

/// A smooth U of about `chars` characters in x and y: a bowl with bumps.
pub fn heavy_u(chars: usize) -> String {
    let mut u = "0.5*(x^2 + y^2)".to_owned();
    let mut k = 0;
    while u.len() < chars {
        let (a, b, c) = (0.001 * (1 + k % 7) as f64, 1 + k % 5, 0.1 * (k % 9) as f64);
        u += &match k % 3 {
            0 => format!(" + {a}*cos({b}*x - {c}*y)"),
            1 => format!(" + {a}*x^2*y^2/(1 + {b}*x^2 + y^2)"),
            _ => format!(" + {a}*exp(-{b}*(x - {c})^2 - y^2)"),
        };
        k += 1;
    }
    u
}

fn methods() -> Vec<Method> {
    let mut specs: Vec<MethodSpec> =
        ["dla", "dla01", "leapfrog", "dd", "dd_avf", "rk4", "rattle"].map(MethodSpec::new).into();
    specs.push(MethodSpec::new("dla").composed("p8s15"));
    specs.extend((2..=5).map(|s| MethodSpec::new("spark").with("stages", f64::from(s))));
    // Methods given as tableaux: the dense solve grows with the stages.
    for (tableau, constraint) in
        [("gauss1", "stage"), ("gauss3", "stage"), ("lobatto5", "stage"), ("gauss2", "midpoint")]
    {
        specs.push(MethodSpec {
            tableau: Some(nhlab_core::methods::TableauChoice::Stored(tableau.into())),
            constraint: Some(constraint.into()),
            ..MethodSpec::new("prk")
        });
    }
    specs.iter().map(|s| Method::from_spec(s).expect("a valid method")).collect()
}

fn scenes() -> Vec<(String, Scene)> {
    let mut out = Vec::new();
    for entry in SYSTEMS.iter() {
        let info = entry.info();
        let req = SceneRequest {
            system: info.id.into(),
            preset: Some(info.presets[0].id.into()),
            t_end: Some(1e6),
            ..Default::default()
        };
        if let Ok(scene) = Scene::resolve(&req) {
            out.push((info.id.to_owned(), scene));
        }
    }
    let u = heavy_u(1800);
    for native in [true, false] {
        let spec = FormulaSpec {
            name: "heavy bowl".into(),
            passenger: vec!["x".into(), "y".into()],
            driver: "theta".into(),
            parameters: vec![("eps".into(), 0.1)],
            passenger_potential: u.clone(),
            driver_potential: "0".into(),
            constraints: vec![vec!["-sin(theta)".into(), "cos(theta) - eps".into()]],
        };
        let limits = CustomLimits { native, ..Default::default() };
        let req = |system| SceneRequest {
            system,
            q: Some(vec![0.3, 0.2, 1.0]),
            v: Some(vec![0.0, 0.0, 1.0]),
            step: Some(0.01),
            t_end: Some(1e6),
            ..Default::default()
        };
        let name = if native { "formulas (jit)" } else { "formulas (tape)" };
        let scene = Scene::resolve_within(&req(SystemRequest::Formulas(spec)), &limits);
        out.push((name.into(), scene.expect("the heavy bowl resolves")));
        let mut general = GeneralSpec::of(
            "heavy bowl, general",
            &["x", "y", "theta"],
            (&["eps"], &[0.1]),
            &u,
            &[&["-sin(theta)", "cos(theta) - eps", "0"]],
        );
        general.detect_class = false;
        let name = if native { "general (jit)" } else { "general (tape)" };
        let scene = Scene::resolve_within(&req(SystemRequest::General(general)), &limits);
        out.push((name.into(), scene.expect("the general heavy bowl resolves")));
    }
    out
}

/// ns per step of `m` on the knife edge, paced or not: best of `rounds`.
fn overhead() -> Result<(), Box<dyn std::error::Error>> {
    let req = SceneRequest {
        system: "knife_edge".into(),
        step: Some(1e-3),
        t_end: Some(1e4),
        ..Default::default()
    };
    let prepared = Scene::resolve(&req)?.prepare(None)?;
    for id in ["leapfrog", "dla"] {
        let m = Method::from_spec(&MethodSpec::new(id))?;
        let mut best = [f64::INFINITY; 2];
        for _ in 0..7 {
            for (i, paced) in [false, true].into_iter().enumerate() {
                let cfg = RunConfig {
                    points: 1000,
                    progress_every: 1024,
                    paced,
                    time_limit: None,
                    ..RunConfig::default()
                };
                let start = cpu_seconds();
                let out = prepared.run(&m, &cfg, &mut Sink);
                best[i] = best[i].min((cpu_seconds() - start) * 1e9 / out.steps as f64);
            }
        }
        let [plain, paced] = best;
        println!(
            "{id}: {plain:.2} ns/step every 1024 steps, {paced:.2} paced ({:+.2} %)",
            (paced / plain - 1.0) * 100.0
        );
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    if std::env::args().nth(1).as_deref() == Some("overhead") {
        return overhead();
    }
    let seconds: f64 = std::env::args().nth(1).map(|s| s.parse()).transpose()?.unwrap_or(0.2);
    let mut worst = (f64::INFINITY, String::new());
    println!(
        "{:<22} {:<14} {:>12} {:>12} {:>7}",
        "system", "method", "measured ns", "estimate", "ratio"
    );
    for (name, scene) in scenes() {
        let prepared = scene.clone().prepare(None)?;
        for m in methods() {
            if prepared.check_method(&m).is_err() {
                continue;
            }
            let cfg = RunConfig {
                points: 10,
                paced: true,
                time_limit: Some(std::time::Duration::from_secs_f64(seconds)),
                ..RunConfig::default()
            };
            let start = cpu_seconds();
            let out = prepared.run(&m, &cfg, &mut Sink);
            let elapsed = cpu_seconds() - start;
            let sub_steps = out.steps as f64 * m.stages() as f64;
            if sub_steps < 10.0 {
                println!("{name:<22} {:<14} too few steps: {:?}", m.label(), out.error);
                continue;
            }
            let measured = elapsed * 1e9 / sub_steps;
            let estimate = run_cost(&scene, &m).ns_per_step;
            let ratio = estimate / measured;
            println!("{name:<22} {:<14} {measured:>12.0} {estimate:>12.0} {ratio:>7.2}", m.label());
            if ratio < worst.0 {
                worst = (ratio, format!("{name} {}", m.label()));
            }
        }
    }
    println!("smallest estimate/measured: {:.2} ({})", worst.0, worst.1);
    Ok(())
}
