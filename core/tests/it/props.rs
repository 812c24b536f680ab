//! Property tests: over random parameters, random consistent initial states and
//! random steps, every method on every system runs without panicking, reports only finite
//! errors, and ends `ok` or with a typed failure naming its step. Resolution of random,
//! possibly absurd, user numbers never panics either.

use crate::common;
use nhlab_core::BuiltIn;
use nhlab_core::{
    Collect, Method, MethodSpec, RunConfig, Scene, SceneRequest, Vector, method_infos,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

fn methods(alpha: f64) -> Vec<Method> {
    method_infos()
        .iter()
        .filter(|info| !info.external)
        .map(|info| {
            let spec = MethodSpec::new(info.id);
            let spec = if info.id == "dla" { spec.with("alpha", alpha) } else { spec };
            Method::from_spec(&spec).unwrap()
        })
        .collect()
}

fn random_runs<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    let info = S::info();
    let mut runner = TestRunner::new(Config { cases: 24, ..Config::default() });
    let param = |p: &nhlab_core::ParamSpec| {
        // Stay strictly inside open ranges.
        let (lo, hi) = (p.min + 1e-3 * (p.max - p.min), p.max - 1e-3 * (p.max - p.min));
        lo..hi
    };
    let params: Vec<_> = info.params.iter().map(param).collect();
    let strategy = (
        params,
        prop::collection::vec(-3.0..3.0f64, N),
        -2.0..2.0f64,
        -3.0..3.0f64,
        (-3.0f64..0.5).prop_map(|e| 10f64.powf(e)),
        0.05..1.0f64,
    );
    runner
        .run(&strategy, |(params, q, speed, zdot, h, alpha)| {
            let sys = S::new(&params);
            let q = Vector::<N>::from_column_slice(&q);
            // A consistent velocity: along the kernel, plus the driver's own speed.
            let mut v = sys.kernel(q[N - 1]) * speed;
            v[N - 1] = zdot;
            let req = SceneRequest {
                system: info.id.into(),
                params: info
                    .params
                    .iter()
                    .map(|p| p.name.to_string())
                    .zip(params.clone())
                    .collect(),
                q: Some(q.as_slice().to_vec()),
                v: Some(v.as_slice().to_vec()),
                step: Some(h),
                t_end: Some(300.0 * h),
                ..Default::default()
            };
            let scene = Scene::resolve(&req).map_err(|e| TestCaseError::fail(e.to_string()))?;
            // The latitude may be undefined (driver at rest, passenger at the origin): typed.
            let prepared = match scene.clone().prepare(None) {
                Ok(p) => p,
                Err(e) => {
                    prop_assert!(e.to_string().contains("latitude"), "{e}");
                    scene.prepare(Some(&["energy".into(), "constraint".into()])).unwrap()
                }
            };
            for m in methods(alpha) {
                let mut c = Collect::default();
                let out = prepared.run(&m, &RunConfig { points: 20, ..Default::default() }, &mut c);
                if let Some(e) = &out.error {
                    prop_assert!(e.to_string().contains("step "), "{}: {e}", m.label());
                }
                for (i, s) in &c.series {
                    for b in s {
                        prop_assert!(b.mean.is_finite() && b.max.is_finite(), "{} {i}", m.label());
                    }
                }
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn random_scenes_never_panic_and_report_finite_errors() {
    for_each_system!(random_runs);
}

proptest! {
    #![proptest_config(Config {
        cases: 256,
        failure_persistence: common::regressions(),
        ..Config::default()
    })]
    #[test]
    fn resolving_absurd_numbers_never_panics(
        system in prop::sample::select(
            nhlab_core::SYSTEMS.iter().map(|s| s.info().id).chain(["nope"]).collect::<Vec<_>>()
        ),
        eps in prop::num::f64::ANY,
        q in prop::collection::vec(prop::num::f64::ANY, 0..6),
        v in prop::collection::vec(prop::num::f64::ANY, 0..6),
        step in prop::num::f64::ANY,
        t_end in prop::num::f64::ANY,
    ) {
        let req = SceneRequest {
            system: system.into(),
            params: vec![("epsilon".into(), eps)],
            q: Some(q),
            v: Some(v),
            step: Some(step),
            t_end: Some(t_end),
            ..Default::default()
        };
        if let Ok(scene) = Scene::resolve(&req) {
            prop_assert!(scene.step > 0.0 && scene.step.is_finite() && scene.t_end >= scene.step);
        }
    }
}
