//! Accuracy of the latitude's monodromy axis, and the latitude as a conserved quantity.

use nalgebra::{Matrix3, Vector3};
use nhlab_core::BuiltIn;
use nhlab_core::measure::latitude::LatitudeAxis;
use nhlab_core::systems::{Cvt, CvtPendulum};
use nhlab_core::{
    Collect, Integral, Method, MethodSpec, RunConfig, Scene, SceneRequest, System, Vector,
};
use std::f64::consts::TAU;

/// Independent reference: classical RK4 with a tiny fixed step on (ζ, ζ̇, u).
fn rk4_passenger<S: System<3, 1>>(
    sys: &S,
    zeta: f64,
    zdot: f64,
    u: Vector3<f64>,
    t: f64,
) -> Vector3<f64> {
    let f = |y: &[f64; 5]| -> [f64; 5] {
        let k = sys.kernel(y[0]);
        [y[1], -sys.driver_potential_d1(y[0]), k[0] * y[4], k[1] * y[4], -k[0] * y[2] - k[1] * y[3]]
    };
    let n = 200_000;
    let h = t / n as f64;
    let mut y = [zeta, zdot, u[0], u[1], u[2]];
    let add =
        |a: &[f64; 5], b: &[f64; 5], s: f64| std::array::from_fn::<f64, 5, _>(|i| a[i] + s * b[i]);
    for _ in 0..n {
        let k1 = f(&y);
        let k2 = f(&add(&y, &k1, h / 2.0));
        let k3 = f(&add(&y, &k2, h / 2.0));
        let k4 = f(&add(&y, &k3, h));
        y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    Vector3::new(y[2], y[3], y[4])
}

fn check_axis<S: System<3, 1>>(sys: &S, q: Vector<3>, v: Vector<3>) -> LatitudeAxis {
    let ax = LatitudeAxis::compute(sys, &q, &v).unwrap();
    let r = ax.monodromy;
    assert!((r.transpose() * r - Matrix3::identity()).amax() < 1e-11, "not orthogonal");
    assert!((r.determinant() - 1.0).abs() < 1e-11);
    assert!((r * ax.axis - ax.axis).amax() < 1e-11, "axis not fixed");
    // R u(0) against an independent RK4 solve over one period.
    let u0 = Vector3::new(q[0], q[1], sys.kernel(q[2]).dot(&v));
    let reference = rk4_passenger(sys, q[2], v[2], u0, ax.period);
    assert!((r * u0 - reference).amax() < 1e-10, "{} vs {}", r * u0, reference);
    ax
}

#[test]
fn harmonic_driver_period_is_two_pi() {
    let ax = check_axis(&Cvt, Vector::<3>::new(1.0, 1.0, 0.0), Vector::<3>::new(0.0, 0.5, 1.0));
    assert!((ax.period - TAU).abs() < 1e-10, "period {}", ax.period);
}

#[test]
fn pendulum_driver_axes_match_an_independent_solve() {
    for eps in [0.0, 0.5] {
        let sys = CvtPendulum::new(&[eps]);
        for zdot in [1.897_366_6, 2.828_427_12, -1.2] {
            check_axis(&sys, Vector::<3>::new(1.0, 1.0, 0.0), Vector::<3>::new(0.0, 0.0, zdot));
        }
    }
}

#[test]
fn latitude_error_converges_at_second_order_for_leapfrog() {
    let run = |h: f64| {
        let req = SceneRequest {
            system: "cvt_pendulum".into(),
            preset: Some("rotating-perturbed".into()),
            step: Some(h),
            t_end: Some(300.0),
            ..Default::default()
        };
        let scene = Scene::resolve(&req).unwrap().prepare(Some(&["latitude".into()])).unwrap();
        let mut c = Collect::default();
        let lf = Method::from_spec(&MethodSpec::new("leapfrog")).unwrap();
        scene.run(&lf, &RunConfig::default(), &mut c);
        c.series[&Integral::Latitude].iter().map(|b| b.max).fold(0.0, f64::max)
    };
    let (e1, e2) = (run(0.04), run(0.02));
    let ratio = e1 / e2;
    assert!((3.2..5.0).contains(&ratio), "latitude error ratio {ratio} ({e1:e}, {e2:e})");
}

#[test]
fn undefined_latitude_is_an_error() {
    let r = LatitudeAxis::compute(&Cvt, &Vector::<3>::new(1.0, 1.0, 0.0), &Vector::<3>::zeros());
    assert!(r.is_err());
}
