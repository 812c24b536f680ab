//! Work–precision rows: errors against the reference fall at each method's order, and the
//! integrals' maxima are reported.

use nhlab_core::work_precision::{measure, reference};
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
