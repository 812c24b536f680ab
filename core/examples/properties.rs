//! Prints every method's measured properties on every system's presets (SPARK with each of
//! its stage counts).
//! `cargo run --release -p nhlab-core --example properties`

use nhlab_core::{Method, MethodSpec, SYSTEMS, Scene, SceneRequest};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut methods: Vec<Method> =
        Method::all().into_iter().filter(|m| m.info().id != "spark").collect();
    for s in 2..=5 {
        methods.push(Method::from_spec(&MethodSpec::new("spark").with("stages", f64::from(s)))?);
    }
    println!(
        "| system/preset | method | reversible | fibration | defect | driver | fiber | constraint |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for entry in SYSTEMS {
        for preset in entry.info().presets {
            let req = SceneRequest {
                system: entry.info().id.into(),
                preset: Some(preset.id.into()),
                ..Default::default()
            };
            let scene = Scene::resolve(&req)?;
            for m in &methods {
                match scene.properties(m) {
                    Ok(p) => println!(
                        "| {}/{} | {} | {} | {} | {:.1e} | {:.1e} | {:.1e} | {:.1e} |",
                        entry.info().id,
                        preset.id,
                        m.label(),
                        p.reversible,
                        p.preserves_fibration,
                        p.reversibility_defect,
                        p.driver_coupling,
                        p.fiber_coupling,
                        p.constraint_defect
                    ),
                    Err(e) => println!(
                        "| {}/{} | {} | failed: {e} |",
                        entry.info().id,
                        preset.id,
                        m.label()
                    ),
                }
            }
        }
    }
    Ok(())
}
