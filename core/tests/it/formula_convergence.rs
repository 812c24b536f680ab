//! A system new to nhlab, given only as formulas: three passengers (a size no built-in has),
//! an anharmonic U (so the general paths run), a pendulum driver and a constraint mixing all
//! three passenger speeds. Every method converges at its order against the reference solve
//! (least-squares slope of log error against log h over 5 step sizes), and DD keeps H at
//! round-off, as it does on every system of the class.

use crate::common;
use nhlab_core::measure::reference::reference_until;
use nhlab_core::model::custom::Custom;
use nhlab_core::model::mechanical::General;
use nhlab_core::{
    CustomLimits, CustomSystem, FormulaSpec, Method, MethodSpec, State, System, Vector,
};

fn spec() -> FormulaSpec {
    FormulaSpec {
        name: "three passengers".into(),
        passenger: vec!["x".into(), "y".into(), "w".into()],
        driver: "z".into(),
        parameters: vec![("k".into(), 2.0)],
        passenger_potential: "(x^2 + k*y^2 + w^2)/2 + x^4/4".into(),
        driver_potential: "1 - cos(z)".into(),
        constraints: vec![vec!["1".into(), "sin(z)".into(), "cos(z)/2".into()]],
    }
}

fn system() -> (Custom<4, 1>, Vector<4>, Vector<4>) {
    let c = CustomSystem::compile(&spec(), &[], &CustomLimits::default()).unwrap();
    let compiled = c.class_compiled().unwrap();
    assert!(!compiled.quadratic_passenger && compiled.angle);
    let sys = Custom::<4, 1>::new(compiled.clone());
    // A consistent start: ẋ + sin(z) ẏ + cos(z)/2 ẇ = 0 at z = 0.3.
    let z: f64 = 0.3;
    let (vy, vw) = (0.4, -0.6);
    let vx = -(z.sin() * vy + z.cos() / 2.0 * vw);
    (sys, Vector::<4>::new(0.5, -0.3, 0.2, z), Vector::<4>::new(vx, vy, vw, 1.2))
}

#[test]
fn every_method_converges_at_its_order_on_a_system_given_as_formulas() {
    let (sys, q0, v0) = system();
    let t_end = 2.0;
    let exact = reference_until(&General(&sys), &q0, &v0, t_end, 1e-13, &|| false).unwrap();
    // Every method, at the order it declares (DLA^0.4: 1).
    for m in Method::all() {
        let order = m.order() as f64;
        let mut hs = Vec::new();
        let mut errors = Vec::new();
        for steps in [20u32, 40, 80, 160, 320] {
            let h = t_end / steps as f64;
            let mut st = State::with_continuous_multiplier(&sys, q0, v0).unwrap();
            let mut memory = m.memory();
            for _ in 0..steps {
                m.step(&sys, &mut st, &mut memory, h).unwrap();
            }
            hs.push(h);
            errors.push((st.q - exact.q).amax().max((st.v - exact.v).amax()));
        }
        // The reference is good to about 1e-12: SPARK3 (order 4) reaches 7e-11 at 160 steps.
        let p = common::slope(&hs, &errors, 2e-11);
        let shown: Vec<String> = errors.iter().map(|e| format!("{e:.2e}")).collect();
        println!("{}: order {p:.3}, errors {shown:?}", m.label());
        assert!((p - order).abs() <= 0.15, "{}: order {p}, expected {order}", m.label());
    }
}

#[test]
fn dd_keeps_the_energy_of_a_system_given_as_formulas() {
    let (sys, q0, v0) = system();
    let dd = Method::from_spec(&MethodSpec::new("dd")).unwrap();
    let mut st = State::with_continuous_multiplier(&sys, q0, v0).unwrap();
    let mut memory = dd.memory();
    let h0 = sys.energy(&st.q, &st.v);
    let mut worst: f64 = 0.0;
    for _ in 0..1000 {
        dd.step(&sys, &mut st, &mut memory, 0.1).unwrap();
        worst = worst.max((sys.energy(&st.q, &st.v) - h0).abs());
    }
    assert!(worst < 1e-12 * h0.abs().max(1.0), "DD's energy moved by {worst:e}");
    // The leap-frog's does not stay there: the test can tell.
    let lf = Method::from_spec(&MethodSpec::new("leapfrog")).unwrap();
    let mut st = State::with_continuous_multiplier(&sys, q0, v0).unwrap();
    let mut memory = lf.memory();
    let mut lf_worst: f64 = 0.0;
    for _ in 0..1000 {
        lf.step(&sys, &mut st, &mut memory, 0.1).unwrap();
        lf_worst = lf_worst.max((sys.energy(&st.q, &st.v) - h0).abs());
    }
    assert!(lf_worst > 1e-6, "{lf_worst:e}");
}
