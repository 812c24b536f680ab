//! The driver's contract: step counts, buckets, typed failures that keep completed buckets,
//! non-finite detection and cancellation.

use nhlab_core::BuiltIn;
use nhlab_core::measure::simulate::{Problem, run};
use nhlab_core::methods::{Memory, Recall};
use nhlab_core::systems::KnifeEdge;
use nhlab_core::{
    Bucket, Collect, Integral, Observer, RunConfig, RunError, State, StepFailure, Stepper, System,
    Vector,
};
use std::ops::ControlFlow;

/// A method that behaves like explicit Euler until step `fail_at`, then fails or returns NaN.
#[derive(Clone, Copy)]
struct Faulty {
    fail_at: u64,
    nan: bool,
}
/// [`Faulty`] remembers nothing.
#[derive(Debug, Clone, Copy)]
struct Nothing;
impl<const N: usize, const R: usize> Memory<N, R> for Nothing {
    fn empty() -> Self {
        Nothing
    }
}
impl<const N: usize, const R: usize> Recall<N, R> for Nothing {}
thread_local! {
    // Tests run on separate threads, so each counts its own steps.
    static STEP: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

impl Stepper for Faulty {
    type Memory<const N: usize, const R: usize> = Nothing;
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        _: &mut Nothing,
        h: f64,
    ) -> Result<(), StepFailure> {
        let k = STEP.get() + 1;
        STEP.set(k);
        if k == self.fail_at {
            if self.nan {
                st.q[0] = f64::NAN;
                return Ok(());
            }
            return Err(StepFailure::NewtonDiverged { iterations: 20, increment: 1.0 });
        }
        st.q += h * st.v;
        st.v -= h * sys.gradient(&st.q);
        Ok(())
    }
}

fn problem(sys: &KnifeEdge, steps: u64) -> Problem<'_, KnifeEdge, 3, 1> {
    let start = State::with_continuous_multiplier(
        sys,
        Vector::<3>::new(0.0, 0.0, 1.0),
        Vector::<3>::new(0.0, 0.0, 1.0),
    )
    .unwrap();
    Problem {
        sys,
        start,
        step: 0.01,
        steps,
        integrals: &[Integral::Energy, Integral::DriverEnergy],
        latitude: None,
        invariants: None,
    }
}

#[test]
fn failure_names_step_and_time_and_keeps_completed_buckets() {
    for nan in [false, true] {
        STEP.set(0);
        let sys = KnifeEdge { epsilon: 0.0 };
        let mut c = Collect::default();
        let out = run(
            &problem(&sys, 1000),
            &Faulty { fail_at: 537, nan },
            &RunConfig { points: 10, progress_every: 64, ..RunConfig::default() },
            &mut c,
        );
        let failure = if nan {
            StepFailure::NonFinite
        } else {
            StepFailure::NewtonDiverged { iterations: 20, increment: 1.0 }
        };
        assert_eq!(out.steps, 536);
        match out.error {
            Some(RunError::Step { step: 537, t, failure: f }) => {
                assert!((t - 5.36).abs() < 1e-12);
                assert_eq!(f, failure);
            }
            other => panic!("{other:?}"),
        }
        // 10 buckets of 100 steps: the 5 completed ones, no NaN anywhere.
        let e: &Vec<Bucket> = &c.series[&Integral::Energy];
        assert_eq!(e.len(), 5);
        assert!(e.iter().all(|b| b.mean.is_finite() && b.max.is_finite()));
        assert_eq!(e.last().unwrap().t, 5.0);
        assert!(out.error.unwrap().to_string().contains("step 537 (t = 5.36"));
    }
}

struct StopAt(u64, Collect);
impl Observer for StopAt {
    fn points(&mut self, i: Integral, b: Bucket) {
        self.1.points(i, b)
    }
    fn progress(&mut self, done: u64, _t: f64) -> ControlFlow<()> {
        if done >= self.0 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }
}

#[test]
fn observer_cancels() {
    STEP.set(0);
    let sys = KnifeEdge { epsilon: 0.0 };
    let mut obs = StopAt(300, Collect::default());
    let out = run(
        &problem(&sys, 100_000),
        &Faulty { fail_at: 0, nan: false },
        &RunConfig { points: 1000, progress_every: 100, ..RunConfig::default() },
        &mut obs,
    );
    assert_eq!(out.steps, 300);
    assert!(matches!(out.error, Some(RunError::Cancelled { step: 300, .. })));
    assert_eq!(obs.1.series[&Integral::Energy].len(), 3);
}

#[test]
fn successful_run_delivers_every_bucket_once() {
    let sys = KnifeEdge { epsilon: 0.0 };
    let mut c = Collect::default();
    let lf = nhlab_core::methods::Leapfrog;
    let out = run(
        &problem(&sys, 30_001),
        &lf,
        &RunConfig { points: 1000, progress_every: 4096, ..RunConfig::default() },
        &mut c,
    );
    assert_eq!(out, nhlab_core::RunOutcome { steps: 30_001, error: None });
    for series in c.series.values() {
        assert_eq!(series.len(), 1000);
        assert!((series.last().unwrap().t - 300.01).abs() < 1e-9);
        assert!(series.windows(2).all(|w| w[0].t < w[1].t));
    }
    assert_eq!(c.initial[&Integral::DriverEnergy], 0.5);
}

#[test]
fn a_diverging_run_says_so() {
    use nhlab_core::{Method, Scene, SceneRequest};
    // h = 2.5 on the CVT is far beyond every method's stability limit.
    let req = SceneRequest {
        system: "cvt".into(),
        step: Some(2.5),
        t_end: Some(1000.0),
        ..Default::default()
    };
    let scene = Scene::resolve(&req).unwrap().prepare(None).unwrap();
    let mut diverged = 0;
    for m in Method::paper_five() {
        let mut c = Collect::default();
        let out = scene.run(&m, &RunConfig::default(), &mut c);
        println!("{}: {:?}", m.label(), out.error);
        if let Some(e) = out.error {
            diverged += 1;
            assert!(e.to_string().contains("diverged") || e.to_string().contains("Newton"), "{e}");
        }
        for s in c.series.values() {
            assert!(s.iter().all(|b| b.mean.is_finite() && b.mean < 1e200), "{}", m.label());
        }
    }
    assert!(diverged >= 1);
}

/// The driver keeps an angle ζ within a turn (`State::take_whole_turns`) and hands the
/// final state over with the turns put back: the same as stepping by hand, which keeps ζ
/// unbounded, to the rounding of ζ, which the motion amplifies (here 480 rad, 76 turns: 10⁻¹¹,
/// 0.3–2.8·10⁻¹¹ as Newton's stopping rule varies, `whole_turns.rs`; over 10⁵ steps the two
/// drift apart by 10⁻⁷, mostly the hand-stepped run's rounding).
#[derive(Default)]
struct Final(Vec<f64>, Vec<f64>);
impl Observer for Final {
    fn points(&mut self, _: Integral, _: Bucket) {}
    fn finish(&mut self, q: &[f64], v: &[f64]) {
        (self.0, self.1) = (q.to_vec(), v.to_vec());
    }
}

#[test]
fn the_final_state_counts_the_turns_taken_off() {
    use nhlab_core::methods::Dd;
    use nhlab_core::systems::CvtPendulum;
    let sys = CvtPendulum { epsilon: 0.5 };
    let p = &CvtPendulum::info().presets[3];
    let start = State::with_continuous_multiplier(
        &sys,
        Vector::<3>::from_column_slice(p.q),
        Vector::<3>::from_column_slice(p.v),
    )
    .unwrap();
    let problem = Problem {
        sys: &sys,
        start,
        step: 0.1,
        steps: 2000,
        integrals: &[],
        latitude: None,
        invariants: None,
    };
    let dd = Dd::default();
    let mut end = Final::default();
    assert_eq!(run(&problem, &dd, &RunConfig::default(), &mut end).error, None);
    let (mut by_hand, mut memory) = (start, <Dd as Stepper>::Memory::<3, 1>::empty());
    for _ in 0..2000 {
        dd.step(&sys, &mut by_hand, &mut memory, 0.1).unwrap();
    }
    assert!(by_hand.q[2] > 400.0, "the driver turned: ζ = {}", by_hand.q[2]);
    let gap = (Vector::<3>::from_column_slice(&end.0) - by_hand.q).amax();
    assert!(gap < 1e-10, "{gap:e}");
    assert!((Vector::<3>::from_column_slice(&end.1) - by_hand.v).amax() < 1e-10);
}

/// Euler steps that take `0.5 ms` each, as a step of a heavy system given as formulas may.
#[derive(Clone, Copy)]
struct Slow;
impl Stepper for Slow {
    type Memory<const N: usize, const R: usize> = Nothing;
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        _: &mut Nothing,
        h: f64,
    ) -> Result<(), StepFailure> {
        let start = std::time::Instant::now();
        while start.elapsed() < std::time::Duration::from_micros(500) {
            std::hint::spin_loop();
        }
        st.q += h * st.v;
        st.v -= h * sys.gradient(&st.q);
        Ok(())
    }
}

/// Cancels at the first progress call after `at`.
struct CancelAfter(std::time::Instant);
impl Observer for CancelAfter {
    fn points(&mut self, _: Integral, _: Bucket) {}
    fn progress(&mut self, _done: u64, _t: f64) -> ControlFlow<()> {
        if std::time::Instant::now() >= self.0 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

#[test]
fn a_paced_run_of_slow_steps_notices_a_stop_within_milliseconds() {
    let sys = KnifeEdge { epsilon: 0.0 };
    let paced = RunConfig { paced: true, ..RunConfig::default() };
    let at = std::time::Instant::now() + std::time::Duration::from_millis(30);
    let out = run(&problem(&sys, 1_000_000), &Slow, &paced, &mut CancelAfter(at));
    let late = at.elapsed();
    assert!(matches!(out.error, Some(RunError::Cancelled { .. })), "{:?}", out.error);
    // Every 1024 steps of 0.5 ms, it would have taken half a second; paced, ~5 ms (a loaded
    // machine may hold the thread longer: the margin is wide).
    assert!(late < std::time::Duration::from_millis(300), "stopped {late:?} after the stop");
    assert!(out.steps < 1024, "{} steps", out.steps);
}

#[test]
fn a_run_past_its_time_limit_ends_with_the_limit_and_where_it_stopped() {
    let sys = KnifeEdge { epsilon: 0.0 };
    let limit = std::time::Duration::from_millis(20);
    for paced in [true, false] {
        let cfg = RunConfig {
            paced,
            progress_every: 16,
            time_limit: Some(limit),
            ..RunConfig::default()
        };
        let mut c = Collect::default();
        let out = run(&problem(&sys, 1_000_000), &Slow, &cfg, &mut c);
        let Some(RunError::TimeLimit { step, t, limit: seconds }) = out.error else {
            panic!("{:?}", out.error)
        };
        assert_eq!((step, seconds), (out.steps, 0.02));
        // Each step takes at least 0.5 ms: at most 40 fit in the limit, and the limit is
        // looked at within 16 more (fewer on a loaded machine, where steps take longer).
        assert!((1..=56).contains(&step), "{step} steps");
        assert!((t - step as f64 * 0.01).abs() < 1e-9);
        let message = out.error.unwrap().to_string();
        assert!(message.starts_with("time limit: ") && message.contains("0.02 s"), "{message}");
    }
    // Within its limit, a run ends as usual.
    let cfg = RunConfig { paced: true, time_limit: Some(limit * 100), ..RunConfig::default() };
    let out = run(&problem(&sys, 10), &Slow, &cfg, &mut Collect::default());
    assert_eq!(out, nhlab_core::RunOutcome { steps: 10, error: None });
}
