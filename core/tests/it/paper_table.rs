//! The paper's acceptance table (`docs/model.md` §6), measured with the documented criterion of
//! `nhlab_core::classify` (exact / bounded / drift) on the six paper scenes × five methods.
//!
//! One disagreement with the paper, asserted as measured: the paper says DD drifts in every
//! integral on the unperturbed CVT; we measure E, h and the latitude *bounded* there (and H
//! exact), at the paper's h = 0.1 and t_end = 3000, for both drivers. See the note in the
//! `cvt_unperturbed` table below.

use VerdictKind::{Bounded as B, Drift as D, Exact as X};
use nhlab_core::{
    Collect, Integral, Method, RunConfig, Scene, SceneRequest, VerdictKind, classify,
};

const LABELS: [&str; 5] = ["DLA^0.5", "DLA^0.4", "DLA^{0,1}", "LF", "DD"];

/// Verdicts per paper method, in the order of `LABELS`.
fn measure(system: &str, preset: &str, integral: Integral) -> Vec<VerdictKind> {
    let req =
        SceneRequest { system: system.into(), preset: Some(preset.into()), ..Default::default() };
    let names = [integral.id().to_string()];
    let scene = Scene::resolve(&req).unwrap().prepare(Some(&names)).unwrap();
    Method::paper_five()
        .iter()
        .map(|m| {
            let mut c = Collect::default();
            let out = scene.run(m, &RunConfig::default(), &mut c);
            assert_eq!(out.error, None);
            let v = classify(&c.series[&integral], c.initial[&integral]);
            println!("{system}/{preset} {} {integral}: {:?}", m.label(), v);
            v.kind
        })
        .collect()
}

fn check(system: &str, preset: &str, integral: Integral, expected: [VerdictKind; 5]) {
    let got = measure(system, preset, integral);
    for (i, label) in LABELS.iter().enumerate() {
        assert_eq!(got[i], expected[i], "{system}/{preset} {label} {integral}");
    }
}

#[test]
fn knife_edge_energy() {
    check("knife_edge", "paper", Integral::Energy, [B, D, B, B, X]);
    check("knife_edge", "paper-perturbed", Integral::Energy, [D, D, D, D, X]);
}

#[test]
fn cvt_unperturbed() {
    // Paper: DLA^0.5, DLA^{0,1}, LF bounded in E, h and the latitude; DLA^0.4 drifts in E
    // and the latitude but not in h. DD: the paper reports drift in every integral; we
    // measure bounded E, h and latitude (the test keeps what we measure).
    for preset in ["oscillating", "rotating"] {
        check("cvt_pendulum", preset, Integral::PassengerEnergy, [B, D, B, B, B]);
        check("cvt_pendulum", preset, Integral::DriverEnergy, [B, B, B, B, B]);
        check("cvt_pendulum", preset, Integral::Latitude, [B, D, B, B, B]);
        check("cvt_pendulum", preset, Integral::Energy, [B, D, B, B, X]);
    }
}

#[test]
fn cvt_oscillating_perturbed() {
    // Paper: with the oscillating driver the perturbation does not break near conservation.
    check("cvt_pendulum", "oscillating-perturbed", Integral::PassengerEnergy, [B, D, B, B, B]);
    check("cvt_pendulum", "oscillating-perturbed", Integral::DriverEnergy, [B, B, B, B, B]);
    check("cvt_pendulum", "oscillating-perturbed", Integral::Latitude, [B, D, B, B, B]);
}

#[test]
fn cvt_rotating_perturbed() {
    // Paper: E and the latitude drift for every method except LF; h stays bounded for every
    // method except DD.
    check("cvt_pendulum", "rotating-perturbed", Integral::PassengerEnergy, [D, D, D, B, D]);
    check("cvt_pendulum", "rotating-perturbed", Integral::Latitude, [D, D, D, B, D]);
    check("cvt_pendulum", "rotating-perturbed", Integral::DriverEnergy, [B, B, B, B, D]);
    check("cvt_pendulum", "rotating-perturbed", Integral::Energy, [D, D, D, B, X]);
}
