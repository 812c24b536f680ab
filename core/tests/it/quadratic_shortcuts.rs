//! The shortcuts DD and DD-AVF take where parts of V are quadratic
//! (`System::quadratic_passenger`, `System::quadratic_driver`) against their general
//! discrete gradients: every test system is wrapped in [`General`], which declares neither,
//! and from every state of a trajectory (each preset) one step of each gives the same
//! `(q₁, q̇₁, λ₁)` to 1e-13 (relative to the state's size). Every test system has a quadratic
//! U, so the wrapped systems are also what runs the general paths at all.

use crate::common::{case, preset_start, worst_step_difference};
use nhlab_core::BuiltIn;
use nhlab_core::methods::{Dd, DdAvf};
use nhlab_core::{DriverTerms, Matrix, Method, System, SystemInfo, Vector};

const STEPS: usize = 2000;
const TOL: f64 = 1e-13;

/// `S` without its declarations of quadratic potentials.
struct General<S>(S);

impl<S: BuiltIn<N, R>, const N: usize, const R: usize> BuiltIn<N, R> for General<S> {
    fn info() -> &'static SystemInfo {
        S::info()
    }
    fn new(params: &[f64]) -> Self {
        Self(S::new(params))
    }
}

impl<S: BuiltIn<N, R>, const N: usize, const R: usize> System<N, R> for General<S> {
    fn zeta_is_angle(&self) -> bool {
        self.0.zeta_is_angle()
    }
    fn passenger_potential(&self, q: &Vector<N>) -> f64 {
        self.0.passenger_potential(q)
    }
    fn passenger_gradient(&self, q: &Vector<N>) -> Vector<N> {
        self.0.passenger_gradient(q)
    }
    fn passenger_hessian(&self, q: &Vector<N>) -> Matrix<N, N> {
        self.0.passenger_hessian(q)
    }
    fn driver_potential(&self, zeta: f64) -> f64 {
        self.0.driver_potential(zeta)
    }
    fn driver_potential_d1(&self, zeta: f64) -> f64 {
        self.0.driver_potential_d1(zeta)
    }
    fn driver_potential_d2(&self, zeta: f64) -> f64 {
        self.0.driver_potential_d2(zeta)
    }
    fn constraint(&self, zeta: f64) -> Matrix<R, N> {
        self.0.constraint(zeta)
    }
    fn constraint_d(&self, zeta: f64) -> Matrix<R, N> {
        self.0.constraint_d(zeta)
    }
    fn kernel(&self, zeta: f64) -> Vector<N> {
        self.0.kernel(zeta)
    }
    fn driver_is_periodic(&self) -> bool {
        self.0.driver_is_periodic()
    }
    fn driver_terms_trig(&self, zeta: f64, sin: f64, cos: f64) -> DriverTerms<N, R> {
        self.0.driver_terms_trig(zeta, sin, cos)
    }
}

/// The largest relative difference between one step of `a` on `S` and one of `b` on
/// `General<S>`, from each state of `b`'s trajectory of preset `preset`.
fn worst_difference<S: BuiltIn<N, R>, const N: usize, const R: usize>(
    preset: usize,
    (a, b): (Method, Method),
) -> f64 {
    let (sys, start, h) = preset_start::<S, N, R>(preset);
    let general = General(sys);
    worst_step_difference(
        start,
        b.memory(),
        STEPS,
        |st, memory| a.step(&general.0, st, memory, h).unwrap_or_else(|e| panic!("{e}")),
        |st, memory| b.step(&general, st, memory, h).unwrap_or_else(|e| panic!("general: {e}")),
    )
}

fn same_steps<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    for preset in 0..S::info().presets.len() {
        for m in [Method::from(Dd::default()), Method::from(DdAvf::default())] {
            let worst = worst_difference::<S, N, R>(preset, (m, m));
            let name = case::<S, N, R>(preset, &m.label());
            assert!(worst <= TOL, "{name}: the shortcut and the general path differ by {worst:e}");
        }
    }
}

#[test]
fn quadratic_shortcuts_take_the_general_steps() {
    for_each_system!(same_steps);
}

/// The comparison above can fail: DD and DD-AVF, whose discrete gradients differ where V_d
/// is not quadratic, are told apart on `cvt_pendulum`.
#[test]
fn different_discrete_gradients_are_caught() {
    let pair = (Method::from(Dd::default()), Method::from(DdAvf::default()));
    let worst = worst_difference::<nhlab_core::systems::CvtPendulum, 3, 1>(0, pair);
    assert!(worst > 1e3 * TOL, "{worst:e}");
}
