//! Shared test helpers: `for_each_system!` callable unqualified, typed access to presets, and
//! the comparison of one step of two methods from the same state.

use nhlab_core::BuiltIn;
use nhlab_core::{State, Vector};
use proptest::test_runner::{FailurePersistence, FileFailurePersistence};
use std::f64::consts::FRAC_PI_2;

/// `nhlab_core::for_each_system!`, callable unqualified from every test module (`main.rs`
/// declares this module `#[macro_use]`, ahead of the others).
#[macro_export]
macro_rules! for_each_system {
    ($($t:tt)*) => {
        nhlab_core::for_each_system!($($t)*)
    };
}

/// Whether formulas run as machine code in this test process, as the build and the
/// environment say: the `jit` feature, and no `NHLAB_JIT=off` (which `scripts/test` sets for
/// its pass on the interpreter).
pub fn machine_code() -> bool {
    cfg!(feature = "jit") && std::env::var_os("NHLAB_JIT").is_none_or(|v| v != "off")
}

/// The size of a state (max norm of q, q̇ and λ, at least 1), to compare steps relative to.
pub fn size<const N: usize, const R: usize>(st: &State<N, R>) -> f64 {
    st.q.amax().max(st.v.amax()).max(st.lambda.amax()).max(1.0)
}

/// `system/preset method`: the case a test's line or failure is about.
pub fn case<S: BuiltIn<N, R>, const N: usize, const R: usize>(
    preset: usize,
    method: &str,
) -> String {
    format!("{}/{} {method}", S::info().id, S::info().presets[preset].id)
}

/// How far one step `a` lands from another `b` taken from the same state: the max norm of
/// their q, q̇ and λ differences, relative to `b`'s [`size`].
pub fn step_difference<const N: usize, const R: usize>(a: &State<N, R>, b: &State<N, R>) -> f64 {
    let diff = (a.q - b.q).amax().max((a.v - b.v).amax()).max((a.lambda - b.lambda).amax());
    diff / size(b)
}

/// The largest [`step_difference`] between one step of `a` and one of `b` from each of `steps`
/// states of `b`'s trajectory from `start`. Steps are compared one at a time from the same
/// state, not as whole trajectories, whose sensitivity would amplify round-off. Each step
/// starts from the state with the memory `b`'s last step left (`memory` at the start): both
/// get a copy of the pair, and the trajectory carries `b`'s.
pub fn worst_step_difference<M: Copy, const N: usize, const R: usize>(
    start: State<N, R>,
    memory: M,
    steps: usize,
    mut a: impl FnMut(&mut State<N, R>, &mut M),
    mut b: impl FnMut(&mut State<N, R>, &mut M),
) -> f64 {
    let (mut st, mut mem, mut worst) = (start, memory, 0.0_f64);
    for _ in 0..steps {
        let ((mut x, mut x_mem), (mut y, mut y_mem)) = ((st, mem), (st, mem));
        a(&mut x, &mut x_mem);
        b(&mut y, &mut y_mem);
        worst = worst.max(step_difference(&x, &y));
        (st, mem) = (y, y_mem);
    }
    worst
}

/// The system built from preset `index` (params applied) and its start state.
pub fn preset_start<S: BuiltIn<N, R>, const N: usize, const R: usize>(
    index: usize,
) -> (S, State<N, R>, f64) {
    let info = S::info();
    let p = &info.presets[index];
    let sys = S::new(&info.preset_params(p));
    let st = State::with_continuous_multiplier(
        &sys,
        Vector::<N>::from_column_slice(p.q),
        Vector::<N>::from_column_slice(p.v),
    )
    .unwrap();
    (sys, st, p.step)
}

/// The observed order: the least-squares slope of log(error) against log(h), the errors at
/// or below `floor` (round-off, or the reference's accuracy) left out; at least 4 points.
pub fn slope(hs: &[f64], errors: &[f64], floor: f64) -> f64 {
    let pts: Vec<(f64, f64)> =
        hs.iter().zip(errors).filter(|(_, e)| **e > floor).map(|(h, e)| (h.ln(), e.ln())).collect();
    assert!(pts.len() >= 4, "too few points above {floor:e}: {errors:?}");
    let n = pts.len() as f64;
    let (mx, my) =
        (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    sxy / sxx
}

/// Knife edge, ε = 0, from q(0) = (0, 0, π/2), q̇(0) = (0, 0, 1).
pub fn knife_exact(t: f64) -> (Vector<3>, Vector<3>) {
    let (s, c) = t.sin_cos();
    let q =
        Vector::<3>::new(1.0 - c - s * s / 2.0, t / 2.0 + (2.0 * t).sin() / 4.0 - s, FRAC_PI_2 + t);
    let v = Vector::<3>::new(s - s * c, 0.5 + (2.0 * t).cos() / 2.0 - c, 1.0);
    (q, v)
}

/// Rolling disk from q(0) = 0, q̇(0) = (−1, 0, 1, 1): the heading turns at unit rate and
/// the contact point runs on the unit circle.
pub fn disk_exact(t: f64) -> (Vector<4>, Vector<4>) {
    let (s, c) = t.sin_cos();
    (Vector::<4>::new(-s, c - 1.0, t, t), Vector::<4>::new(-c, -s, 1.0, 1.0))
}

/// Where proptest keeps the failing cases it has found: `<module>.proptest-regressions` beside
/// the module's file (`formulas.rs` → `formulas.proptest-regressions`). Proptest's default,
/// `SourceParallel`, looks above the source file for a `lib.rs` or `main.rs`, would find this
/// binary's `main.rs` and use `core/tests/proptest-regressions/<module>.txt` instead.
pub fn regressions() -> Option<Box<dyn FailurePersistence>> {
    Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions")))
}
