//! At rest at an equilibrium every method stays there. Gonzalez's correction `c/|Δq|²` is
//! 0/0 there in exact arithmetic and rounding over rounding in doubles: DD's Jacobian came out
//! singular on the mobile robot (`dd::is_rounding`), and its solve for the driver's speed
//! alone had no root (`dd::reduced`, which hands that step to the general solve).

use nhlab_core::BuiltIn;
use nhlab_core::systems::{CvtPendulum, MobileRobot};
use nhlab_core::{Method, State, Vector};

/// Ten steps of every method, by its default path and its general one, from rest at `q`.
fn stays_at_rest<S: BuiltIn<N, R>, const N: usize, const R: usize>(sys: &S, q: Vector<N>) {
    for m in Method::all() {
        for m in [Some(m), m.general_path()].into_iter().flatten() {
            let case = format!("{} {}", S::info().id, m.label());
            let mut st = State::with_continuous_multiplier(sys, q, Vector::zeros())
                .unwrap_or_else(|| panic!("{case}: a state at rest is consistent"));
            if let Err(e) = m.steps(sys, &mut st, 0.1, 10) {
                panic!("{case}: {e:?}");
            }
            // V_d' is 6·10⁻¹⁷ at −π/2 in doubles, not 0: the robot may creep by that much.
            assert!((st.q - q).amax() < 1e-14 && st.v.amax() < 1e-14, "{case}: {:?}", st.q);
        }
    }
}

#[test]
fn every_method_stays_at_rest_at_an_equilibrium() {
    stays_at_rest(&MobileRobot, Vector::<4>::new(1.0, -2.0, 0.5, -std::f64::consts::FRAC_PI_2));
    stays_at_rest(&CvtPendulum { epsilon: 0.0 }, Vector::<3>::zeros());
}
