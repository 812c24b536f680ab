//! DD's energy error at round-off over very long runs. DD conserves H exactly in
//! exact arithmetic, so |H − H(0)| is pure round-off.
//!
//! `cargo run --release -p nhlab-core --example dd_roundoff -- [steps]`
//! (default 10⁸ steps of the paper's knife edge, at the paper's h = π/10 and at h = 0.31,
//! whole turns taken off ζ as the driver does). Three runs each:
//! - "DD": DD as it runs by default, its step ending in double-double (`dd::closed_form`; the
//!   state's compensations are the low parts);
//! - "plain": the same, with the compensations zeroed after every step, i.e. the state rounded
//!   to doubles;
//! - "doubles": DD's general `(q̇₁, λ)` Newton solve (`fast_path: false`), in doubles with
//!   compensated summation of q (Hairer, Lubich & Wanner, *Geometric Numerical Integration*,
//!   VIII.5), which is how DD ran before its exact end.
//!
//! At h = π/10 the discrete orbit is periodic (20 steps to a period, as is the exact one,
//! 2π): every period rounds the same numbers the same way, so in doubles the rounding errors
//! add up linearly instead of like √N. h = 0.31 is not commensurate with the period.

use nhlab_core::BuiltIn;
use nhlab_core::methods::{Dd, Memory};
use nhlab_core::systems::KnifeEdge;
use nhlab_core::{Scene, SceneRequest, State, Stepper, System, Vector};

fn run(steps: u64, h: f64, m: &Dd, compensated: bool) -> Vec<(u64, f64)> {
    let req = SceneRequest {
        system: "knife_edge".into(),
        preset: Some("paper".into()),
        ..Default::default()
    };
    let scene = Scene::resolve(&req).expect("preset");
    let sys = KnifeEdge::new(&scene.params);
    let (q, v) =
        (Vector::<3>::from_column_slice(&scene.q), Vector::<3>::from_column_slice(&scene.v));
    let mut st = State::with_continuous_multiplier(&sys, q, v).expect("regular");
    let mut memory = <Dd as Stepper>::Memory::<3, 1>::empty();
    let h0 = sys.energy(&st.q, &st.v);
    let mut worst: f64 = 0.0;
    let mut out = Vec::new();
    let mut next = 10_000;
    for k in 1..=steps {
        m.step(&sys, &mut st, &mut memory, h).expect("step");
        // As the driver does (`simulate::run`): ζ is an angle, kept within [−π, π].
        st.take_whole_turns(&mut memory);
        if !compensated {
            st.q_compensation = Vector::zeros();
            st.v_compensation = Vector::zeros();
        }
        worst = worst.max((sys.energy(&st.q, &st.v) - h0).abs());
        if k == next || k == steps {
            out.push((k, worst));
            next *= 10;
        }
    }
    out
}

fn main() {
    let steps: u64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(100_000_000);
    let dd = Dd::default();
    let doubles = Dd { fast_path: false, ..Dd::default() };
    println!("steps | h | max |H − H(0)|: DD | plain | doubles");
    for h in [std::f64::consts::PI / 10.0, 0.31] {
        let exact = run(steps, h, &dd, true);
        let plain = run(steps, h, &dd, false);
        let general = run(steps, h, &doubles, true);
        for (((k, a), (_, b)), (_, c)) in exact.iter().zip(&plain).zip(&general) {
            println!("{k} | {h:.4} | {a:.2e} | {b:.2e} | {c:.2e}");
        }
    }
}
