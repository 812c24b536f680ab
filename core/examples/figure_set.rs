//! Runs the paper's whole figure set (knife edge ε ∈ {0, 0.1} to t = 100 with h = π/10, the
//! four CVT scenes to t = 3000 with h = 0.1; five methods each; all integrals, latitude axis
//! included; 1000 points) `REPS` times on one thread and prints the time per figure set.
//! `cargo build --release -p nhlab-core --example figure_set &&
//!  /usr/bin/time -f 'user %U s' target/release/examples/figure_set`
//! (user CPU time is robust when the machine is shared; wall time is printed too).

use nhlab_core::{Bucket, Integral, Method, Observer, RunConfig, Scene, SceneRequest};
use std::hint::black_box;

const REPS: u32 = 20;

struct Sink(u64);
impl Observer for Sink {
    fn points(&mut self, integral: Integral, bucket: Bucket) {
        self.0 += 1;
        black_box((integral, bucket));
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let t = std::time::Instant::now();
    let (mut steps, mut buckets) = (0, 0);
    // Where the time goes: preparing the scenes (latitude axes), then each method.
    let mut prepare = std::time::Duration::ZERO;
    let mut per_method = vec![std::time::Duration::ZERO; Method::paper_five().len()];
    for _ in 0..REPS {
        for (system, preset) in nhlab_core::PAPER_SCENES {
            let req = SceneRequest {
                system: system.into(),
                preset: Some(preset.into()),
                ..Default::default()
            };
            let t_prepare = std::time::Instant::now();
            let scene = Scene::resolve(&req)?.prepare(None)?;
            prepare += t_prepare.elapsed();
            for (i, m) in Method::paper_five().iter().enumerate() {
                let mut sink = Sink(0);
                let t_run = std::time::Instant::now();
                steps += scene.run(m, &RunConfig::default(), &mut sink).steps;
                per_method[i] += t_run.elapsed();
                buckets += sink.0;
            }
        }
    }
    let per = t.elapsed() / REPS;
    println!(
        "figure set: {} steps, {} buckets, {per:.1?} wall per set",
        steps / REPS as u64,
        buckets / REPS as u64
    );
    print!("  prepare {:.1?}", prepare / REPS);
    for (m, d) in Method::paper_five().iter().zip(&per_method) {
        print!(", {} {:.1?}", m.label(), *d / REPS);
    }
    println!();
    Ok(())
}
