//! Whether a fast path biases the energy: from every state of a trajectory (taken by the
//! general path, whole turns taken off ζ as the driver does), one step of each method's fast
//! path and one of its general path, and the mean over the states of each step's energy
//! change `ΔH / (½|q̇|² + |V|)` (relative to the size of H's terms at the step's start, as
//! `tests/it/fast_path.rs` asserts it for DD and DD-AVF). A mean above round-off's (~10⁻¹⁸ per
//! step) is a bias: over 10⁸ steps it grows linearly, where unbiased rounding grows like √N.
//! The mean difference of the two steps' `q̇·δq̇` and `∇V·δq`, component by component (same
//! scale), says where it sits: driver or passenger, velocity or position. This found the two
//! biases of DD's `(σ, ε)` experiment (`git show 3afd52e:docs/benchmarks-history.md`).
//! `cargo run --release -p nhlab-core --example energy_bias` (`STEPS`, default 10⁵ per preset).

use nhlab_core::BuiltIn;
use nhlab_core::{Method, Scene, SceneRequest, State, Vector};

fn report<S: BuiltIn<N, R>, const N: usize, const R: usize>(steps: usize) {
    let info = S::info();
    let pairs = Method::all().into_iter().filter_map(|m| Some((m, m.general_path()?)));
    for (fast, general) in pairs {
        for preset in info.presets {
            let req = SceneRequest {
                system: info.id.into(),
                preset: Some(preset.id.into()),
                ..Default::default()
            };
            let scene = Scene::resolve(&req).expect("a preset resolves");
            let sys = S::new(&scene.params);
            let (q, v) = (Vector::from_column_slice(&scene.q), Vector::from_column_slice(&scene.v));
            let Some(mut st) = State::<N, R>::with_continuous_multiplier(&sys, q, v) else {
                continue;
            };
            let mut memory = general.memory();
            // The state's value, with the compensations (which carry DD's exact end where V
            // is quadratic, `dd::closed_form`); H and the size of its terms there.
            let value = |s: &State<N, R>| (s.q + s.q_compensation, s.v + s.v_compensation);
            let energy = |s: &State<N, R>| {
                let (q, v) = value(s);
                let (kinetic, potential) = (0.5 * v.norm_squared(), sys.potential(&q));
                (kinetic + potential, kinetic + potential.abs())
            };
            let (mut kinetic, mut potential) = (Vector::<N>::zeros(), Vector::<N>::zeros());
            let (mut fast_dh, mut general_dh, mut taken) = (0.0, 0.0, 0usize);
            for _ in 0..steps {
                let (h0, scale) = energy(&st);
                let ((mut a, mut a_mem), (mut b, mut b_mem)) = ((st, memory), (st, memory));
                if fast.step(&sys, &mut a, &mut a_mem, scene.step).is_err()
                    || general.step(&sys, &mut b, &mut b_mem, scene.step).is_err()
                {
                    break;
                }
                let ((qa, va), (qb, vb)) = (value(&a), value(&b));
                kinetic += vb.component_mul(&(va - vb)) / scale;
                potential += sys.gradient(&qb).component_mul(&(qa - qb)) / scale;
                fast_dh += (energy(&a).0 - h0) / scale;
                general_dh += (energy(&b).0 - h0) / scale;
                taken += 1;
                (st, memory) = (b, b_mem);
                if sys.zeta_is_angle() {
                    st.take_whole_turns(&mut memory);
                }
            }
            let per_step = |x: f64| x / taken.max(1) as f64;
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
        "| system/preset | method | steps | mean ΔH per step, fast | general | q̇·δq̇ per component | ∇V·δq per component |"
    );
    println!("|---|---|---|---|---|---|---|");
    nhlab_core::for_each_system!(report, steps);
}
