//! [`RunCost`]: what a run will cost in CPU time, estimated from the scene and the method
//! alone, before any work: nanoseconds per step ([`step_ns`]) × steps, a composition's
//! sub-steps counted (as the step limits count them).
//!
//! - A built-in system's step costs what its method's does on the slowest built-in
//!   ([`built_in_ns`], measured with `cargo bench -p nhlab-core --bench steps`, rounded up
//!   with room for a slower machine).
//! - A system given as formulas costs what its compiled code evaluates per step, on top of
//!   the method's own arithmetic: each compiled function's instructions
//!   ([`Tape::len`](crate::formula::Tape::len), a call of `sin`, `exp`, `^`… counted as
//!   [`CALL_WEIGHT`] instructions), times the evaluations of it that the method makes per
//!   sub-step ([`Evaluations`]: an explicit step one to five gradients, an implicit one a
//!   gradient and a Hessian per Newton iteration, at the iterations it typically takes and
//!   half as many again), at [`JIT_NS`] per instruction where it runs as machine code and
//!   [`TAPE_NS`] where its tape is interpreted, plus [`EVALUATION_NS`] per evaluation.
//!
//! The constants are measured (`core/examples/cost_check.rs` prints the estimate beside the
//! measured cost, method by method, for heavy formula systems) and rounded up: the estimate
//! errs on the costly side, by up to a few times for a light system. It is what a server
//! refuses a request by, never what it reports as the run's cost.

use crate::catalogue::scene::{Scene, SceneSystem};
use crate::formula::Function;
use crate::formula::tape::Op;
use crate::methods::prk::Constraint;
use crate::methods::{BaseMethod, Method};
use crate::model::custom::{Passenger, Structure};

/// Nanoseconds per instruction of a tape compiled to machine code (measured 0.3–0.5, calls
/// weighted, on a U of 1,800 characters and its derivatives).
pub const JIT_NS: f64 = 0.8;
/// Nanoseconds per instruction of a tape interpreted, one too long to compile (measured
/// 1.2–1.8).
pub const TAPE_NS: f64 = 3.0;
/// Instructions a call of an elementary function (`sin`, `exp`, `x^y`…) counts as (5–30 ns).
pub const CALL_WEIGHT: f64 = 20.0;
/// Instructions an integer power (`x^7`, a call too) counts as.
pub const POWI_WEIGHT: f64 = 8.0;
/// Nanoseconds one evaluation of a compiled function costs besides its instructions: the
/// call, its inputs and outputs.
pub const EVALUATION_NS: f64 = 30.0;

/// Nanoseconds per step of a method written in Python (`python`): the call's cost and a
/// small step's numpy work.
pub const EXTERNAL_NS: f64 = 20_000.0;

/// Accelerations a step of the `reference` method evaluates: its Dop853 solve's twelve per
/// inner step, at the ~8 inner steps a step of 0.1 takes at tolerance 10⁻¹⁵ on the built-ins'
/// time scales (measured with `core/examples/cost_check.rs`), rounded up. Its cost grows with
/// the step; a step much longer than the system's time scale is priced low.
pub const REFERENCE_EVALUATIONS: f64 = 100.0;

/// What one run costs: its steps and nanoseconds per step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunCost {
    /// Nanoseconds per step (per sub-step of a composition).
    pub ns_per_step: f64,
    /// Steps, a composition's sub-steps counted.
    pub steps: f64,
}

impl RunCost {
    /// The run's CPU time, in seconds.
    pub fn seconds(&self) -> f64 {
        self.ns_per_step * self.steps * 1e-9
    }
}

/// The cost of a run of `method` on `scene` (its step and t_end).
pub fn run_cost(scene: &Scene, method: &Method) -> RunCost {
    run_cost_of(&scene.system, method, scene.t_end / scene.step)
}

/// The cost of `steps` steps of `method` on `system` (a composition's stages multiply them).
pub fn run_cost_of(system: &SceneSystem, method: &Method, steps: f64) -> RunCost {
    RunCost { ns_per_step: step_ns(system, method), steps: steps * method.stages() as f64 }
}

/// Nanoseconds per step (per sub-step of a composition) of `method` on `system`.
pub fn step_ns(system: &SceneSystem, method: &Method) -> f64 {
    // The compiled size: a system given as formulas with 7 to 11 coordinates runs padded to 12.
    let base = built_in_ns(method) + dense_solve_ns(system.code().dof, method);
    match system.formulas() {
        None => base,
        Some(custom) => {
            let general = matches!(custom.structure, Structure::General(_));
            base + formulas_ns(&custom.structure, &Evaluations::of(method, general))
        }
    }
}

/// SPARK's nanoseconds per step on a built-in, s = 2 … 5: measured at most 626, 1372, 2599
/// and 4495 (the vertical disk, release build), about 1.4× that on the test profile.
const SPARK_NS: [f64; 4] = [2000.0, 4000.0, 7000.0, 11000.0];

/// Iterations a `prk` step is priced at: its Newton iterations (3–4 measured) and room.
const PRK_ITERATIONS: f64 = 6.0;

/// Nanoseconds per multiply–add of `prk`'s dense solve (measured 0.05–0.1 on the built-ins
/// at the sizes below, which overstate d where R < N).
const DENSE_NS: f64 = 0.25;

/// Nanoseconds a step of `prk` spends on its dense Newton system, of size s·(N + R) ≤ 2sN
/// for N coordinates: an LU (d³/3 multiply–adds) and the Jacobian's assembly (s²N³) per
/// iteration; 0 for the other methods, whose systems are small and fixed-size (priced in
/// [`built_in_ns`]).
fn dense_solve_ns(dof: usize, method: &Method) -> f64 {
    let BaseMethod::Prk(m) = method.base else { return 0.0 };
    let (s, n) = (m.tableau.stages as f64, dof as f64);
    let d = 2.0 * s * n;
    PRK_ITERATIONS * (d * d * d / 3.0 + s * s * n * n * n) * DENSE_NS
}

/// Nanoseconds per step of `method` on a built-in: the slowest built-in's, measured (a
/// run's step with its integrals, on the test profile, slower than the release build), times
/// about 1.5. A system given as formulas adds its evaluations to it.
pub fn built_in_ns(method: &Method) -> f64 {
    match method.base {
        // Measured at most 92 (the Chaplygin sleigh), 140 for DLA^α on the paper's class
        // with three coordinates.
        BaseMethod::Leapfrog(_) => 150.0,
        // 335 (the sleigh).
        BaseMethod::Dla(_) | BaseMethod::Dla01(_) | BaseMethod::Rattle(_) => 500.0,
        // 341 and 538 (the anharmonic CVT).
        BaseMethod::Dd(_) => 600.0,
        BaseMethod::DdAvf(_) => 800.0,
        // 467 (the sleigh).
        BaseMethod::Rk4(_) => 700.0,
        // Newton on (s − 1)(N + R) unknowns through a Schur complement of (s − 1)R.
        BaseMethod::Spark(m) => SPARK_NS[usize::from(m.stages.clamp(2, 5)) - 2],
        // Its dense solve is priced by size ([`dense_solve_ns`]); this is the rest.
        // Measured 330–1040 for one stage (Gauss1), 920–4150 for three (Gauss3), with the
        // dense solve.
        BaseMethod::Prk(m) => 2000.0 * m.tableau.stages as f64,
        BaseMethod::ReferenceStep(_) => REFERENCE_EVALUATIONS * 200.0,
        // A call into Python and a few numpy operations: microseconds, whatever the system.
        BaseMethod::External(_) => EXTERNAL_NS,
    }
}

/// Evaluations per step (per sub-step of a composition) of each kind of compiled function,
/// a method's step on a system given as formulas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluations {
    /// The potential (`U`; `V` on the general class): for the energy, once per step, and
    /// in a discrete gradient.
    pub potential: f64,
    /// Its gradient (`∇U`; `∇V` with `A` on the general class).
    pub gradient: f64,
    /// Its second derivatives (`∇²U`; `∇V`, `A`, `∇²V`, `∂A/∂q` on the general class).
    pub hessian: f64,
    /// The driver's terms (`V_d`, its derivatives, `A(ζ)` and `dA/dζ`), the class only.
    pub driver: f64,
}

impl Evaluations {
    /// Those of `method`'s step on the paper's class, or on the `general` one. Counted on a
    /// heavy U (each function's evaluations over 2,000 steps); those of an implicit step,
    /// which depend on its Newton iterations (two there), half as many again.
    pub fn of(method: &Method, general: bool) -> Self {
        const E: f64 = REFERENCE_EVALUATIONS;
        let (potential, gradient, hessian, driver) = match (method.base, general) {
            (BaseMethod::Leapfrog(_), false) => (1.0, 2.0, 0.0, 2.0),
            // Counted 1 (and 2 on the class): the forces at the step's end are the next
            // step's start, but not always kept.
            (BaseMethod::Leapfrog(_), true) => (1.0, 2.0, 0.0, 0.0),
            (BaseMethod::Rk4(_), false) => (1.0, 4.0, 0.0, 4.0),
            (BaseMethod::Rk4(_), true) => (1.0, 5.0, 4.0, 0.0),
            (BaseMethod::ReferenceStep(_), false) => (0.0, E, 0.0, E),
            (BaseMethod::ReferenceStep(_), true) => (0.0, E, E, 0.0),
            // Not known: a leap-frog's worth, beside the call's own cost.
            (BaseMethod::External(_), _) => (1.0, 2.0, 1.0, 2.0),
            // Counted 3 gradients and 2 Hessians (4 driver terms); RATTLE 4, 2 (2.3).
            (BaseMethod::Dla(_) | BaseMethod::Rattle(_), false) => (1.0, 6.0, 3.0, 6.0),
            // The driver alone by Newton, the passenger one linear solve.
            (BaseMethod::Dla01(_), false) => (1.0, 1.5, 0.0, 6.0),
            (BaseMethod::Dla(_) | BaseMethod::Dla01(_) | BaseMethod::Rattle(_), true) => {
                (1.0, 3.0, 3.0, 0.0)
            }
            // Counted 4 potentials, 5 gradients, 2 Hessians (5 driver terms).
            (BaseMethod::Dd(_), false) => (6.0, 7.5, 3.0, 7.5),
            (BaseMethod::Dd(_), true) => (4.5, 4.5, 3.0, 0.0),
            // Counted 2(s − 1) + 1 forces and s derivatives a step (two iterations, the end
            // point); taken at 4(s − 1), for the steps that iterate more.
            (BaseMethod::Spark(m), _) => {
                let s = f64::from(m.stages);
                (1.0, 4.0 * (s - 1.0), s, 0.0)
            }
            // s forces and derivatives per iteration and once more at the solution; one more
            // per iteration at the step's end or midpoint for those constraints.
            (BaseMethod::Prk(m), _) => {
                let s = m.tableau.stages as f64;
                let condition = if m.constraint == Constraint::Stage { 0.0 } else { 1.0 };
                let each = (PRK_ITERATIONS + 1.0) * s + PRK_ITERATIONS * condition;
                (1.0, each, each, 0.0)
            }
            // Counted 1, 7, 6 (8.6 driver terms): quadrature in the passenger.
            (BaseMethod::DdAvf(_), _) => (1.0, 10.5, 9.0, 13.0),
        };
        Self { potential, gradient, hessian, driver }
    }

    /// Evaluations in all.
    pub fn total(&self) -> f64 {
        self.potential + self.gradient + self.hessian + self.driver
    }
}

/// Nanoseconds per step that evaluating the compiled functions of `structure` costs at
/// `evaluations`.
pub fn formulas_ns(structure: &Structure, evaluations: &Evaluations) -> f64 {
    let e = evaluations;
    match structure {
        Structure::Class { compiled, .. } => {
            let passenger = match &compiled.passenger {
                Passenger::Quadratic { h, .. } => {
                    // Constants: a matrix–vector product per gradient, in the method's code.
                    let n = h.len() as f64;
                    (e.potential + e.gradient) * n * JIT_NS
                }
                Passenger::General(p) => {
                    e.potential * function_ns(&p.u)
                        + e.gradient * function_ns(&p.gradient)
                        + e.hessian * function_ns(&p.hessian)
                }
            };
            passenger + e.driver * function_ns(&compiled.driver) + e.total() * EVALUATION_NS
        }
        Structure::General(g) => {
            e.potential * function_ns(&g.potential)
                + e.gradient * function_ns(&g.forces)
                + e.hessian * function_ns(&g.terms)
                + e.total() * EVALUATION_NS
        }
    }
}

/// Nanoseconds one evaluation of `f` costs: its weighted instructions at the speed of its
/// code (machine code, or the tape interpreted).
pub fn function_ns(f: &Function) -> f64 {
    let per_instruction = if f.is_native() { JIT_NS } else { TAPE_NS };
    weighted_instructions(f) * per_instruction
}

/// The instructions of `f`'s tape, a call of an elementary function counted as
/// [`CALL_WEIGHT`] and an integer power as [`POWI_WEIGHT`].
pub fn weighted_instructions(f: &Function) -> f64 {
    let tape = f.tape();
    let powi = tape.instructions().iter().filter(|i| matches!(i.op, Op::PowI(..))).count();
    tape.len() as f64
        + (CALL_WEIGHT - 1.0) * tape.calls() as f64
        + (POWI_WEIGHT - 1.0) * powi as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::catalogue::scene::SceneRequest;
    use crate::model::custom::FormulaSpec;
    use crate::{MethodSpec, SystemRequest};

    fn method(id: &str, composition: Option<&str>) -> Method {
        let spec = MethodSpec::new(id);
        let spec = match composition {
            Some(c) => spec.composed(c),
            None => spec,
        };
        Method::from_spec(&spec).expect("a valid method")
    }

    /// A skate in a bowl whose U is `terms` cosines beside `½|x|²`.
    fn bowl(terms: usize, native: bool) -> Scene {
        let u = (0..terms).fold("0.5*(x^2 + y^2)".to_owned(), |u, k| {
            format!("{u} + 0.001*cos({}*x - {}*y)", 1 + k % 7, 2 + k % 5)
        });
        let spec = FormulaSpec {
            name: "bowl".into(),
            passenger: vec!["x".into(), "y".into()],
            driver: "theta".into(),
            parameters: vec![("eps".into(), 0.1)],
            passenger_potential: u,
            driver_potential: "0".into(),
            constraints: vec![vec!["-sin(theta)".into(), "cos(theta) - eps".into()]],
        };
        let limits = crate::CustomLimits { native, ..Default::default() };
        let req = SceneRequest {
            system: SystemRequest::Formulas(spec),
            q: Some(vec![0.0, 0.0, 1.0]),
            v: Some(vec![0.0, 0.0, 1.0]),
            step: Some(0.1),
            t_end: Some(100.0),
            ..Default::default()
        };
        Scene::resolve_within(&req, &limits).expect("a valid scene")
    }

    #[test]
    fn a_built_in_costs_its_methods_constant_times_the_steps_and_stages() {
        let req = SceneRequest {
            system: "cvt".into(),
            preset: Some("default".into()),
            step: Some(0.1),
            t_end: Some(1000.0),
            ..Default::default()
        };
        let scene = Scene::resolve(&req).expect("cvt resolves");
        let lf = run_cost(&scene, &method("leapfrog", None));
        assert_eq!((lf.ns_per_step, lf.steps), (built_in_ns(&method("leapfrog", None)), 10_000.0));
        assert!((lf.seconds() - lf.ns_per_step * 1e-5).abs() < 1e-12);
        let composed = run_cost(&scene, &method("dla", Some("p8s15")));
        assert_eq!(composed.steps, 150_000.0, "15 sub-steps per step");
    }

    #[test]
    fn a_formula_system_costs_more_the_longer_its_formulas_and_more_interpreted() {
        let dla = method("dla", None);
        let small = step_ns(&bowl(1, true).system, &dla);
        let large = step_ns(&bowl(60, true).system, &dla);
        let interpreted = step_ns(&bowl(60, false).system, &dla);
        assert!(small > built_in_ns(&dla), "{small}");
        assert!(large > 10.0 * (small - built_in_ns(&dla)), "{small} {large}");
        // Without machine code (the JIT not built in, or `NHLAB_JIT=off`), both run on the
        // interpreter and cost the same.
        if crate::formula::native_code_status().native() {
            assert!(interpreted > 2.0 * large, "{large} {interpreted}");
        } else {
            assert_eq!(interpreted, large);
        }
        // An explicit step evaluates no Hessian and fewer gradients than Newton's.
        let lf = step_ns(&bowl(60, true).system, &method("leapfrog", None));
        assert!(lf < large / 2.0, "{lf} {large}");
        // The instructions are weighted: the 35 distinct cosines (of 60 terms, some the same)
        // cost more than as many additions would.
        let Some(custom) = bowl(60, true).system.formulas().map(|c| c.structure.clone()) else {
            panic!("a system given as formulas")
        };
        let Structure::Class { compiled, .. } = custom else { panic!("the paper's class") };
        let Passenger::General(p) = &compiled.passenger else { panic!("not quadratic") };
        let (len, calls) = (p.u.tape().len() as f64, p.u.tape().calls() as f64);
        assert!(calls >= 35.0, "{calls} calls");
        assert_eq!(weighted_instructions(&p.u), len + (CALL_WEIGHT - 1.0) * calls);
    }
}
