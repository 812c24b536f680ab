//! Structural properties on every registered system: constraints at every step, exact
//! energy for DD, and reversibility (`docs/model.md` §3).

use crate::common::preset_start;
use nhlab_core::BuiltIn;
use nhlab_core::measure::simulate::run_method;
use nhlab_core::{
    BaseMethod, Bucket, Integral, Method, MethodMemory, MethodSpec, Observer, Problem, RunConfig,
    State,
};

fn method(id: &str) -> Method {
    Method::from_spec(&MethodSpec::new(id)).unwrap()
}
fn dla(alpha: f64) -> Method {
    Method::from_spec(&MethodSpec::new("dla").with("alpha", alpha)).unwrap()
}

fn constraints_every_step<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    let (sys, start, h) = preset_start::<S, N, R>(0);
    for m in [
        dla(0.5),
        dla(0.4),
        dla(1.0),
        method("dla01"),
        method("leapfrog"),
        method("dd"),
        method("dd_avf"),
    ] {
        let (mut st, mut memory) = (start, m.memory());
        for k in 0..2000 {
            let prev = st;
            m.step(&sys, &mut st, &mut memory, h).unwrap();
            let residual = if matches!(m.base, BaseMethod::Dd(_) | BaseMethod::DdAvf(_)) {
                // DD imposes the constraint at the midpoint: A(q̄)(q̇₀ + q̇₁)/2 = 0.
                let z_mid = 0.5 * (prev.q[N - 1] + st.q[N - 1]);
                (sys.constraint(z_mid) * (prev.v + st.v) * 0.5).amax()
            } else {
                (sys.constraint(st.q[N - 1]) * st.v).amax()
            };
            // Round-off in A q̇ scales with |q̇|, which grows for the drifting DLA^1.
            let bound = 1e-12 * st.v.amax().max(1.0);
            assert!(
                residual <= bound,
                "{} {}: step {k}: residual {residual:e}",
                S::info().id,
                m.label()
            );
        }
    }
}

#[test]
fn constraints_hold_at_every_step() {
    for_each_system!(constraints_every_step);
}

/// Watches the energy series of a run and the state it ends in.
#[derive(Default)]
struct EnergyWatch {
    initial: f64,
    worst: f64,
    kinetic_end: f64,
    zeta_end: f64,
}

impl Observer for EnergyWatch {
    fn initial(&mut self, _: Integral, value: f64) {
        self.initial = value;
    }
    fn points(&mut self, _: Integral, bucket: Bucket) {
        self.worst = self.worst.max(bucket.max);
    }
    fn finish(&mut self, q: &[f64], v: &[f64]) {
        self.kinetic_end = 0.5 * v.iter().map(|x| x * x).sum::<f64>();
        self.zeta_end = q.last().copied().unwrap_or(f64::NAN);
    }
}

/// `m`'s largest |H − H(0)| over `steps` steps, through the driver (as a user runs it: the
/// driver keeps an angle ζ within a turn), relative to the size of H's terms: |H(0)|, or the
/// kinetic energy at the end where the motion runs away (the perturbed knife edge slides
/// 1.3·10⁶ down its plane in 10⁵ steps, and H = 0.5 is the difference of two terms of that
/// size, whose rounding alone is 10⁻¹⁰); and the final ζ, as the run started it.
fn dd_energy_error<S: BuiltIn<N, R>, const N: usize, const R: usize>(
    sys: &S,
    start: State<N, R>,
    h: f64,
    steps: u64,
    m: &Method,
) -> (f64, f64) {
    let problem = Problem {
        sys,
        start,
        step: h,
        steps,
        integrals: &[Integral::Energy],
        latitude: None,
        invariants: None,
    };
    let mut watch = EnergyWatch::default();
    let out =
        run_method(&problem, m, &RunConfig { points: 100, ..RunConfig::default() }, &mut watch);
    assert_eq!(out.error, None);
    (watch.worst / watch.initial.abs().max(watch.kinetic_end), watch.zeta_end)
}

fn dd_energy<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    let dd = method("dd");
    for (p, preset) in S::info().presets.iter().enumerate() {
        let (sys, start, h) = preset_start::<S, N, R>(p);
        let (rel, _) = dd_energy_error(&sys, start, h, 100_000, &dd);
        println!(
            "{}/{}: dd max |H − H(0)|, relative, over 1e5 steps = {rel:.2e}",
            S::info().id,
            preset.id
        );
        assert!(rel <= 1e-12, "{}/{}: relative energy error {rel:e}", S::info().id, preset.id);
    }
}

#[test]
fn dd_conserves_energy_over_1e5_steps() {
    for_each_system!(dd_energy);
}

/// On a rotating driver ζ grows without bound (to 2.3·10⁴ here). Stepped as it is, ζ is
/// stored to ulp(ζ), 4·10⁻¹² at the end, V_d and A are evaluated at that rounded angle, and
/// DD's energy error walks to 2.6·10⁻¹¹ of H over these 10⁵ steps, 25× more from
/// ζ₀ + 2π·50000. The driver takes whole turns off ζ after every step
/// (`State::take_whole_turns`), which leaves 7·10⁻¹⁴ from either start, for DD and DD-AVF.
#[test]
fn dd_energy_on_a_rotating_driver_does_not_grow_with_the_angle() {
    use nhlab_core::systems::CvtPendulum;
    assert_eq!(CvtPendulum::info().presets[3].id, "rotating-perturbed");
    for m in [method("dd"), method("dd_avf")] {
        for turns in [0.0, 50_000.0] {
            let (sys, mut start, h) = preset_start::<CvtPendulum, 3, 1>(3);
            start.q[2] += turns * std::f64::consts::TAU;
            let (rel, zeta_end) = dd_energy_error(&sys, start, h, 100_000, &m);
            println!("rotating-perturbed from ζ₀ + 2π·{turns}: {} {rel:.2e}", m.label());
            assert!(zeta_end - start.q[2] > 2e4, "the driver turns: ζ ends at {zeta_end}");
            assert!(
                rel <= 1e-12,
                "{} from ζ₀ + 2π·{turns}: relative energy error {rel:e}",
                m.label()
            );
        }
    }
}

/// One step, flip the velocity (λ unchanged), one step, flip again: distance to the start.
/// `memory` is what the start was reached with (a memory of another method is dropped).
fn round_trip<S: BuiltIn<N, R>, const N: usize, const R: usize>(
    sys: &S,
    m: &Method,
    (start, memory): (State<N, R>, MethodMemory<N, R>),
    h: f64,
) -> f64 {
    let (mut st, mut memory) = (start, memory);
    m.step(sys, &mut st, &mut memory, h).unwrap();
    st.v = -st.v;
    m.step(sys, &mut st, &mut memory, h).unwrap();
    st.v = -st.v;
    (st.q - start.q).amax().max((st.v - start.v).amax())
}

fn reversibility<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    for p in 0..S::info().presets.len() {
        let (sys, mut start, h) = preset_start::<S, N, R>(p);
        let leapfrog = method("leapfrog");
        let mut memory = leapfrog.memory();
        // Also from a generic point along the trajectory, not only the symmetric start.
        for _ in 0..2 {
            for m in [dla(0.5), method("dla01"), leapfrog, method("dd"), method("dd_avf")] {
                let d = round_trip(&sys, &m, (start, memory), h);
                assert!(d <= 1e-11, "{} {}: not reversible, {d:e}", S::info().id, m.label());
            }
            let d = round_trip(&sys, &dla(0.4), (start, memory), h);
            assert!(d > 1e-6, "{}: DLA^0.4 should not be reversible ({d:e})", S::info().id);
            for _ in 0..37 {
                leapfrog.step(&sys, &mut start, &mut memory, h).unwrap();
            }
        }
    }
}

#[test]
fn reversibility_of_every_method_on_every_system() {
    for_each_system!(reversibility);
}
