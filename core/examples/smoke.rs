//! Prints the paper's figure set as a quick look (not a test).
use nhlab_core::{Collect, Method, RunConfig, Scene, SceneRequest, classify};

fn main() {
    for (system, preset) in [
        ("knife_edge", "paper"),
        ("knife_edge", "paper-perturbed"),
        ("cvt_pendulum", "oscillating"),
        ("cvt_pendulum", "rotating"),
        ("cvt_pendulum", "oscillating-perturbed"),
        ("cvt_pendulum", "rotating-perturbed"),
    ] {
        let req = SceneRequest {
            system: system.into(),
            preset: Some(preset.into()),
            ..Default::default()
        };
        let scene = Scene::resolve(&req).unwrap().prepare(None).unwrap();
        println!(
            "== {system} {preset} steps={} latitude={:?}",
            scene.scene.steps(),
            scene.latitude.map(|l| (l.period, l.axis))
        );
        for m in Method::paper_five() {
            let mut c = Collect::default();
            let t = std::time::Instant::now();
            let out = scene.run(&m, &RunConfig::default(), &mut c);
            let el = t.elapsed();
            let verdicts: Vec<String> = c
                .series
                .iter()
                .map(|(i, b)| {
                    let v = classify(b, 1.0);
                    format!("{i}:{}({:.1e},r={:.2})", v.kind.id(), v.max, v.ratio)
                })
                .collect();
            println!("  {:10} {:?} {:>8.2?} {}", m.label(), out.error, el, verdicts.join(" "));
        }
    }
}
