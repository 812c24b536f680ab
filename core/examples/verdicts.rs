//! Prints the paper's table as nhlab measures it: every paper scene × method × integral
//! with its verdict and the numbers behind it. `cargo run --release -p nhlab-core --example verdicts`

use nhlab_core::{Collect, Method, RunConfig, Scene, SceneRequest, classify};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("| scene | method | integral | verdict | max | early max | late mean | ratio |");
    println!("|---|---|---|---|---|---|---|---|");
    for (system, preset) in nhlab_core::PAPER_SCENES {
        let req = SceneRequest {
            system: system.into(),
            preset: Some(preset.into()),
            ..Default::default()
        };
        let scene = Scene::resolve(&req)?.prepare(None)?;
        for m in Method::all() {
            let mut c = Collect::default();
            scene.run(&m, &RunConfig::default(), &mut c);
            for (integral, buckets) in &c.series {
                let v = classify(buckets, c.initial[integral]);
                println!(
                    "| {preset} | {} | {integral} | {} | {:.2e} | {:.2e} | {:.2e} | {:.2} |",
                    m.label(),
                    v.kind.id(),
                    v.max,
                    v.early,
                    v.late,
                    v.ratio
                );
            }
        }
    }
    Ok(())
}
