//! The compute alone of a `/simulate` request, for `bench/stream_overhead.py`: resolves and
//! prepares the scene (latitude axis included, as the server does), then runs the methods on
//! one thread each, all at once (as the server's blocking pool does), into an observer that
//! only counts the buckets. Prints one JSON line per repetition:
//! `{"prepare_ms", "wall_ms" (prepare + runs), "runs_ms" (each run's own time), "steps"}`.
//!
//! `cargo build --release -p nhlab-core --example compute_baseline &&
//!  target/release/examples/compute_baseline SYSTEM PRESET [T_END] [METHODS] [POINTS] [REPS]`
//!
//! METHODS: comma-separated ids, `dla@0.4` for DLA with α = 0.4, `paper` for the paper's five
//! (the default); T_END `-` for the preset's.

use nhlab_core::{Bucket, Integral, Method, MethodSpec, Observer, RunConfig, Scene, SceneRequest};
use std::hint::black_box;
use std::time::Instant;

struct Sink(u64);
impl Observer for Sink {
    fn points(&mut self, integral: Integral, bucket: Bucket) {
        self.0 += 1;
        black_box((integral, bucket));
    }
}

fn methods(arg: &str) -> Result<Vec<Method>, Box<dyn std::error::Error>> {
    if arg == "paper" {
        return Ok(Method::paper_five().to_vec());
    }
    arg.split(',')
        .map(|m| {
            let spec = match m.split_once('@') {
                Some((id, alpha)) => MethodSpec::new(id).with("alpha", alpha.parse()?),
                None => MethodSpec::new(m),
            };
            Ok(Method::from_spec(&spec)?)
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize| args.get(i).map(String::as_str).filter(|s| *s != "-");
    let (Some(system), Some(preset)) = (arg(0), arg(1)) else {
        return Err(
            "usage: compute_baseline SYSTEM PRESET [T_END] [METHODS] [POINTS] [REPS]".into()
        );
    };
    let t_end = arg(2).map(str::parse).transpose()?;
    let methods = methods(arg(3).unwrap_or("paper"))?;
    let points = arg(4).map(str::parse).transpose()?.unwrap_or(1000);
    let reps: u32 = arg(5).map(str::parse).transpose()?.unwrap_or(5);
    let cfg = RunConfig { points, ..RunConfig::default() };
    for _ in 0..reps {
        let start = Instant::now();
        let req = SceneRequest {
            system: system.into(),
            preset: Some(preset.into()),
            t_end,
            ..Default::default()
        };
        let scene = Scene::resolve(&req)?.prepare(None)?;
        let prepare_ms = start.elapsed().as_secs_f64() * 1e3;
        let runs: Vec<(f64, u64)> = std::thread::scope(|s| {
            let handles: Vec<_> = methods
                .iter()
                .map(|m| {
                    let scene = &scene;
                    s.spawn(move || {
                        let t = Instant::now();
                        let mut sink = Sink(0);
                        let steps = scene.run(m, &cfg, &mut sink).steps;
                        black_box(sink.0);
                        (t.elapsed().as_secs_f64() * 1e3, steps)
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().expect("a run panicked")).collect()
        });
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        let runs_ms: Vec<String> = runs.iter().map(|(ms, _)| format!("{ms:.3}")).collect();
        let steps: u64 = runs.iter().map(|(_, n)| n).sum();
        println!(
            "{{\"prepare_ms\": {prepare_ms:.3}, \"wall_ms\": {wall_ms:.3}, \"runs_ms\": [{}], \
             \"steps\": {steps}}}",
            runs_ms.join(", ")
        );
    }
    Ok(())
}
