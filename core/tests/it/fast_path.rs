//! The coupled fast paths (DLA^α's and DLA^{0,1}'s, on `cvt` and `particle`), DD's
//! (and DD-AVF's) closed form where V is quadratic (`dd::closed_form`) and DD's solve for the
//! driver's speed on the mobile robot (`dd::reduced`), against the general Newton solves: from
//! every state of a trajectory on every system (each preset), one step of each gives the same
//! `(q₁, q̇₁, λ₁)` to 1e-13 (relative to the state's size). Steps are compared one at a time
//! from the same state, not as whole trajectories, whose sensitivity would amplify the
//! round-off the two paths are allowed to differ by. DD's and DD-AVF's fast paths must also
//! leave the energy unbiased: the mean of one step's energy change along a trajectory stays at
//! round-off's, as on their general paths, at the presets' steps and at larger ones.

use crate::common::{case, preset_start, size, step_difference};
use nhlab_core::BuiltIn;
use nhlab_core::methods::{Dd, DdAvf, Dla, Dla01, Spark};
use nhlab_core::{BaseMethod, Method};

const STEPS: usize = 2000;
const TOL: f64 = 1e-13;

/// Pairs (fast, general) of every method that has a fast path.
fn pairs() -> Vec<(Method, Method)> {
    let dla = [0.5, 0.4, 1.0].map(|alpha| Method::from(Dla { alpha, ..Dla::default() }));
    let others = [
        Method::from(Dla01::default()),
        Method::from(Dd::default()),
        Method::from(DdAvf::default()),
    ];
    let spark = (2..=5).map(|stages| Method::from(Spark { stages, ..Spark::default() }));
    let out: Vec<_> = dla
        .into_iter()
        .chain(others)
        .chain(spark)
        .filter_map(|m| Some((m, m.general_path()?)))
        .collect();
    assert_eq!(out.len(), 10, "every fast path has its general path");
    // A general path equal to the fast one would make the comparison below vacuous.
    assert!(out.iter().all(|(fast, general)| fast != general));
    out
}

fn same_steps<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    for preset in 0..S::info().presets.len() {
        let (sys, start, h) = preset_start::<S, N, R>(preset);
        for (fast, general) in pairs() {
            let name = case::<S, N, R>(preset, &fast.label());
            let (mut st, mut memory) = (start, general.memory());
            let mut worst: f64 = 0.0;
            for k in 0..STEPS {
                let ((mut a, mut a_mem), (mut b, mut b_mem)) = ((st, memory), (st, memory));
                match (
                    fast.step(&sys, &mut a, &mut a_mem, h),
                    general.step(&sys, &mut b, &mut b_mem, h),
                ) {
                    (Ok(()), Ok(())) => {}
                    // A method that diverges (DLA^1 gains energy, and on `anharmonic_cvt`'s
                    // stiffening spring runs away) fails alike on both paths.
                    (Err(x), Err(y)) if x == y && k > 0 => break,
                    (x, y) => panic!("{name} step {k}: fast {x:?}, general {y:?}"),
                }
                let rel = step_difference(&a, &b);
                worst = worst.max(rel);
                assert!(rel <= TOL, "{name} step {k}: fast and general differ by {rel:e}");
                (st, memory) = (b, b_mem);
            }
            assert!(worst.is_finite());
        }
    }
}

#[test]
fn fast_paths_take_the_general_paths_steps() {
    for_each_system!(same_steps);
}

/// The test above can fail: a fast path with a wrong equation (here, DLA's with another α
/// than the general path's) is caught at the first step (on `cvt`, where DLA's fast path runs).
#[test]
fn a_different_method_is_caught() {
    let (sys, st, h) = preset_start::<nhlab_core::systems::Cvt, 3, 1>(0);
    let (fast, other) = (
        Method::from(Dla { alpha: 0.5, ..Dla::default() }),
        Method::from(Dla { alpha: 0.5 + 1e-9, fast_path: false, ..Dla::default() }),
    );
    let (mut a, mut b) = (st, st);
    fast.step(&sys, &mut a, &mut fast.memory(), h).unwrap();
    other.step(&sys, &mut b, &mut other.memory(), h).unwrap();
    assert!((a.v - b.v).amax() / size(&b) > TOL);
}

/// DLA^α's and DLA^{0,1}'s fast paths run only where they measured at least 2× their general
/// paths: on `cvt` and `particle`. Elsewhere `fast_path: true` takes the general
/// solve, so the comparison above holds there trivially.
#[test]
fn dla_fast_paths_run_where_they_pay() {
    use nhlab_core::methods::coupled::coupled_fast_path;
    use nhlab_core::systems::*;
    assert!(coupled_fast_path(&Cvt::new(&[])) && coupled_fast_path(&Particle::new(&[])));
    assert!(
        !coupled_fast_path(&CvtPendulum::new(&[0.0]))
            && !coupled_fast_path(&KnifeEdge::new(&[0.0]))
    );
    assert!(
        !coupled_fast_path(&RollingDisk::new(&[])) && !coupled_fast_path(&MobileRobot::new(&[]))
    );
}

/// States along the trajectory from which the two paths step.
const BIAS_STEPS: usize = 20_000;
/// Largest mean energy change per step, relative to the size of H's terms, that an
/// energy-conserving path may show: unbiased rounding averages to ~10⁻¹⁹ over these steps.
const BIAS_TOL: f64 = 1e-17;

/// The mean, over the states of a trajectory, of one step's energy change `ΔH / (½|q̇|² + |V|)`
/// for `m`, and the same for `general` (the trajectory is `general`'s, with whole turns taken
/// off ζ as the driver does), with steps of `h` (the preset's if `None`).
fn mean_energy_change<S: BuiltIn<N, R>, const N: usize, const R: usize>(
    preset: usize,
    m: &Method,
    general: &Method,
    h: Option<f64>,
) -> (f64, f64) {
    let (sys, mut st, preset_h) = preset_start::<S, N, R>(preset);
    let mut memory = general.memory();
    let h = h.unwrap_or(preset_h);
    // The state's value: with the compensations, which carry DD's exact end (`dd::closed_form`).
    let energy = |s: &nhlab_core::State<N, R>| {
        let (q, v) = (s.q + s.q_compensation, s.v + s.v_compensation);
        let (kinetic, potential) = (0.5 * v.norm_squared(), sys.potential(&q));
        (kinetic + potential, kinetic + potential.abs())
    };
    let (mut fast_sum, mut general_sum) = (0.0, 0.0);
    for _ in 0..BIAS_STEPS {
        let (h0, scale) = energy(&st);
        let ((mut a, mut a_mem), (mut b, mut b_mem)) = ((st, memory), (st, memory));
        m.step(&sys, &mut a, &mut a_mem, h).unwrap();
        general.step(&sys, &mut b, &mut b_mem, h).unwrap();
        fast_sum += (energy(&a).0 - h0) / scale;
        general_sum += (energy(&b).0 - h0) / scale;
        (st, memory) = (b, b_mem);
        if sys.zeta_is_angle() {
            st.take_whole_turns(&mut memory);
        }
    }
    (fast_sum / BIAS_STEPS as f64, general_sum / BIAS_STEPS as f64)
}

fn unbiased<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    for preset in 0..S::info().presets.len() {
        for (fast, general) in pairs() {
            if !matches!(fast.base, BaseMethod::Dd(_) | BaseMethod::DdAvf(_)) {
                continue;
            }
            let (mean, general_mean) = mean_energy_change::<S, N, R>(preset, &fast, &general, None);
            let name = case::<S, N, R>(preset, &fast.label());
            println!("{name}: mean ΔH per step {mean:+.1e} (general path {general_mean:+.1e})");
            assert!(
                mean.abs() <= BIAS_TOL && general_mean.abs() <= BIAS_TOL,
                "{name}: the energy changes by {mean:e} per step on average ({general_mean:e} \
                 on the general path): a bias, which grows linearly over a long run"
            );
        }
    }
}

/// A fast path can take the general path's steps to 10⁻¹³ each and still bias DD's or
/// DD-AVF's energy by a rounding whose sign does not average out: 5·10⁻¹⁷ of H per step in
/// DD's `(σ, ε)` experiment (`git show 3afd52e:docs/benchmarks-history.md`), a linear drift
/// of 5·10⁻⁹ over 10⁸ steps, which the test above cannot see. Measured on every path as it is: ≤ 2.9·10⁻¹⁸ (DD
/// on the mobile robot, whose solve for σ in closed-form w measured 3.3·10⁻¹⁷ and failed).
#[test]
fn energy_conserving_fast_paths_do_not_bias_the_energy() {
    for_each_system!(unbiased);
}

/// DD and DD-AVF at steps larger than the presets', where Newton's last increments are no
/// longer tiny and what the last iteration leaves, of one sign, shows in the energy. DD's
/// solve for σ on the mobile robot takes its last increment linearly (with ∂F₁/∂w approximated
/// by a m, it drifted by 2·10⁻¹² of H per step at h = 0.3 and 0.5; with the exact slope but
/// Newton's tolerance alone, 3·10⁻¹⁵ and 9·10⁻¹⁵); the general solves stopped at an estimated
/// 10⁻¹⁴ (DD on `cvt_pendulum`'s `oscillating-perturbed` scene: 3·10⁻¹⁶ per step at h = 0.5).
/// Measured in this test before the fix: −1.7·10⁻¹⁵ (the solve for σ, h = 0.2).
fn unbiased_at_large_steps<S: BuiltIn<N, R>, const N: usize, const R: usize>(preset: usize) {
    for (fast, general) in pairs() {
        if !matches!(fast.base, BaseMethod::Dd(_) | BaseMethod::DdAvf(_)) {
            continue;
        }
        for h in [0.2, 0.3, 0.5] {
            let (mean, general_mean) =
                mean_energy_change::<S, N, R>(preset, &fast, &general, Some(h));
            let name = format!("{} at h = {h}", case::<S, N, R>(preset, &fast.label()));
            println!("{name}: mean ΔH per step {mean:+.1e} (general path {general_mean:+.1e})");
            assert!(
                mean.abs() <= BIAS_TOL && general_mean.abs() <= BIAS_TOL,
                "{name}: the energy changes by {mean:e} per step on average ({general_mean:e} \
                 on the general path)"
            );
        }
    }
}

#[test]
fn energy_conserving_methods_stay_unbiased_at_large_steps() {
    use nhlab_core::systems::{CvtPendulum, MobileRobot};
    unbiased_at_large_steps::<MobileRobot, 4, 2>(0);
    unbiased_at_large_steps::<CvtPendulum, 3, 1>(2);
}
