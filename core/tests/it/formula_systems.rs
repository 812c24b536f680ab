//! Every built-in system written as formulas (`SystemInfo::formulas`, what `GET /systems`
//! lists) is the same system: each method's step from every state of 1,000 along the
//! built-in's trajectory lands where the built-in's does to 10⁻¹² (relative), on every
//! preset, compiled to machine code (with the `jit` feature) and interpreted alike; and on
//! the paper's six scenes every method's verdicts are the built-in's.

use crate::common::{case, preset_start, step_difference};
use nhlab_core::model::custom::Custom;
use nhlab_core::{
    BuiltIn, Collect, CustomLimits, CustomSystem, FormulaSpec, Integral, Method, PAPER_SCENES,
    RunConfig, SYSTEMS, Scene, SceneRequest, SystemRequest, classify,
};

const STEPS: usize = 1000;
const TOL: f64 = 1e-12;

fn same_steps<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    let info = S::info();
    for (index, preset) in info.presets.iter().enumerate() {
        let (sys, start, h) = preset_start::<S, N, R>(index);
        let overrides: Vec<(String, f64)> =
            preset.params.iter().map(|(n, v)| (n.to_string(), *v)).collect();
        let spec = FormulaSpec::of(info).expect("a class built-in");
        // Without machine code both would be the interpreter: it runs once.
        let natives: &[bool] =
            if crate::common::machine_code() { &[true, false] } else { &[false] };
        for &native in natives {
            let limits = CustomLimits { native, ..CustomLimits::default() };
            let compiled = CustomSystem::compile(&spec, &overrides, &limits)
                .unwrap_or_else(|e| panic!("{}: {e}", info.id));
            assert_eq!(compiled.class_compiled().unwrap().driver.is_native(), native);
            let formulas = Custom::<N, R>::new(compiled.class_compiled().unwrap().clone());
            for m in Method::all() {
                let name = case::<S, N, R>(index, &format!("{} (native: {native})", m.label()));
                let (mut st, mut memory) = (start, m.memory());
                let mut worst: f64 = 0.0;
                for k in 0..STEPS {
                    let ((mut a, mut a_mem), (mut b, mut b_mem)) = ((st, memory), (st, memory));
                    match (
                        m.step(&formulas, &mut a, &mut a_mem, h),
                        m.step(&sys, &mut b, &mut b_mem, h),
                    ) {
                        (Ok(()), Ok(())) => {}
                        (Err(x), Err(y)) if x == y && k > 0 => break,
                        (x, y) => panic!("{name} step {k}: formulas {x:?}, built-in {y:?}"),
                    }
                    let rel = step_difference(&a, &b);
                    worst = worst.max(rel);
                    assert!(rel <= TOL, "{name} step {k}: formulas and built-in differ by {rel:e}");
                    (st, memory) = (b, b_mem);
                }
                println!("{name}: worst {worst:.1e}");
            }
        }
    }
}

#[test]
fn built_ins_as_formulas_take_the_built_ins_steps() {
    for_each_system!(same_steps);
}

/// The verdicts of every method on one scene, by integral.
fn verdicts(req: &SceneRequest) -> Vec<(String, Integral, String)> {
    let scene = Scene::resolve(req).unwrap().prepare(None).unwrap();
    let mut out = Vec::new();
    for m in Method::all() {
        let mut c = Collect::default();
        scene.run(&m, &RunConfig::default(), &mut c);
        for (integral, buckets) in &c.series {
            let scale = c.initial.get(integral).copied().unwrap_or(0.0);
            let kind = format!("{:?}", classify(buckets, scale).kind);
            out.push((m.label(), *integral, kind));
        }
    }
    out
}

#[test]
fn built_ins_as_formulas_get_the_built_ins_verdicts_on_the_paper_scenes() {
    for (system, preset) in PAPER_SCENES {
        let built_in = SceneRequest {
            system: system.into(),
            preset: Some(preset.into()),
            ..Default::default()
        };
        let resolved = Scene::resolve(&built_in).unwrap();
        let entry = SYSTEMS.iter().find(|s| s.info().id == system).unwrap();
        let as_formulas = SceneRequest {
            system: SystemRequest::Formulas(
                FormulaSpec::of(entry.info()).expect("a class built-in"),
            ),
            params: resolved.named_params().into_iter().map(|(n, v)| (n.to_string(), v)).collect(),
            q: Some(resolved.q.clone()),
            v: Some(resolved.v.clone()),
            step: Some(resolved.step),
            t_end: Some(resolved.t_end),
            ..Default::default()
        };
        assert_eq!(verdicts(&as_formulas), verdicts(&built_in), "{system}/{preset}");
    }
}
