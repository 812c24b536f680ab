//! Measured method properties, and the new methods' guarantees. The paper's table
//! "Preserves fibration / Preserves reversibility" is reproduced on the CVT with pendulum
//! driver: DD reversible but not fibration-preserving, DLA^0.4 not reversible, the other
//! three both. RK4 must be caught leaving the constraint manifold.

use crate::common::preset_start;
use nhlab_core::BuiltIn;
use nhlab_core::{
    Collect, Method, MethodSpec, RunConfig, SYSTEMS, Scene, SceneRequest, method_infos,
};

fn method(id: &str) -> Method {
    Method::from_spec(&MethodSpec::new(id)).unwrap()
}

#[test]
fn paper_property_table_on_the_cvt() {
    let five = Method::paper_five();
    // (reversible, preserves fibration) for DLA^0.5, DLA^0.4, DLA^{0,1}, LF, DD.
    let expected = [(true, true), (false, true), (true, true), (true, true), (true, false)];
    for preset in ["oscillating", "rotating", "oscillating-perturbed", "rotating-perturbed"] {
        let req = SceneRequest {
            system: "cvt_pendulum".into(),
            preset: Some(preset.into()),
            ..Default::default()
        };
        let scene = Scene::resolve(&req).unwrap();
        for (m, (rev, fib)) in five.iter().zip(expected) {
            let p = scene.properties(m).unwrap();
            assert_eq!(
                (p.reversible, p.preserves_fibration),
                (rev, fib),
                "{preset} {}: {p:?}",
                m.label()
            );
        }
        let p = scene.properties(&method("rk4")).unwrap();
        assert!(!p.preserves_fibration && p.constraint_defect > 1e-8, "RK4 {preset}: {p:?}");
        let p = scene.properties(&method("dd_avf")).unwrap();
        assert!(p.reversible && p.preserves_fibration, "DD-AVF {preset}: {p:?}");
    }
}

#[test]
fn every_method_runs_on_every_system() {
    for entry in SYSTEMS {
        let req = SceneRequest { system: entry.info().id.into(), ..Default::default() };
        let scene = Scene::resolve(&req).unwrap().prepare(None).unwrap();
        for info in method_infos().into_iter().filter(|info| !info.external) {
            let m = method(info.id);
            if let Err(e) = scene.check_method(&m) {
                // Refused before it runs, only where the method has no step for the system.
                assert!(info.class_only.is_some() && !scene.scene.system.in_paper_class(), "{e}");
                continue;
            }
            let mut c = Collect::default();
            let out = scene.run(&m, &RunConfig { points: 50, ..Default::default() }, &mut c);
            assert_eq!(out.error, None, "{} {}", entry.info().id, info.id);
            assert_eq!(out.steps, scene.scene.steps());
            for (i, s) in &c.series {
                assert!(
                    s.iter().all(|b| b.mean.is_finite()),
                    "{} {} {i}",
                    entry.info().id,
                    info.id
                );
            }
        }
    }
}

fn avf_energy<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    let (sys, mut st, h) = preset_start::<S, N, R>(0);
    let h0 = sys.energy(&st.q, &st.v);
    let m = method("dd_avf");
    let mut memory = m.memory();
    let mut worst: f64 = 0.0;
    for _ in 0..100_000 {
        m.step(&sys, &mut st, &mut memory, h).unwrap();
        worst = worst.max((sys.energy(&st.q, &st.v) - h0).abs());
    }
    let rel = worst / h0.abs().max(f64::MIN_POSITIVE);
    println!("{}: dd_avf max |H − H(0)|/|H(0)| over 1e5 steps = {rel:.2e}", S::info().id);
    assert!(rel <= 1e-12, "{}: relative energy error {rel:e}", S::info().id);
}

#[test]
fn dd_avf_conserves_energy_to_round_off() {
    for_each_system!(avf_energy);
}

#[test]
fn rk4_drifts_off_the_constraint() {
    let req = SceneRequest { system: "knife_edge".into(), ..Default::default() };
    let scene = Scene::resolve(&req).unwrap().prepare(Some(&["constraint".into()])).unwrap();
    let mut c = Collect::default();
    scene.run(&method("rk4"), &RunConfig::default(), &mut c);
    let last = c.series.values().next().unwrap().last().unwrap().max;
    assert!(last > 1e-6, "the constraint series must show RK4's drift: {last:e}");
}
