//! ns/step for every method × system, `cvt_pendulum` given as formulas beside the built-in,
//! and the paper's whole figure set on one core, built in and as formulas.
//! `cargo bench -p nhlab-core`; numbers go to `docs/performance.md`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use nhlab_core::BuiltIn;
use nhlab_core::model::custom::Custom;
use nhlab_core::systems::CvtPendulum;
use nhlab_core::{
    CustomLimits, CustomSystem, FormulaSpec, Method, Observer, RunConfig, Scene, SceneRequest,
    State, SystemRequest, Vector,
};
use std::hint::black_box;

const STEPS: u64 = 10_000;

/// Every registered method: the paper's five first (implicit ones on their fast paths),
/// then the others (DD-AVF, RK4), then the implicit ones on their general Newton paths, so
/// that one run gives the fast/general ratio.
fn methods() -> Vec<(String, Method)> {
    let mut out: Vec<(String, Method)> =
        Method::all().into_iter().map(|m| (m.label(), m)).collect();
    let general: Vec<_> = out
        .iter()
        .filter_map(|(label, m)| Some((format!("{label} general"), m.general_path()?)))
        .collect();
    out.extend(general);
    out
}

fn bench_system<S: BuiltIn<N, R>, const N: usize, const R: usize>(c: &mut Criterion) {
    let info = S::info();
    let p = &info.presets[0];
    let sys = S::new(&info.preset_params(p));
    let start = State::with_continuous_multiplier(
        &sys,
        Vector::<N>::from_column_slice(p.q),
        Vector::<N>::from_column_slice(p.v),
    )
    .expect("preset is regular");
    let mut group = c.benchmark_group(format!("step/{}", info.id));
    group.throughput(Throughput::Elements(STEPS));
    for (label, m) in methods() {
        group.bench_function(BenchmarkId::from_parameter(label), |b| {
            b.iter(|| {
                let mut st = start;
                m.steps(&sys, &mut st, black_box(p.step), STEPS).expect("steps");
                black_box(st)
            })
        });
    }
    group.finish();
}

struct Sink;
impl Observer for Sink {
    fn points(&mut self, integral: nhlab_core::Integral, bucket: nhlab_core::Bucket) {
        black_box((integral, bucket));
    }
}

/// `cvt_pendulum` (rotating, ε = 0.5) built in and given as formulas, each method's steps
/// side by side: what compiled formulas cost.
fn formulas(c: &mut Criterion) {
    let info = CvtPendulum::info();
    let p = &info.presets[3];
    let sys = CvtPendulum::new(&info.preset_params(p));
    let overrides: Vec<(String, f64)> = p.params.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    let compiled = CustomSystem::compile(
        &FormulaSpec::of(info).expect("a class built-in"),
        &overrides,
        &CustomLimits::default(),
    )
    .expect("the formula form compiles");
    let formulas = Custom::<3, 1>::new(compiled.class_compiled().expect("the class").clone());
    let (q, v) = (Vector::<3>::from_column_slice(p.q), Vector::<3>::from_column_slice(p.v));
    let start = State::with_continuous_multiplier(&sys, q, v).expect("preset is regular");
    let mut group = c.benchmark_group("formulas/cvt_pendulum");
    group.throughput(Throughput::Elements(STEPS));
    for m in Method::all() {
        let label = m.label();
        group.bench_function(BenchmarkId::from_parameter(format!("{label} built-in")), |b| {
            b.iter(|| {
                let mut st = start;
                m.steps(&sys, &mut st, black_box(p.step), STEPS).expect("steps");
                black_box(st)
            })
        });
        group.bench_function(BenchmarkId::from_parameter(format!("{label} formulas")), |b| {
            b.iter(|| {
                let mut st = start;
                m.steps(&formulas, &mut st, black_box(p.step), STEPS).expect("steps");
                black_box(st)
            })
        });
    }
    group.finish();
}

/// The scene requests of the figure set: built in, or with each system given as formulas
/// (the preset's parameters and state written out).
fn figure_set_requests(as_formulas: bool) -> Vec<SceneRequest> {
    nhlab_core::PAPER_SCENES
        .iter()
        .map(|(system, preset)| {
            let req = SceneRequest {
                system: (*system).into(),
                preset: Some((*preset).into()),
                ..Default::default()
            };
            if !as_formulas {
                return req;
            }
            let scene = Scene::resolve(&req).expect("preset");
            let info = scene.system.built_in().expect("a built-in").info();
            SceneRequest {
                system: SystemRequest::Formulas(FormulaSpec::of(info).expect("a class built-in")),
                params: scene.named_params().iter().map(|(n, v)| (n.to_string(), *v)).collect(),
                q: Some(scene.q.clone()),
                v: Some(scene.v.clone()),
                step: Some(scene.step),
                t_end: Some(scene.t_end),
                ..Default::default()
            }
        })
        .collect()
}

/// Knife edge ε ∈ {0, 0.1} to t = 100 and the four CVT scenes to t = 3000, five methods
/// each, all integrals (latitude axis included), 1000 points: about 620,000 steps.
/// The same with every system given as formulas (compiled per scene, inside the timing).
fn figure_set(c: &mut Criterion) {
    let mut group = c.benchmark_group("figure_set");
    group.sample_size(10);
    for (name, as_formulas) in [("paper_six_scenes_five_methods", false), ("as_formulas", true)] {
        let requests = figure_set_requests(as_formulas);
        group.bench_function(name, |b| {
            b.iter(|| {
                for req in &requests {
                    let scene = Scene::resolve(req).expect("scene").prepare(None).expect("ok");
                    for m in Method::paper_five() {
                        black_box(scene.run(&m, &RunConfig::default(), &mut Sink));
                    }
                }
            })
        });
    }
    group.finish();
}

fn steps(c: &mut Criterion) {
    nhlab_core::for_each_system!(bench_system, c);
}

criterion_group!(benches, steps, formulas, figure_set);
criterion_main!(benches);
