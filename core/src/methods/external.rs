//! `python`: a method whose step is code outside nhlab, registered in the running process
//! (`docs/own-methods.md`). The nhlab Python package registers a researcher's
//! `nhlab.Method` here and names it in a request as `{"id": "python", "handle": k}`; the run
//! loop then steps it like any method of the list, so every instrument measures it. A server
//! process registers nothing: there the id is refused, and users' code never runs in it.
//!
//! The step sees the system through [`SystemView`] (slices in, slices out, sizes erased) and
//! returns the new `(q, q̇)`; λ is left as it was (no measurement reads it). The view reaches
//! the invariants a system declares through the system itself (`System::invariants`,
//! `Mechanical::invariants`: a system given as formulas is built carrying those of its spec),
//! so every caller of a step, a run as the property checks, hands them over with it. What the
//! outside code keeps between steps is its own, named by *keys* that this method's memory
//! ([`ExternalMemory`]) holds: each step reads what the step before left under one key and
//! leaves its own under a new one, so a memory copied to two branches (the property checks
//! step twice from one point) gives each the same start. A step that starts from a
//! configuration q other than where the last one ended gets key 0, nothing, as the built-ins'
//! memories do for a state moved from outside; a velocity changed from outside keeps the
//! key, as it keeps the built-ins' λ (the reversibility check flips q̇ and steps on).

mod view;

pub use view::{ClassView, SystemView};

use crate::methods::general_memory::GeneralMemory;
use crate::methods::integrator::{GeneralStepper, Integrator, MethodInfo, Stepper};
use crate::methods::memory::{Memory, Recall};
use crate::model::mechanical::Mechanical;
use crate::model::system::{ParamSpec, System};
use crate::{InputError, State, StepFailure, Vector};
use std::collections::{HashMap, HashSet};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError, RwLock};

/// A step written outside nhlab, as the registry holds it.
pub trait ExternalStep: Send + Sync {
    /// Its label in tables and plots.
    fn name(&self) -> &str;
    /// The order its author claims (work–precision measures it).
    fn order(&self) -> u32;
    /// Whether its author declares it symmetric, which lets it be composed (the scorecard
    /// measures whether it is).
    fn symmetric(&self) -> bool;
    /// Replaces `(q, v)` by the state one step `h` later on `sys`, reading what a step left
    /// under the key `from` (0: nothing) and leaving its own under the new key `to`. An
    /// error is the run's failure, in words.
    fn step(
        &self,
        sys: &dyn SystemView,
        keys: (u64, u64),
        q: &mut [f64],
        v: &mut [f64],
        h: f64,
    ) -> Result<(), String>;
}

/// The steps registered in this process, by handle (never reused).
static REGISTRY: RwLock<Option<HashMap<u32, Arc<dyn ExternalStep>>>> = RwLock::new(None);
static NEXT_HANDLE: AtomicU64 = AtomicU64::new(1);
static NEXT_KEY: AtomicU64 = AtomicU64::new(1);

/// Registers `step`; its handle names it in a request until [`unregister`].
pub fn register(step: Arc<dyn ExternalStep>) -> u32 {
    let handle = u32::try_from(NEXT_HANDLE.fetch_add(1, Ordering::Relaxed)).unwrap_or(u32::MAX);
    let mut registry = REGISTRY.write().unwrap_or_else(PoisonError::into_inner);
    registry.get_or_insert_with(HashMap::new).insert(handle, step);
    handle
}

/// Forgets the step registered under `handle` (a run still stepping it fails).
pub fn unregister(handle: u32) {
    let removed = {
        let mut registry = REGISTRY.write().unwrap_or_else(PoisonError::into_inner);
        registry.as_mut().and_then(|map| map.remove(&handle))
    };
    // Dropped after the lock is released: dropping the step may run outside code (a Python
    // object's finaliser) that registers or steps another method.
    drop(removed);
}

fn lookup(handle: u32) -> Option<Arc<dyn ExternalStep>> {
    let registry = REGISTRY.read().unwrap_or_else(PoisonError::into_inner);
    registry.as_ref()?.get(&handle).cloned()
}

/// A failure's message kept for the life of the process ([`StepFailure`] is `Copy`): each
/// distinct message once, at most [`MAX_MESSAGES`] of them.
fn intern(message: String) -> &'static str {
    const MAX_MESSAGES: usize = 4096;
    static MESSAGES: Mutex<Option<HashSet<&'static str>>> = Mutex::new(None);
    let mut messages = MESSAGES.lock().unwrap_or_else(PoisonError::into_inner);
    let messages = messages.get_or_insert_with(HashSet::new);
    if let Some(kept) = messages.get(message.as_str()) {
        return kept;
    }
    if messages.len() >= MAX_MESSAGES {
        return "the step failed (its message is not kept: too many distinct failures)";
    }
    let kept: &'static str = Box::leak(message.into_boxed_str());
    messages.insert(kept);
    kept
}

/// A registered step as a method of the list.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct External {
    /// Its handle in the registry.
    pub handle: u32,
    /// The order claimed, read at registration.
    order: u32,
    /// Declared symmetric, read at registration.
    symmetric: bool,
}

static INFO: MethodInfo = MethodInfo {
    id: "python",
    name: "A method written in Python (the nhlab package only)",
    params: &[ParamSpec {
        name: "handle",
        default: 0.0,
        min: 0.0,
        max: 4_294_967_295.0,
        min_open: false,
        max_open: false,
        description: "the handle under which the nhlab Python package registered the method",
    }],
    order: 2,
    reference: "its author (docs/own-methods.md)",
    implicit: false,
    composed_order_limit: None,
    class_only: None,
    instrument: false,
    symmetric_at: None,
    external: true,
    by_tableau: false,
};

impl Integrator for External {
    fn info() -> &'static MethodInfo {
        &INFO
    }
    fn from_params(params: &[f64]) -> Result<Self, InputError> {
        let refused = |why: &str| InputError::NotApplicable {
            field: "handle".into(),
            message: format!(
                "{why}: methods written in Python run only in the nhlab Python package \
                 (nhlab.Method), never in a server"
            ),
        };
        let value = params.first().copied().unwrap_or(0.0);
        if value.fract() != 0.0 {
            return Err(refused(&format!("handle {value} is not a whole number")));
        }
        // A whole number within the parameter's range.
        let handle = value as u32;
        let step = lookup(handle).ok_or_else(|| {
            refused(&format!("no method written in Python is registered under handle {handle}"))
        })?;
        Ok(Self { handle, order: step.order(), symmetric: step.symmetric() })
    }
    fn params(&self) -> Vec<f64> {
        vec![f64::from(self.handle)]
    }
    fn order(&self) -> u32 {
        self.order
    }
    fn label(&self) -> String {
        lookup(self.handle).map_or_else(|| format!("python#{}", self.handle), |s| s.name().into())
    }
    fn symmetric(&self) -> bool {
        self.symmetric
    }
}

/// What [`External`] carries between steps: the key under which the last step left its
/// memory, and the configuration where that step ended.
#[derive(Debug, Clone, Copy)]
pub struct ExternalMemory<const N: usize, const R: usize> {
    key: u64,
    q: Vector<N>,
}

impl<const N: usize, const R: usize> Recall<N, R> for ExternalMemory<N, R> {
    fn moved(&mut self, from: &Vector<N>, to: &Vector<N>) {
        if self.q == *from {
            self.q = *to;
        }
    }
}

impl<const N: usize, const R: usize> Memory<N, R> for ExternalMemory<N, R> {
    fn empty() -> Self {
        Self { key: 0, q: Vector::repeat(f64::NAN) }
    }
}

impl External {
    /// The step on a system seen through `view`.
    fn step_on<const N: usize, const R: usize>(
        &self,
        view: &dyn SystemView,
        st: &mut State<N, R>,
        memory: &mut ExternalMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let step = lookup(self.handle)
            .ok_or(StepFailure::External("the method was unregistered during the run"))?;
        let from = if memory.q == st.q { memory.key } else { 0 };
        let to = NEXT_KEY.fetch_add(1, Ordering::Relaxed);
        let (mut q, mut v) = (st.q, st.v);
        step.step(view, (from, to), q.as_mut_slice(), v.as_mut_slice(), h)
            .map_err(|message| StepFailure::External(intern(message)))?;
        if !q.iter().chain(v.iter()).all(|x| x.is_finite()) {
            return Err(StepFailure::NonFinite);
        }
        (st.q, st.v) = (q, v);
        (st.q_compensation, st.v_compensation) = (Vector::zeros(), Vector::zeros());
        (memory.key, memory.q) = (to, q);
        Ok(())
    }
}

impl Stepper for External {
    type Memory<const N: usize, const R: usize> = ExternalMemory<N, R>;
    fn step<S: System<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        memory: &mut ExternalMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        self.step_on(&view::Class(sys), st, memory, h)
    }
}

impl GeneralStepper for External {
    fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
        &self,
        sys: &S,
        st: &mut State<N, R>,
        memory: &mut GeneralMemory<N, R>,
        h: f64,
    ) -> Result<(), StepFailure> {
        let mut own = ExternalMemory::<N, R>::empty();
        if let Some(key) = memory.external_key(&st.q) {
            (own.key, own.q) = (key, st.q);
        }
        self.step_on(&view::Mechanics(sys), st, &mut own, h)?;
        memory.remember_external_key(&st.q, own.key);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::custom::GeneralSpec;
    use crate::model::systems::KnifeEdge;
    use crate::{Collect, Method, MethodSpec, RunConfig, Scene, SceneRequest, SystemRequest};

    /// Records the keys it is given; fails when asked to by h < 0.
    struct Keys(Mutex<Vec<(u64, u64)>>);

    impl ExternalStep for Keys {
        fn name(&self) -> &str {
            "keys"
        }
        fn order(&self) -> u32 {
            1
        }
        fn symmetric(&self) -> bool {
            false
        }
        fn step(
            &self,
            sys: &dyn SystemView,
            keys: (u64, u64),
            q: &mut [f64],
            v: &mut [f64],
            h: f64,
        ) -> Result<(), String> {
            if h < 0.0 {
                return Err("ValueError: backwards".into());
            }
            self.0.lock().unwrap().push(keys);
            assert_eq!(sys.sizes(), (3, 1));
            q.iter_mut().zip(v.iter()).for_each(|(q, v)| *q += h * v);
            Ok(())
        }
    }

    #[test]
    fn a_registered_step_runs_as_a_method_with_keys_per_branch() {
        let keys = Arc::new(Keys(Mutex::default()));
        let handle = register(keys.clone());
        let method = Method::from_spec(&MethodSpec::new("python").with("handle", handle.into()))
            .expect("registered");
        assert_eq!((method.label(), method.order()), ("keys".to_owned(), 1));
        let sys = KnifeEdge { epsilon: 0.0 };
        let start = State::<3, 1>::with_continuous_multiplier(
            &sys,
            Vector::<3>::new(0.0, 0.0, 0.3),
            Vector::<3>::new(0.3f64.cos(), 0.3f64.sin(), 1.0),
        )
        .expect("a start");
        let (mut st, mut memory) = (start, method.memory());
        method.step(&sys, &mut st, &mut memory, 0.1).unwrap();
        let branch = (st, memory);
        method.step(&sys, &mut st, &mut memory, 0.1).unwrap();
        let (mut other, mut other_memory) = branch;
        other.v = -other.v; // a velocity flip keeps the key
        method.step(&sys, &mut other, &mut other_memory, 0.1).unwrap();
        let mut moved = start;
        moved.q[0] += 1.0; // a configuration moved from outside has none
        method.step(&sys, &mut moved, &mut method.memory(), 0.1).unwrap();
        let seen = keys.0.lock().unwrap().clone();
        assert_eq!(seen[0].0, 0);
        assert_eq!((seen[1].0, seen[2].0), (seen[0].1, seen[0].1), "both branches read step 1's");
        assert_ne!(seen[1].1, seen[2].1);
        assert_eq!(seen[3].0, 0);
        let failed = method.step(&sys, &mut st, &mut memory, -0.1);
        assert_eq!(failed, Err(StepFailure::External("ValueError: backwards")));
        unregister(handle);
        let gone = Method::from_spec(&MethodSpec::new("python").with("handle", handle.into()));
        assert!(gone.unwrap_err().to_string().contains("only in the nhlab Python package"));
        assert!(!Method::all().iter().any(|m| m.info().external));
    }

    /// What a step saw of the invariants: names, values, and the `(q, q̇)` they are at.
    type Seen = (Vec<String>, Vec<f64>, Vec<f64>, Vec<f64>);

    /// Records what the view gives of the invariants at each step's start; steps by Euler.
    struct Invariants(Mutex<Vec<Seen>>);

    impl ExternalStep for Invariants {
        fn name(&self) -> &str {
            "invariants"
        }
        fn order(&self) -> u32 {
            1
        }
        fn symmetric(&self) -> bool {
            false
        }
        fn step(
            &self,
            sys: &dyn SystemView,
            _: (u64, u64),
            q: &mut [f64],
            v: &mut [f64],
            h: f64,
        ) -> Result<(), String> {
            let names: Vec<String> = sys.invariant_names().into_iter().map(String::from).collect();
            let mut values = vec![f64::NAN; names.len()];
            sys.invariants(q, v, &mut values);
            self.0.lock().unwrap().push((names, values, q.to_vec(), v.to_vec()));
            q.iter_mut().zip(v.iter()).for_each(|(q, v)| *q += h * v);
            Ok(())
        }
    }

    /// What the steps of a short run of the scene `req` saw.
    fn seen(req: SceneRequest) -> Vec<Seen> {
        let recorder = Arc::new(Invariants(Mutex::default()));
        let handle = register(recorder.clone());
        let method = Method::from_spec(&MethodSpec::new("python").with("handle", handle.into()))
            .expect("registered");
        let req = SceneRequest { t_end: Some(2.0), ..req };
        let scene = Scene::resolve(&req).expect("a scene").prepare(None).expect("prepared");
        let out = scene.run(&method, &RunConfig::default(), &mut Collect::default());
        unregister(handle);
        assert_eq!(out.error, None);
        let seen = recorder.0.lock().unwrap().clone();
        assert!(seen.len() >= 3);
        seen
    }

    #[test]
    fn the_view_gives_the_invariants_a_system_declares_and_the_class_energies() {
        let built_in = |id: &str| seen(SceneRequest { system: id.into(), ..Default::default() });
        // Found in the paper's class with y the driver: the run holds (x, z, y).
        for (names, values, q, v) in built_in("contact_oscillator") {
            assert_eq!(names, ["passenger_energy", "driver_energy", "H_y"]);
            let (x, z, y) = (q[0], q[1], q[2]);
            let passenger =
                0.5 * (v[0] * v[0] + v[1] * v[1]) + 0.5 * (x * x + z * z) + 0.15 * x * x * z * z;
            let h_y = 0.5 * (y * y + v[2] * v[2]);
            for (value, expected) in values.iter().zip([passenger, h_y, h_y]) {
                assert!((value - expected).abs() <= 1e-14 * expected.abs().max(1.0));
            }
        }
        let sleigh = GeneralSpec::of(
            "sleigh",
            &["x", "y", "theta"],
            (&["m", "I", "a"], &[2.0, 0.5, 0.5]),
            "0",
            &[&["-sin(theta)", "cos(theta)", "-a"]],
        )
        .with_diagonal_mass(&["m", "m", "I"])
        .with_invariant("kinetic", "m*(x_dot^2 + y_dot^2)/2 + I*theta_dot^2/2");
        let general = seen(SceneRequest {
            system: SystemRequest::General(sleigh),
            q: Some(vec![0.0; 3]),
            v: Some(vec![0.0, 0.5, 1.0]),
            ..Default::default()
        });
        for (names, values, _, v) in general {
            assert_eq!(names, ["kinetic"]);
            let kinetic = v[0] * v[0] + v[1] * v[1] + 0.25 * v[2] * v[2];
            assert!((values[0] - kinetic).abs() <= 1e-14 * kinetic);
        }
        // A built-in of the paper's class declares none; one of the general class, nothing.
        assert_eq!(built_in("knife_edge")[0].0, ["passenger_energy", "driver_energy"]);
        let native = built_in("chaplygin_sleigh");
        assert!(native.iter().all(|(names, values, _, _)| names.is_empty() && values.is_empty()));
    }
}
