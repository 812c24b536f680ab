//! Work–precision rows: errors against the reference fall at each method's order, and the
//! integrals' maxima are reported; a stop flag ends a measurement; a scene prepared with a
//! given latitude axis uses it.

use nhlab_core::catalogue::work_precision::{measure, measure_until, reference};
use nhlab_core::{Integral, Method, MethodSpec, Scene, SceneRequest};

#[test]
fn final_errors_fall_at_each_methods_order() {
    let req = SceneRequest { system: "knife_edge".into(), t_end: Some(10.0), ..Default::default() };
    let scene = Scene::resolve(&req).unwrap().prepare(Some(&["energy".into()])).unwrap();
    let r = reference(&scene).unwrap();
    assert!(r.state.constraint_residual < 1e-10);
    for (id, order) in [("leapfrog", 2.0), ("dd", 2.0), ("rk4", 4.0)] {
        let m = Method::from_spec(&MethodSpec::new(id)).unwrap();
        let a = measure(&scene, &r.state, &m, 0.1, 2);
        let b = measure(&scene, &r.state, &m, 0.05, 2);
        assert_eq!((a.steps, b.steps), (100, 200));
        let (ea, eb) = (a.final_error.unwrap(), b.final_error.unwrap());
        let observed = (ea / eb).log2();
        assert!((observed - order).abs() < 0.2, "{id}: order {observed} ({ea:e}, {eb:e})");
        assert!(a.max_error[&Integral::Energy] > 0.0 || id == "dd");
        assert!(a.elapsed_ms > 0.0);
    }
}

#[test]
fn a_failed_run_has_no_final_error() {
    let req = SceneRequest { system: "cvt".into(), t_end: Some(1000.0), ..Default::default() };
    let scene = Scene::resolve(&req).unwrap().prepare(None).unwrap();
    let r = reference(&scene).unwrap();
    let lf = Method::from_spec(&MethodSpec::new("leapfrog")).unwrap();
    let row = measure(&scene, &r.state, &lf, 2.5, 1);
    assert!(row.final_error.is_none() && row.error.unwrap().contains("diverged"));
}

#[test]
fn a_stopped_measurement_ends_as_cancelled_without_repeating() {
    let req =
        SceneRequest { system: "knife_edge".into(), t_end: Some(100.0), ..Default::default() };
    let scene = Scene::resolve(&req).unwrap().prepare(Some(&["energy".into()])).unwrap();
    let r = reference(&scene).unwrap();
    let lf = Method::from_spec(&MethodSpec::new("leapfrog")).unwrap();
    let calls = std::cell::Cell::new(0);
    let stop = || {
        calls.set(calls.get() + 1);
        true
    };
    // 10⁵ steps: the first look at the flag (after 4096 steps) stops the run.
    let row = measure_until(&scene, &r.state, &lf, 1e-3, 5, &stop);
    assert!(row.final_error.is_none(), "{row:?}");
    assert!(row.error.as_deref().is_some_and(|e| e.contains("cancel")), "{row:?}");
    assert!(row.steps < 100_000, "{row:?}");
    assert_eq!(calls.get(), 2, "one look in the run, one before a second repetition");
    // Never stopped: the same as measure.
    let free = measure_until(&scene, &r.state, &lf, 0.1, 1, &|| false);
    assert_eq!(free.final_error, measure(&scene, &r.state, &lf, 0.1, 1).final_error);
}

#[test]
fn a_scene_prepared_with_a_given_axis_uses_it() {
    let req = SceneRequest {
        system: "cvt_pendulum".into(),
        preset: Some("oscillating".into()),
        ..Default::default()
    };
    let scene = Scene::resolve(&req).unwrap();
    let axis = scene.latitude_axis().unwrap();
    let computed = scene.clone().prepare(None).unwrap();
    assert_eq!(computed.latitude, Some(axis));
    let mut asked = 0;
    let given = scene
        .clone()
        .prepare_with_latitude(None, |_| {
            asked += 1;
            Ok(axis)
        })
        .unwrap();
    assert_eq!((given.latitude, asked), (Some(axis), 1));
    // Without the latitude among the integrals the axis is not asked for.
    let energy = scene.prepare_with_latitude(Some(&["energy".into()]), |_| panic!("not asked"));
    assert!(energy.unwrap().latitude.is_none());
}
