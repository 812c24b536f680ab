//! Observed order of every method against exact solutions: the least-squares slope of
//! log(global error at a fixed time) against log(h) over 5 step sizes (4 halvings), with
//! errors at the round-off plateau (< 1e-11) dropped.

use crate::common::{self, disk_exact, knife_exact};
use nhlab_core::BuiltIn;
use nhlab_core::systems::{KnifeEdge, RollingDisk};
use nhlab_core::{Method, MethodSpec, State, System, Vector};

fn global_error<S: System<N, R>, const N: usize, const R: usize>(
    sys: &S,
    method: &Method,
    exact: fn(f64) -> (Vector<N>, Vector<N>),
    t_end: f64,
    steps: u32,
) -> f64 {
    let (q0, v0) = exact(0.0);
    let mut st = State::with_continuous_multiplier(sys, q0, v0).unwrap();
    let (h, mut memory) = (t_end / steps as f64, method.memory());
    for _ in 0..steps {
        method.step(sys, &mut st, &mut memory, h).unwrap();
    }
    let (q, v) = exact(t_end);
    (st.q - q).amax().max((st.v - v).amax())
}

fn methods() -> Vec<(Method, f64)> {
    let spec = |id: &str| Method::from_spec(&MethodSpec::new(id)).unwrap();
    let dla = |a: f64| Method::from_spec(&MethodSpec::new("dla").with("alpha", a)).unwrap();
    vec![
        (dla(0.5), 2.0),
        (dla(0.4), 1.0),
        (spec("dla01"), 2.0),
        (spec("leapfrog"), 2.0),
        (spec("dd"), 2.0),
        (spec("dd_avf"), 2.0),
        (spec("rk4"), 4.0),
    ]
}

fn check_orders<S: System<N, R>, const N: usize, const R: usize>(
    name: &str,
    sys: &S,
    exact: fn(f64) -> (Vector<N>, Vector<N>),
    t_end: f64,
    base_steps: u32,
) {
    for (method, order) in methods() {
        let steps: Vec<u32> = (0..5).map(|k| base_steps << k).collect();
        let hs: Vec<f64> = steps.iter().map(|&n| t_end / n as f64).collect();
        let errors: Vec<f64> =
            steps.iter().map(|&n| global_error(sys, &method, exact, t_end, n)).collect();
        let p = common::slope(&hs, &errors, 1e-11);
        println!("{name} {}: order {p:.3} errors {errors:?}", method.label());
        assert!((p - order).abs() <= 0.1, "{name} {}: order {p}, expected {order}", method.label());
        assert_eq!(method.order() as f64, order);
    }
}

#[test]
fn knife_edge_orders() {
    check_orders("knife_edge", &KnifeEdge::new(&[0.0]), knife_exact, 2.0, 20);
}

#[test]
fn rolling_disk_orders() {
    check_orders("rolling_disk", &RollingDisk::new(&[]), disk_exact, 2.0, 20);
}

#[test]
fn exact_solutions_satisfy_the_equations() {
    // Guards the references themselves: constraint holds and velocities are derivatives.
    let ke = KnifeEdge::new(&[0.0]);
    let rd = RollingDisk::new(&[]);
    for t in [0.0, 0.3, 1.7, 4.0] {
        let h = 1e-6;
        let (q, v) = knife_exact(t);
        assert!(ke.constraint_residual(&q, &v) < 1e-14);
        assert!(((knife_exact(t + h).0 - knife_exact(t - h).0) / (2.0 * h) - v).amax() < 1e-8);
        let (q, v) = disk_exact(t);
        assert!(rd.constraint_residual(&q, &v) < 1e-14);
        assert!(((disk_exact(t + h).0 - disk_exact(t - h).0) / (2.0 * h) - v).amax() < 1e-8);
    }
}
