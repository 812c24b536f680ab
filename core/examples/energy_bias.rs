//! Whether a fast path biases the energy: from every state of a trajectory (taken by the
//! general path), one step of each method's fast path and one of its general path, and the
//! mean over the states of each step's energy change, `H(q₁, q̇₁) − H(q₀, q̇₀)`, for both.
//! A mean that is not at round-off's (a few 10⁻¹⁹ of H per step here) is a bias: over 10⁸
//! steps it grows linearly, where unbiased rounding grows like √N. The difference of the two
//! steps' `q̇·δq̇` and `∇V·δq`, component by component, says where it sits (driver or
//! passenger, velocity or position). This found the two biases of DD's `(σ, ε)` experiment
//! (`docs/benchmarks.md`).
//! `cargo run --release -p nhlab-core --example energy_bias` (`STEPS`, default 10⁵ per preset).

use nhlab_core::systems::*;
use nhlab_core::{Method, MethodSpec, State, System, Vector, method_infos};

fn report<S: System<N, R>, const N: usize, const R: usize>(steps: usize) {
    let info = S::info();
    // The paper's five (DLA^α at α = ½ and 0.4), then the other methods.
    let mut all = Method::paper_five().to_vec();
    for i in method_infos() {
        if !all.iter().any(|m| m.info().id == i.id) {
            all.extend(Method::from_spec(&MethodSpec::new(i.id)));
        }
    }
    let methods = all.into_iter().filter_map(|m| Some((m, m.general_path()?)));
    for (fast, general) in methods {
        for preset in info.presets {
            let mut params: Vec<f64> = info.params.iter().map(|s| s.default).collect();
            for (name, value) in preset.params {
                if let Some(i) = info.params.iter().position(|s| s.name == *name) {
                    params[i] = *value;
                }
            }
            let sys = S::new(&params);
            let (q, v) = (Vector::from_column_slice(preset.q), Vector::from_column_slice(preset.v));
            let Some(mut st) = State::<N, R>::with_continuous_multiplier(&sys, q, v) else {
                continue;
            };
            let energy = |s: &State<N, R>| 0.5 * s.v.norm_squared() + sys.potential(&s.q);
            let scale = energy(&st).abs().max(f64::MIN_POSITIVE);
            let (mut kinetic, mut potential) = (Vector::<N>::zeros(), Vector::<N>::zeros());
            let (mut fast_dh, mut general_dh, mut taken) = (0.0, 0.0, 0usize);
            for _ in 0..steps {
                let (mut a, mut b) = (st, st);
                if fast.step(&sys, &mut a, preset.step).is_err()
                    || general.step(&sys, &mut b, preset.step).is_err()
                {
                    break;
                }
                let g = sys.gradient(&b.q);
                kinetic += b.v.component_mul(&(a.v - b.v));
                potential += g.component_mul(&(a.q - b.q));
                fast_dh += energy(&a) - energy(&st);
                general_dh += energy(&b) - energy(&st);
                taken += 1;
                st = b;
                // As the driver does: a rotating ζ left to grow loses digits (and with them
                // the energy), whatever the path.
                if S::ZETA_IS_ANGLE {
                    st.take_whole_turns();
                }
            }
            let per_step = |x: f64| x / (taken.max(1) as f64 * scale);
            let row = |v: &Vector<N>| {
                v.iter().map(|x| format!("{:+.1e}", per_step(*x))).collect::<Vec<_>>().join(" ")
            };
            println!(
                "| {}/{} | {} | {taken} | {:+.1e} | {:+.1e} | {} | {} |",
                info.id,
                preset.id,
                fast.label(),
                per_step(fast_dh),
                per_step(general_dh),
                row(&kinetic),
                row(&potential),
            );
        }
    }
}

fn main() {
    let steps = std::env::var("STEPS").ok().and_then(|s| s.parse().ok()).unwrap_or(100_000);
    println!(
        "| system/preset | method | steps | mean ΔH/H per step, fast | general | q̇·δq̇ per component | ∇V·δq per component |"
    );
    println!("|---|---|---|---|---|---|---|");
    report::<KnifeEdge, 3, 1>(steps);
    report::<CvtPendulum, 3, 1>(steps);
    report::<Cvt, 3, 1>(steps);
    report::<Particle, 3, 1>(steps);
    report::<RollingDisk, 4, 2>(steps);
    report::<MobileRobot, 4, 2>(steps);
}
