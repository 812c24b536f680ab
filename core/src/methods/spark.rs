//! `spark`: Jay's Lobatto IIIA–IIIB SPARK methods with s = 2 … 5 stages, of order 2s − 2
//! (`docs/model.md` §3). Positions by Lobatto IIIA, velocities and the constraint forces by
//! Lobatto IIIB, the constraint imposed as s − 1 conditions weighted by IIIA's rows 2 … s (the
//! last one: on average over the step) and exactly at the step's end:
//!
//! ```text
//! Q_i   = q₀ + h Σ_j a_ij V_j
//! M V_i = M q̇₀ + h Σ_j ā_ij (−∇V(Q_j) + A(Q_j)ᵀ Λ_j)
//! 0     = Σ_j a_ij A(Q_j) V_j                                   (i = 2 … s)
//! q₁    = q₀ + h Σ_j b_j V_j,   M q̇₁ = M q̇₀ + h Σ_j b_j (−∇V(Q_j) + A(Q_j)ᵀ Λ_j),   0 = A(q₁) q̇₁
//! ```
//!
//! (L. Jay, BIT 43 (2003), as odelab's `Spark` and GeometricIntegrators.jl's
//! `SPARKLobattoIIIAIIIB` write it.) IIIB's last column is zero, so Λ_s enters only q̇₁: the
//! end condition is the M-orthogonal projection of q̇₁ onto the constraint at q₁, and Newton
//! solves for the stage velocities and Λ_1 … Λ_{s−1} alone. Symmetric and reversible; the
//! stage velocities lie off the constraint by O(h^{s−1}), the end point on it. On a class
//! system with a quadratic U of diagonal Hessian it takes the class step (`spark/class.rs`),
//! elsewhere the general one (`spark/general.rs`).

mod class;
mod general;
mod response;
pub(crate) mod tableau;

use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::{GeneralStepper, Integrator, MethodInfo, Stepper};
use crate::model::mechanical::General;
use crate::model::system::{ParamSpec, System};
use crate::solver::newton::NewtonConfig;
use crate::{InputError, State, StepFailure};

/// A Lobatto IIIA–IIIB SPARK method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spark {
    /// Stages s, 2 … 5: order 2s − 2.
    pub stages: u8,
    /// Newton's settings.
    pub newton: NewtonConfig,
    /// On the paper's class with a quadratic U of diagonal Hessian, take the class step
    /// (`spark/class.rs`: the driver alone, then one linear solve for the multipliers);
    /// elsewhere solve each Newton iteration's linear system with its structure (a Schur
    /// complement on the multipliers, `spark/general.rs`) where the step is small enough for
    /// it, densely otherwise. `false` forces the general step with the dense solve of the
    /// whole system, which both are tested against.
    pub fast_path: bool,
}

impl Default for Spark {
    fn default() -> Self {
        Self { stages: 3, newton: NewtonConfig::default(), fast_path: true }
    }
}

/// The range of `stages`, as the API states it.
const STAGES: &str = "2, 3, 4 or 5";

static INFO: MethodInfo = MethodInfo {
    id: "spark",
    name: "Lobatto IIIA–IIIB SPARK (Jay)",
    params: &[ParamSpec {
        name: "stages",
        default: 3.0,
        min: 2.0,
        max: 5.0,
        min_open: false,
        max_open: false,
        description: "stages s (2, 3, 4 or 5): order 2s − 2",
    }],
    order: 4,
    reference: "L. Jay, BIT 43 (2003); odelab's Spark, GeometricIntegrators.jl's SPARKLobattoIIIAIIIB",
    implicit: true,
    composed_order_limit: None,
    class_only: None,
    instrument: false,
    symmetric_at: None,
    external: false,
    by_tableau: false,
};

impl Integrator for Spark {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(params: &[f64]) -> Result<Self, InputError> {
        let s = params[0];
        if s.fract() != 0.0 || !(2.0..=5.0).contains(&s) {
            return Err(InputError::ParamOutOfRange {
                field: "stages".into(),
                name: "stages".into(),
                value: s,
                range: STAGES.into(),
            });
        }
        Ok(Self { stages: s as u8, ..Self::default() })
    }
    fn params(&self) -> Vec<f64> {
        vec![f64::from(self.stages)]
    }
    fn general_path(&self) -> Option<Self> {
        Some(Self { fast_path: false, ..*self })
    }
    fn order(&self) -> u32 {
        2 * u32::from(self.stages) - 2
    }
    fn label(&self) -> String {
        format!("SPARK{}", self.stages)
    }
    fn symmetric(&self) -> bool {
        true
    }
}

impl Stepper for Spark {
    type Memory<const N: usize, const R: usize> = GeneralMemory<N, R>;
    #[inline]
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        mem: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        if self.fast_path
            && let Some(kappa) = class::diagonal_hessian(sys, &st.q)
        {
            return self.step_class(sys, st, mem, h, &kappa);
        }
        self.step_general(&General(sys), st, mem, h)
    }
}
