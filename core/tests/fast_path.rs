//! The coupled fast paths (issue 4: DLA^α's, DLA^{0,1}'s and DD-AVF's), and DD's
//! two-unknown solve (`dd_reduced`), against the general Newton solves: from every state of
//! a trajectory on every system (each preset), one step of each gives the same
//! `(q₁, q̇₁, λ₁)` to 1e-13 (relative to the state's size). Steps are compared one at a time
//! from the same state, not as whole trajectories, whose sensitivity would amplify the
//! round-off the two paths are allowed to differ by.

mod common;
use common::{preset_start, size};
use nhlab_core::methods::{Dd, DdAvf, Dla, Dla01};
use nhlab_core::{Method, System};

const STEPS: usize = 2000;
const TOL: f64 = 1e-13;

/// Pairs (fast, general) of every method that has a fast path.
fn pairs() -> Vec<(Method, Method)> {
    let dla = [0.5, 0.4, 1.0].map(|alpha| Method::Dla(Dla { alpha, ..Dla::default() }));
    let others = [
        Method::Dla01(Dla01::default()),
        Method::Dd(Dd::default()),
        Method::DdAvf(DdAvf::default()),
    ];
    let out: Vec<_> =
        dla.into_iter().chain(others).filter_map(|m| Some((m, m.general_path()?))).collect();
    assert_eq!(out.len(), 6, "every fast path has its general path");
    // A general path equal to the fast one would make the comparison below vacuous.
    assert!(out.iter().all(|(fast, general)| fast != general));
    out
}

fn same_steps<S: System<N, R>, const N: usize, const R: usize>() {
    for preset in 0..S::info().presets.len() {
        let (sys, start, h) = preset_start::<S, N, R>(preset);
        for (fast, general) in pairs() {
            let mut st = start;
            let mut worst: f64 = 0.0;
            for k in 0..STEPS {
                let (mut a, mut b) = (st, st);
                fast.step(&sys, &mut a, h).unwrap();
                general.step(&sys, &mut b, h).unwrap();
                let diff =
                    (a.q - b.q).amax().max((a.v - b.v).amax()).max((a.lambda - b.lambda).amax());
                let rel = diff / size(&b);
                worst = worst.max(rel);
                assert!(
                    rel <= TOL,
                    "{}/{}: {} step {k}: fast and general differ by {rel:e}",
                    S::info().id,
                    S::info().presets[preset].id,
                    fast.label()
                );
                st = b;
            }
            assert!(worst.is_finite());
        }
    }
}

#[test]
fn fast_paths_take_the_general_paths_steps() {
    common::assert_typed_list_matches_registry();
    for_each_system!(same_steps);
}

/// The test above can fail: a fast path with a wrong equation (here, DLA's with another α
/// than the general path's) is caught at the first step.
#[test]
fn a_different_method_is_caught() {
    let (sys, st, h) = preset_start::<nhlab_core::systems::CvtPendulum, 3, 1>(0);
    let (mut a, mut b) = (st, st);
    Method::Dla(Dla { alpha: 0.5, ..Dla::default() }).step(&sys, &mut a, h).unwrap();
    Method::Dla(Dla { alpha: 0.5 + 1e-9, fast_path: false, ..Dla::default() })
        .step(&sys, &mut b, h)
        .unwrap();
    assert!((a.v - b.v).amax() / size(&b) > TOL);
}
