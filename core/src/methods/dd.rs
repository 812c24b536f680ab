//! `dd`: the discrete-derivative method (Gonzalez's discrete gradient, as Betsch uses it).
//!
//! Conserves the total energy H exactly (up to round-off) and is reversible, but does not
//! preserve the fibration: through `|Δq|²` the driver's update sees the passenger. One map,
//! `docs/model.md` §3, solved three ways:
//! - [`step`]: the general path, Newton in `(q̇₁, λ)` with Gonzalez's gradient
//!   ([`gonzalez`]), shared with DD-AVF, starting from Euler's step with the driver's speed
//!   extrapolated from the last steps ([`driver_history`]);
//! - [`closed_form`]: where V is quadratic, the step in closed form, ended in double-double
//!   so that H stays at round-off however long the run (DD-AVF's too);
//! - [`reduced`]: where the passenger feels no potential and its kernel is one line (the
//!   mobile robot), Newton in the driver's speed alone, the passenger's following in closed
//!   form.
//!
//! The fast paths give the same steps to round-off and are tested against the general path
//! (`tests/it/fast_path.rs`).

pub(crate) mod closed_form;
pub(crate) mod driver_history;
mod general;
mod gonzalez;
mod memory;
pub(crate) mod reduced;
pub(crate) mod step;

use self::gonzalez::discrete_gradient;
pub use self::memory::DdMemory;
use self::step::discrete_derivative_step;
use crate::methods::integrator::{Integrator, MethodInfo, Stepper};
use crate::model::system::{DriverTerms, System};
use crate::solver::angle_tracker::AngleTracker;
use crate::solver::newton::NewtonConfig;
use crate::{InputError, State, StepFailure, Vector};

/// The discrete-derivative method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dd {
    /// Newton's settings.
    pub newton: NewtonConfig,
    /// Where V is quadratic, take the step in closed form and end it in double-double
    /// ([`closed_form`]); on the mobile robot, solve Newton for the driver's speed alone, the
    /// passenger's following in closed form ([`reduced`]). Same steps to round-off; `false`
    /// forces the general `(q̇₁, λ)` solve, which they are tested against (in doubles: its
    /// energy error grows with the run where the exact end's stays flat).
    pub fast_path: bool,
}

impl Default for Dd {
    fn default() -> Self {
        Self { newton: NewtonConfig::ENERGY_CONSERVING, fast_path: true }
    }
}

static INFO: MethodInfo = MethodInfo {
    id: "dd",
    name: "Discrete derivative (DD)",
    params: &[],
    order: 2,
    reference: "Gonzalez, J. Nonlinear Sci. 6 (1996); Betsch, CMAME 195 (2006); Modin & Verdier §2",
    implicit: true,
    composed_order_limit: Some(4),
    class_only: None,
    instrument: false,
    symmetric_at: None,
    external: false,
    by_tableau: false,
};

impl Integrator for Dd {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(_params: &[f64]) -> Result<Self, InputError> {
        Ok(Self::default())
    }
    fn label(&self) -> String {
        "DD".into()
    }
    fn general_path(&self) -> Option<Self> {
        Some(Self { fast_path: false, ..*self })
    }
    fn symmetric(&self) -> bool {
        true
    }
}

impl Stepper for Dd {
    type Memory<const N: usize, const R: usize> = DdMemory<N, R>;
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut DdMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        if self.fast_path && closed_form::applies(sys) {
            return closed_form::step(sys, st, mem, h);
        }
        if self.fast_path && reduced::applies(sys) {
            // Where the solve for σ fails (at rest at an equilibrium its closed form is 0/0),
            // the general one decides, out of line: inlined here it slowed every step.
            return reduced::step(sys, st, mem, h, &self.newton)
                .or_else(|_| self.general_step_out_of_line(sys, st, mem, h));
        }
        self.general_step(sys, st, mem, h)
    }
}

impl Dd {
    /// DD's step by the general `(q̇₁, λ)` solve.
    #[inline]
    fn general_step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut DdMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let v_q0 =
            sys.passenger_potential(&st.q) + mem.end.driver_potential_and_constraint(sys, st).0;
        let q0 = st.q;
        // Gonzalez's correction makes the Jacobian dense unless V is quadratic.
        let diagonal = sys.quadratic_passenger() && sys.quadratic_driver();
        let gradient = |dq: &Vector<N>, mid: &DriverTerms<N, R>, end: &mut AngleTracker| {
            discrete_gradient(sys, (&q0, v_q0), dq, h, mid, end)
        };
        discrete_derivative_step(sys, st, mem, h, &self.newton, diagonal, gradient)
    }

    /// [`Dd::general_step`] where it is the exception.
    #[cold]
    #[inline(never)]
    fn general_step_out_of_line<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut DdMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        self.general_step(sys, st, mem, h)
    }
}
