//! The reference solve's bounds: a caller's stop flag ends it, and the states Dop853 keeps do
//! not grow with the number of steps.

use nhlab_core::BuiltIn;
use nhlab_core::Vector;
use nhlab_core::measure::reference::{CHUNK, ReferenceError, TOL, reference, reference_until};
use nhlab_core::model::mechanical::General;
use nhlab_core::systems::{Cvt, CvtPendulum};
use std::cell::Cell;

fn cvt_start() -> (Vector<3>, Vector<3>) {
    (Vector::<3>::new(1.0, 1.0, 0.0), Vector::<3>::new(0.0, 0.5, 1.0))
}

#[test]
fn a_stop_that_turns_true_at_the_kth_look_cancels_the_solve() {
    let (q, v) = cvt_start();
    for k in [1, 3] {
        let calls = Cell::new(0);
        let stop = || {
            calls.set(calls.get() + 1);
            calls.get() >= k
        };
        let r = reference_until(&General(&Cvt), &q, &v, 1000.0, TOL, &stop);
        assert!(
            matches!(r, Err(ReferenceError::Cancelled { t }) if t > 0.0 && t < 1000.0),
            "{r:?}"
        );
        assert_eq!(calls.get(), k, "the solve goes on after the stop");
    }
    // Across the one-time-unit segments of an angle ζ too.
    let sys = CvtPendulum::new(&[0.5]);
    let (q, v) = (Vector::<3>::new(1.0, 1.0, 0.0), Vector::<3>::new(0.0, 0.0, 2.828_427_12));
    let calls = Cell::new(0);
    let stop = || {
        calls.set(calls.get() + 1);
        calls.get() >= 2
    };
    let r = reference_until(&General(&sys), &q, &v, 3000.0, TOL, &stop);
    assert!(matches!(r, Err(ReferenceError::Cancelled { .. })), "{r:?}");
    assert_eq!(calls.get(), 2);
}

#[test]
fn a_stop_that_stays_false_changes_nothing() {
    let (q, v) = cvt_start();
    let calls = Cell::new(0);
    let stop = || {
        calls.set(calls.get() + 1);
        false
    };
    let a = reference_until(&General(&Cvt), &q, &v, 300.0, TOL, &stop).unwrap();
    assert_eq!(a, reference(&General(&Cvt), &q, &v, 300.0, TOL).unwrap());
    // Looked at as the pace says: after the first step, then ever fewer times as the
    // steps between two looks grow (doubled while they take less than the aim).
    assert!(calls.get() >= 1 && calls.get() < a.steps / 10, "{} looks", calls.get());
}

#[test]
fn the_states_kept_do_not_grow_with_the_steps() {
    let (q, v) = cvt_start();
    let r = reference(&General(&Cvt), &q, &v, 2000.0, TOL).unwrap();
    assert!(r.steps > 20 * CHUNK, "{} steps", r.steps);
    assert_eq!(r.stored, CHUNK as usize + 1, "states kept by one solver");
}
