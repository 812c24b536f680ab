//! Bad input gives typed errors naming the field; resolution fills from presets.

use nhlab_core::{InputError, Method, MethodSpec, Scene, SceneRequest};

fn req(system: &str) -> SceneRequest {
    SceneRequest { system: system.into(), ..Default::default() }
}

fn err(r: SceneRequest) -> InputError {
    Scene::resolve(&r).expect_err("should be rejected")
}

#[test]
fn presets_fill_and_fields_override() {
    let s = Scene::resolve(&req("cvt_pendulum")).unwrap();
    assert_eq!(
        (s.preset, s.steps(), s.params.as_slice()),
        (Some("oscillating"), 30_000, &[0.0][..])
    );
    let s = Scene::resolve(&SceneRequest {
        preset: Some("rotating-perturbed".into()),
        ..req("cvt_pendulum")
    })
    .unwrap();
    assert_eq!(s.named_params(), vec![("epsilon", 0.5)]);
    let s = Scene::resolve(&SceneRequest {
        preset: Some("rotating-perturbed".into()),
        params: vec![("epsilon".into(), 0.2)],
        step: Some(0.05),
        ..req("cvt_pendulum")
    })
    .unwrap();
    assert_eq!((s.params[0], s.step, s.steps()), (0.2, 0.05, 60_000));
    assert_eq!(Scene::resolve(&req("knife_edge")).unwrap().steps(), 318);
}

#[test]
fn scene_errors_name_their_field() {
    let cases: Vec<(SceneRequest, &str, &str)> = vec![
        (req("skate"), "system", "valid systems: knife_edge"),
        (
            SceneRequest { preset: Some("nope".into()), ..req("knife_edge") },
            "preset",
            "paper-perturbed",
        ),
        (
            SceneRequest { params: vec![("eps".into(), 0.1)], ..req("knife_edge") },
            "params.eps",
            "epsilon",
        ),
        (
            SceneRequest { params: vec![("epsilon".into(), 1.0)], ..req("knife_edge") },
            "params.epsilon",
            "(-1, 1)",
        ),
        (
            SceneRequest { params: vec![("epsilon".into(), f64::NAN)], ..req("knife_edge") },
            "params.epsilon",
            "finite",
        ),
        (
            SceneRequest { params: vec![("alpha".into(), 1.0)], ..req("cvt") },
            "params.alpha",
            "none",
        ),
        (SceneRequest { q: Some(vec![0.0, 0.0]), ..req("knife_edge") }, "q", "3 components"),
        (SceneRequest { v: Some(vec![0.0; 5]), ..req("rolling_disk") }, "v", "4 components"),
        (
            SceneRequest { q: Some(vec![0.0, f64::INFINITY, 0.0]), ..req("knife_edge") },
            "q[1]",
            "finite",
        ),
        (SceneRequest { v: Some(vec![1.0, 0.0, 1.0]), ..req("knife_edge") }, "v", "1.000e0"),
        // So large that the run would count as diverged from its first step.
        (SceneRequest { q: Some(vec![1e300, 1e300, 0.0]), ..req("cvt") }, "q[0]", "at most 1e90"),
        (
            SceneRequest {
                q: Some(vec![0.0, 0.0, 1.0]),
                v: Some(vec![0.0, 0.0, -1e95]),
                ..req("knife_edge")
            },
            "v[2]",
            "too large",
        ),
        (SceneRequest { step: Some(0.0), ..req("knife_edge") }, "step", "positive"),
        (SceneRequest { step: Some(-0.1), ..req("knife_edge") }, "step", "positive"),
        (SceneRequest { step: Some(f64::NAN), ..req("knife_edge") }, "step", "finite"),
        (SceneRequest { t_end: Some(0.1), ..req("knife_edge") }, "t_end", "at least one step"),
        (SceneRequest { t_end: Some(f64::INFINITY), ..req("knife_edge") }, "t_end", "finite"),
    ];
    for (r, field, text) in cases {
        let e = err(r.clone());
        assert_eq!(e.field(), field, "{r:?}: {e}");
        assert!(e.to_string().contains(text), "{r:?}: '{e}' lacks '{text}'");
    }
}

#[test]
fn integral_errors() {
    let s = || Scene::resolve(&req("knife_edge")).unwrap();
    let e = s().prepare(Some(&["latitude".into()])).unwrap_err();
    assert!(matches!(e, InputError::IntegralUnavailable { .. }), "{e}");
    assert!(e.to_string().contains("energy, passenger_energy"), "{e}");
    let e = s().prepare(Some(&["entropy".into()])).unwrap_err();
    assert_eq!(e.field(), "integrals");
    assert!(e.to_string().contains("latitude"), "{e}");
    assert_eq!(s().prepare(None).unwrap().integrals.len(), 4);
}

#[test]
fn method_errors() {
    let e = Method::from_spec(&MethodSpec::new("rk5")).unwrap_err();
    assert!(e.to_string().contains("dla, dla01, leapfrog, dd, dd_avf, rk4"), "{e}");
    let e = Method::from_spec(&MethodSpec::new("dla").with("alpha", 0.0))
        .unwrap_err()
        .within("methods[1]");
    assert_eq!(e.field(), "methods[1].alpha");
    assert!(e.to_string().contains("(0, 1]"), "{e}");
    let e = Method::from_spec(&MethodSpec::new("leapfrog").with("alpha", 0.5)).unwrap_err();
    assert_eq!(e.field(), "alpha");
    let m = Method::from_spec(&MethodSpec::new("dla").with("alpha", 0.4)).unwrap();
    assert_eq!((m.label().as_str(), m.order()), ("DLA^0.4", 1));
    assert_eq!(Method::from_spec(&MethodSpec::new("dla")).unwrap().params(), vec![("alpha", 0.5)]);
}
