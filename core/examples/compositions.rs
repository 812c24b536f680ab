//! The measurements of `docs/high-order.md`.
//!
//! - `wp`: work–precision CSV (the columns of the `work_precision` example) of RK4, LF, DD and
//!   every symmetric method in every composition, on the knife edge (paper, to t = 100) and the
//!   rotating perturbed CVT (to t = 3000), steps divided by √2 from the scene's own. A method's
//!   ladder stops once its error reaches 1e-11 (round-off) or a run takes over 2 s; runs over
//!   0.3 s are timed once, the others the minimum of 3.
//! - `verdicts`: every composed method on the paper's six scenes to t = 30,000, with the
//!   verdict of each integral (run on every core; not timed).
//! - `cost`: what a composed step costs against its stages times the base step at the same h,
//!   on the knife edge and the rotating perturbed CVT: base and composed runs interleaved, 9
//!   rounds, the fastest of each (so both see the same noise).
//!
//!
//! `wp spark` and `verdicts spark` do the same for the SPARK methods (s = 2 … 5): the verdicts
//! on the paper's six scenes; work–precision of RK4, the SPARKs and every composition that
//! applies, on the same two scenes and the inclined Chaplygin sleigh (to t = 100).
//! `verdicts prk` takes methods given as stored tableaux ([`tableaux`]) to the same six scenes.
//!
//! ```text
//! cargo run --release -p nhlab-core --example compositions -- wp > target/wp_compositions.csv
//! cargo run --release -p nhlab-core --example compositions -- verdicts
//! cargo run --release -p nhlab-core --example compositions -- cost
//! cargo run --release -p nhlab-core --example compositions -- wp spark > target/wp_spark.csv
//! cargo run --release -p nhlab-core --example compositions -- verdicts spark
//! cargo run --release -p nhlab-core --example compositions -- verdicts prk
//! ```

use nhlab_core::catalogue::work_precision::{measure, reference};
use nhlab_core::systems::{CvtPendulum, KnifeEdge};
use nhlab_core::{
    BuiltIn, Collect, Composition, Method, MethodSpec, RunConfig, Scene, SceneRequest, State,
    System, Vector, classify,
};
use std::hint::black_box;
use std::sync::Mutex;
use std::time::Instant;

fn scene(system: &str, preset: &str) -> Result<Scene, Box<dyn std::error::Error>> {
    let req =
        SceneRequest { system: system.into(), preset: Some(preset.into()), ..Default::default() };
    Ok(Scene::resolve(&req)?)
}

/// Every symmetric method of the list in every composition.
fn composed() -> Vec<Method> {
    let symmetric = Method::all().into_iter().filter(|m| m.base.symmetric());
    symmetric
        .flat_map(|m| Composition::ALL.map(move |c| m.composed(c).expect("symmetric")))
        .collect()
}

/// Methods given as stored tableaux: Gauss and Radau IIA with stage conditions (order 2s and
/// 2s − 1, not symmetric), Gauss2 with one multiplier at the end and at the midpoint (order 2,
/// symmetric).
fn tableaux() -> Vec<Method> {
    let prk = |tableau: &str, constraint: &str| {
        let spec = MethodSpec {
            tableau: Some(nhlab_core::methods::TableauChoice::Stored(tableau.into())),
            constraint: Some(constraint.into()),
            ..MethodSpec::new("prk")
        };
        Method::from_spec(&spec).expect("a stored tableau")
    };
    let stage = ["gauss1", "gauss2", "gauss3", "radau2", "radau3"].map(|t| prk(t, "stage"));
    stage.into_iter().chain([prk("gauss2", "end"), prk("gauss2", "midpoint")]).collect()
}

/// The SPARK methods, s = 2 … 5.
fn sparks() -> Vec<Method> {
    (2..=5)
        .map(|s| Method::from_spec(&MethodSpec::new("spark").with("stages", f64::from(s))))
        .collect::<Result<_, _>>()
        .expect("s = 2 … 5")
}

fn work_precision(spark: bool) -> Result<(), Box<dyn std::error::Error>> {
    println!("scene,method,step,steps,elapsed_ms,final_error");
    let spec = |id: &str| Method::from_spec(&MethodSpec::new(id));
    let mut methods = vec![spec("rk4")?];
    if spark {
        methods.extend(sparks());
    } else {
        methods.extend([spec("leapfrog")?, spec("dd")?]);
    }
    // Beside the SPARKs, the compositions of the methods that reach every order in q and q̇
    // (`docs/high-order.md`): LF's stop at 4, DD's at 2 in q̇.
    let reaches = |m: &Method| ["dla", "dla01", "rattle"].contains(&m.info().id);
    methods.extend(composed().into_iter().filter(|m| !spark || reaches(m)));
    let mut scenes =
        vec![("knife_edge", "paper", 0.4), ("cvt_pendulum", "rotating-perturbed", 0.2)];
    if spark {
        scenes.push(("chaplygin_sleigh", "inclined", 0.4));
    }
    for (system, preset, h0) in scenes {
        let prepared = scene(system, preset)?.prepare(Some(&["energy".into()]))?;
        let r = reference(&prepared)?;
        for m in methods.iter().filter(|m| prepared.check_method(m).is_ok()) {
            let mut elapsed = 0.0;
            for k in 0.. {
                let h = h0 / 2f64.powf(0.5 * k as f64);
                let reps = if elapsed > 300.0 { 1 } else { 3 };
                let row = measure(&prepared, &r.state, m, h, reps);
                elapsed = row.elapsed_ms;
                let error = row.final_error.map_or("failed".into(), |e| format!("{e:.3e}"));
                println!(
                    "{system}/{preset},\"{}\",{},{},{:.4},{error}",
                    m.label(),
                    row.step,
                    row.steps,
                    row.elapsed_ms
                );
                if row.final_error.is_some_and(|e| e < 1e-11) || elapsed > 2000.0 || k >= 40 {
                    break;
                }
            }
        }
    }
    Ok(())
}

fn verdicts(which: &str) -> Result<(), Box<dyn std::error::Error>> {
    println!("| scene | method | integral | verdict | max | early max | late mean | ratio |");
    println!("|---|---|---|---|---|---|---|---|");
    for (system, preset) in nhlab_core::PAPER_SCENES {
        let mut s = scene(system, preset)?;
        s.t_end = 30_000.0;
        let prepared = s.prepare(None)?;
        let methods = match which {
            "spark" => sparks(),
            "prk" => tableaux(),
            _ => composed(),
        };
        let lines = Mutex::new(vec![Vec::new(); methods.len()]);
        let next = Mutex::new(0);
        std::thread::scope(|scope| {
            for _ in 0..std::thread::available_parallelism().map_or(1, |n| n.get()) {
                scope.spawn(|| {
                    loop {
                        let i = {
                            let mut n = next.lock().unwrap();
                            *n += 1;
                            *n - 1
                        };
                        let Some(m) = methods.get(i) else { break };
                        let mut c = Collect::default();
                        let out = prepared.run(m, &RunConfig::default(), &mut c);
                        let mut rows = Vec::new();
                        if let Some(e) = out.error {
                            rows.push(format!("| {preset} | {} | – | failed: {e} | | | | |", m.label()));
                        }
                        for (integral, buckets) in &c.series {
                            let v = classify(buckets, c.initial[integral]);
                            rows.push(format!(
                                "| {preset} | {} | {integral} | {} | {:.2e} | {:.2e} | {:.2e} | {:.2} |",
                                m.label(),
                                v.kind.id(),
                                v.max,
                                v.early,
                                v.late,
                                v.ratio
                            ));
                        }
                        lines.lock().unwrap()[i] = rows;
                    }
                });
            }
        });
        for rows in lines.into_inner().unwrap() {
            for row in rows {
                println!("{row}");
            }
        }
    }
    Ok(())
}

/// Seconds for `n` steps of `m` from the scene's start, nothing measured.
fn timed<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    start: &State<N, R>,
    m: &Method,
    h: f64,
    n: u64,
) -> f64 {
    let mut st = *start;
    let t = Instant::now();
    m.steps(sys, &mut st, black_box(h), n).expect("the scene runs");
    black_box(st);
    t.elapsed().as_secs_f64()
}

fn cost_on<S: BuiltIn<N, R>, const N: usize, const R: usize>(preset: &str) {
    let info = S::info();
    let p = info.presets.iter().find(|p| p.id == preset).expect("the preset exists");
    let sys = S::new(&info.preset_params(p));
    let (q, v) = (Vector::<N>::from_column_slice(p.q), Vector::<N>::from_column_slice(p.v));
    let start = State::with_continuous_multiplier(&sys, q, v).expect("a preset is regular");
    const SUB_STEPS: u64 = 150_000;
    for base in Method::all().into_iter().filter(|m| m.base.symmetric()) {
        for c in Composition::ALL {
            let m = base.composed(c).expect("symmetric");
            let n = SUB_STEPS / c.stages() as u64;
            let (mut plain, mut composed) = (f64::INFINITY, f64::INFINITY);
            for _ in 0..9 {
                plain = plain.min(timed(&sys, &start, &base, p.step, n * c.stages() as u64));
                composed = composed.min(timed(&sys, &start, &m, p.step, n));
            }
            let per_base = plain / (n * c.stages() as u64) as f64 * 1e9;
            let per_composed = composed / n as f64 * 1e9;
            println!(
                "| {}/{preset} | {} | {per_base:.0} | {per_composed:.0} | {:.2} |",
                info.id,
                m.label(),
                per_composed / (c.stages() as f64 * per_base)
            );
        }
    }
}

fn cost() -> Result<(), Box<dyn std::error::Error>> {
    println!("| scene | method | base ns/step | composed ns/step | composed / (stages × base) |");
    println!("|---|---|---|---|---|");
    cost_on::<KnifeEdge, 3, 1>("paper");
    cost_on::<CvtPendulum, 3, 1>("rotating-perturbed");
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let which = std::env::args().nth(2).unwrap_or_default();
    let spark = which == "spark";
    match std::env::args().nth(1).as_deref() {
        Some("wp") => work_precision(spark),
        Some("verdicts") => verdicts(&which),
        Some("cost") => cost(),
        _ => Err("usage: compositions wp [spark] | verdicts [spark|prk] | cost".into()),
    }
}
