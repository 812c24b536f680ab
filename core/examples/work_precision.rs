//! Work–precision table of every method on the two scenes of `docs/performance.md`: the knife
//! edge (paper, to t = 100) and the rotating CVT with ε = 0.5 (to t = 3000), steps divided
//! by √2 from the scene's own (a ladder as fine as SciPy's half-decade tolerances in
//! bench/scipy_dop853.py, so that neither side's grid decides an error level). Prints CSV (labels quoted: `DLA^{0,1}` has a comma):
//! scene,method,step,steps,elapsed_ms,final_error.
//! `cargo run --release -p nhlab-core --example work_precision > target/wp_nhlab.csv`

use nhlab_core::catalogue::work_precision::{measure, reference};
use nhlab_core::{Method, Scene, SceneRequest};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("scene,method,step,steps,elapsed_ms,final_error");
    let scenes =
        [("knife_edge", "paper", 0.4, 19), ("cvt_pendulum", "rotating-perturbed", 0.2, 19)];
    for (system, preset, h0, levels) in scenes {
        let req = SceneRequest {
            system: system.into(),
            preset: Some(preset.into()),
            ..Default::default()
        };
        let scene = Scene::resolve(&req)?.prepare(Some(&["energy".into()]))?;
        let r = reference(&scene)?;
        eprintln!(
            "{system}/{preset}: reference {:.1} ms, {} evaluations, constraint residual {:.1e}, \
             y = {:?}",
            r.elapsed_ms,
            r.state.evaluations,
            r.state.constraint_residual,
            [r.state.q.as_slice(), r.state.v.as_slice()].concat()
        );
        let methods = Method::all();
        for m in &methods {
            for k in 0..levels {
                let h = h0 / 2f64.powf(0.5 * k as f64);
                let row = measure(&scene, &r.state, m, h, 5);
                println!(
                    "{system}/{preset},\"{}\",{},{},{:.4},{}",
                    m.label(),
                    row.step,
                    row.steps,
                    row.elapsed_ms,
                    row.final_error.map_or("failed".into(), |e| format!("{e:.3e}"))
                );
            }
        }
    }
    Ok(())
}
