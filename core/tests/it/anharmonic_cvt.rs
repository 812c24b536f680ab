//! `anharmonic_cvt` at κ = 0 is `cvt_pendulum`: every method takes the same steps on both,
//! bit for bit where the two systems' code paths coincide (LF, RK4, DLA^{0,1}), and to
//! Newton's tolerance where `cvt_pendulum`'s quadratic U shortens a solve (DLA^α, DD, DD-AVF,
//! SPARK).

use nhlab_core::BuiltIn;
use nhlab_core::systems::{AnharmonicCvt, CvtPendulum};
use nhlab_core::{Method, State, System, Vector};

/// The largest difference of q and q̇, relative to their size, along `steps` steps of
/// `method` from preset `preset` of both systems.
fn gap(method: &Method, preset: usize, steps: usize) -> f64 {
    let p = &CvtPendulum::info().presets[preset];
    let epsilon = CvtPendulum::info().preset_params(p)[0];
    let (pendulum, anharmonic) = (CvtPendulum { epsilon }, AnharmonicCvt { epsilon, kappa: 0.0 });
    let (q, v) = (Vector::<3>::from_column_slice(p.q), Vector::<3>::from_column_slice(p.v));
    let mut a = State::with_continuous_multiplier(&pendulum, q, v).unwrap();
    let mut b = State::with_continuous_multiplier(&anharmonic, q, v).unwrap();
    assert_eq!(a, b, "the same start");
    let (mut ma, mut mb) = (method.memory(), method.memory());
    let mut worst: f64 = 0.0;
    for _ in 0..steps {
        method.step(&pendulum, &mut a, &mut ma, p.step).unwrap();
        method.step(&anharmonic, &mut b, &mut mb, p.step).unwrap();
        let size = a.q.amax().max(a.v.amax()).max(1.0);
        worst = worst.max((a.q - b.q).amax().max((a.v - b.v).amax()) / size);
    }
    worst
}

#[test]
fn kappa_zero_takes_cvt_pendulums_steps() {
    let methods: Vec<Method> = Method::all()
        .into_iter()
        .flat_map(|m| std::iter::once(m).chain(m.general_path()))
        .collect();
    for m in &methods {
        for preset in 0..4 {
            let gap = gap(m, preset, 500);
            let label = format!("{} ({preset})", m.label());
            if matches!(m.info().id, "dd" | "dd_avf" | "dla" | "spark") {
                // Newton stops within 1e-14 of the same solution, not at the same iterate:
                // DD's and DD-AVF's Jacobians drop terms a quadratic U makes zero, DLA^α
                // trusts its bilinear error estimate only where U is quadratic, and SPARK's
                // class step solves the passenger's equations (linear for a quadratic U) in
                // one. The motion amplifies that little over 500 steps.
                assert!(gap < 1e-11, "{label}: {gap:e}");
            } else {
                assert_eq!(gap, 0.0, "{label}");
            }
        }
    }
}

/// With κ = 1 U is not quadratic, so DD's and DD-AVF's discrete gradients carry their
/// correction terms: the energy stays at round-off only if those are right.
#[test]
fn dd_and_dd_avf_keep_the_energy_of_the_quartic_spring() {
    let kappa_terms = AnharmonicCvt { epsilon: 0.0, kappa: 1.0 };
    assert_eq!(kappa_terms.passenger_potential(&Vector::<3>::new(1.0, 1.0, 0.0)), 2.0);
    for m in Method::all().into_iter().filter(|m| matches!(m.info().id, "dd" | "dd_avf")) {
        for preset in 0..4 {
            let info = AnharmonicCvt::info();
            let p = &info.presets[preset];
            let sys = AnharmonicCvt::new(&info.preset_params(p));
            let (q, v) = (Vector::<3>::from_column_slice(p.q), Vector::<3>::from_column_slice(p.v));
            let mut st = State::with_continuous_multiplier(&sys, q, v).unwrap();
            let h0 = sys.energy(&st.q, &st.v);
            let mut memory = m.memory();
            let mut worst: f64 = 0.0;
            for _ in 0..5000 {
                m.step(&sys, &mut st, &mut memory, p.step).unwrap();
                worst = worst.max((sys.energy(&st.q, &st.v) - h0).abs());
            }
            assert!(worst <= 1e-12 * h0.abs().max(1.0), "{} ({}): {worst:e}", m.label(), p.id);
        }
    }
}
