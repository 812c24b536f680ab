//! Parameters as inputs of the code (`CompiledSystems::parameters_as_inputs`): one
//! compilation bound to each set of values runs as the system compiled with those values
//! folded in, in both forms, with M and the invariants depending on the parameters too.

use nhlab_core::model::custom::{FormulaSpec, GeneralSpec, MassEntry, MassSpec, Parameters};
use nhlab_core::{
    Collect, CompiledSystems, CustomLimits, Integral, Method, Observer, RunConfig, Scene,
    SceneRequest, SystemRequest,
};

#[derive(Default)]
struct End {
    q: Vec<f64>,
    v: Vec<f64>,
    collect: Collect,
}

impl Observer for End {
    fn initial(&mut self, integral: Integral, value: f64) {
        self.collect.initial(integral, value);
    }
    fn points(&mut self, integral: Integral, bucket: nhlab_core::Bucket) {
        self.collect.points(integral, bucket);
    }
    fn finish(&mut self, q: &[f64], v: &[f64]) {
        (self.q, self.v) = (q.to_vec(), v.to_vec());
    }
}

fn run(scene: Scene, m: &Method) -> End {
    let scene = scene.prepare(None).unwrap();
    let mut end = End::default();
    let out = scene.run(m, &RunConfig { points: 32, ..RunConfig::default() }, &mut end);
    assert_eq!(out.error, None, "{}", m.label());
    end
}

/// A bowl in the paper's form whose U, V_d and A read the parameters.
fn coupled() -> SystemRequest {
    SystemRequest::Formulas(FormulaSpec {
        name: "bowl".into(),
        passenger: vec!["x".into(), "y".into()],
        driver: "theta".into(),
        parameters: vec![("k".into(), 1.0), ("c".into(), 0.3)],
        passenger_potential: "k*(x^2 + y^2)/2 + c*x^4".into(),
        driver_potential: "k*(1 - cos(theta))".into(),
        constraints: vec![vec!["1".into(), "c + sin(theta)".into()]],
    })
}

/// A sleigh-like general system whose M, V, A and invariant read the parameters.
fn general() -> SystemRequest {
    SystemRequest::General(GeneralSpec {
        name: "sleigh".into(),
        coordinates: vec!["x".into(), "y".into(), "theta".into()],
        parameters: vec![("m".into(), 1.0), ("a".into(), 0.5), ("g".into(), 0.2)],
        mass: MassSpec::Diagonal(vec![
            MassEntry::Formula("m".into()),
            MassEntry::Formula("m".into()),
            MassEntry::Formula("1 + m*a^2".into()),
        ]),
        potential: "m*g*y + a*x^2/2".into(),
        constraints: vec![vec!["-sin(theta)".into(), "cos(theta)".into(), "-a".into()]],
        invariants: vec![("speed".into(), "m*(x_dot*cos(theta) + y_dot*sin(theta))".into())],
        detect_class: true,
    })
}

fn request(system: &SystemRequest, params: &[(&str, f64)], q: &[f64], v: &[f64]) -> SceneRequest {
    SceneRequest {
        system: system.clone(),
        params: params.iter().map(|(n, x)| (n.to_string(), *x)).collect(),
        q: Some(q.to_vec()),
        v: Some(v.to_vec()),
        step: Some(0.05),
        t_end: Some(20.0),
        ..Default::default()
    }
}

/// Runs each set of values through one compilation with the parameters as inputs, and
/// compiled with them folded in: the same trajectories to round-off.
fn bound_runs_as_folded(system: SystemRequest, sets: &[&[(&str, f64)]], q: &[f64], v: &[f64]) {
    let limits = CustomLimits::default();
    let mut inputs = CompiledSystems::parameters_as_inputs();
    let mut compilations = std::collections::HashSet::new();
    for set in sets {
        let req = request(&system, set, q, v);
        let bound = Scene::resolve_cached(&req, &limits, &mut inputs).unwrap();
        let folded = Scene::resolve(&req).unwrap();
        let custom = bound.system.formulas().unwrap();
        assert_eq!(custom.parameters, Parameters::Inputs);
        assert_eq!(folded.system.formulas().unwrap().parameters, Parameters::Folded);
        assert_eq!(bound.params, folded.params, "{set:?}");
        assert_eq!(bound.system.integrals(), folded.system.integrals(), "{set:?}");
        compilations.insert(std::sync::Arc::as_ptr(&custom.spec) as usize);
        for m in Method::all().into_iter().filter(|m| m.info().class_only.is_none()) {
            let (a, b) = (run(bound.clone(), &m), run(folded.clone(), &m));
            let scale = a.q.iter().chain(&a.v).fold(1.0_f64, |s, x| s.max(x.abs()));
            let d =
                a.q.iter()
                    .chain(&a.v)
                    .zip(b.q.iter().chain(&b.v))
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max);
            assert!(d <= 1e-9 * scale, "{set:?} {}: {d:.1e}", m.label());
            for (i, series) in &a.collect.series {
                let (x, y) = (series.last().unwrap(), b.collect.series[i].last().unwrap());
                // Errors near round-off differ by round-off.
                let d = (x.max - y.max).abs();
                assert!(
                    d <= 1e-9 * x.max.abs() + 1e-13,
                    "{set:?} {} {i}: {} vs {}",
                    m.label(),
                    x.max,
                    y.max
                );
            }
        }
    }
    assert_eq!(compilations.len(), 1, "one compilation serves every set of values");
}

#[test]
fn a_system_in_the_paper_s_form_bound_to_values_runs_as_compiled_with_them() {
    let sets: [&[(&str, f64)]; 3] = [&[("k", 1.0)], &[("k", 2.5), ("c", 0.1)], &[("k", 0.5)]];
    bound_runs_as_folded(coupled(), &sets, &[0.5, 0.2, 0.1], &[0.0, 0.0, 1.0]);
}

/// The sleigh's initial velocity at θ = 0.3: along its blade (on the constraint for any a).
const SLEIGH_V: [f64; 3] = [0.5 * 0.955_336_489_125_606, 0.5 * 0.295_520_206_661_339_6, 0.0];

#[test]
fn a_system_in_the_general_form_bound_to_values_runs_as_compiled_with_them() {
    let sets: [&[(&str, f64)]; 3] = [&[], &[("m", 2.0), ("a", 0.25)], &[("g", 0.0), ("m", 0.5)]];
    bound_runs_as_folded(general(), &sets, &[0.0, 0.0, 0.3], &SLEIGH_V);
}

/// Values that make M singular are that binding's error, at `system.mass`, as when compiled
/// with them.
#[test]
fn binding_checks_m_at_the_new_values() {
    let limits = CustomLimits::default();
    let mut inputs = CompiledSystems::parameters_as_inputs();
    let (q, v) = ([0.0, 0.0, 0.3], SLEIGH_V);
    Scene::resolve_cached(&request(&general(), &[], &q, &v), &limits, &mut inputs).unwrap();
    let bad = request(&general(), &[("m", 0.0)], &q, &v);
    let err = Scene::resolve_cached(&bad, &limits, &mut inputs).unwrap_err();
    let folded = Scene::resolve(&bad).unwrap_err();
    assert_eq!(err.to_string(), folded.to_string());
    assert!(err.to_string().contains("positive definite"), "{err}");
}

/// A U whose second derivatives read a parameter but no coordinate stays quadratic (the fast
/// path), its coefficients taken per binding; the latitude is defined for the values that
/// make `U = ½|x|²` only.
#[test]
fn a_quadratic_u_stays_quadratic_its_coefficients_bound() {
    let SystemRequest::Formulas(mut spec) = coupled() else { unreachable!() };
    spec.passenger_potential = "k*(x^2 + y^2)/2".into();
    let system = SystemRequest::Formulas(spec);
    let limits = CustomLimits::default();
    let mut inputs = CompiledSystems::parameters_as_inputs();
    for (k, latitude) in [(2.0, false), (1.0, true), (0.5, false)] {
        let req = request(&system, &[("k", k)], &[0.5, 0.2, 0.1], &[0.0, 0.0, 1.0]);
        let bound = Scene::resolve_cached(&req, &limits, &mut inputs).unwrap();
        let c = bound.system.formulas().unwrap().class_compiled().unwrap().clone();
        assert!(c.quadratic_passenger, "k = {k}");
        assert_eq!(c.latitude, latitude, "k = {k}");
        assert_eq!(bound.system.integrals().contains(&Integral::Latitude), latitude, "k = {k}");
        let folded = Scene::resolve(&req).unwrap();
        for m in Method::paper_five() {
            let (a, b) = (run(bound.clone(), &m), run(folded.clone(), &m));
            assert_eq!((a.q, a.v), (b.q, b.v), "k = {k} {}: bit for bit", m.label());
        }
    }
}
