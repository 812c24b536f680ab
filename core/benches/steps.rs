//! ns/step for every method × system, and the paper's whole figure set on one core.
//! `cargo bench -p nhlab-core`; numbers go to `docs/performance.md`.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use nhlab_core::BuiltIn;
use nhlab_core::{Method, Observer, RunConfig, Scene, SceneRequest, State, Vector};
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

/// Knife edge ε ∈ {0, 0.1} to t = 100 and the four CVT scenes to t = 3000, five methods
/// each, all integrals (latitude axis included), 1000 points: about 620,000 steps.
fn figure_set(c: &mut Criterion) {
    let scenes = nhlab_core::PAPER_SCENES;
    let mut group = c.benchmark_group("figure_set");
    group.sample_size(10);
    group.bench_function("paper_six_scenes_five_methods", |b| {
        b.iter(|| {
            for (system, preset) in scenes {
                let req = SceneRequest {
                    system: system.into(),
                    preset: Some(preset.into()),
                    ..Default::default()
                };
                let scene = Scene::resolve(&req).expect("preset").prepare(None).expect("ok");
                for m in Method::paper_five() {
                    black_box(scene.run(&m, &RunConfig::default(), &mut Sink));
                }
            }
        })
    });
    group.finish();
}

fn steps(c: &mut Criterion) {
    nhlab_core::for_each_system!(bench_system, c);
}

criterion_group!(benches, steps, figure_set);
criterion_main!(benches);
