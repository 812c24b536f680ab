//! The integrators of `docs/model.md` §3, one file or folder each, and the one list of them.
//!
//! A new method is one file (or folder) here plus one line in the `methods!` invocation
//! below: the list declares the module and generates [`Method`], the configured method the
//! API, the dispatch, the tests' cross products and `GET /systems` (hence the page) all use.
//! Each method is a small config struct implementing [`Integrator`]; what it carries from
//! step to step is its own [`Memory`]. Fast paths sit beside their general path, in the
//! method's file or folder, and are tested against it (`tests/it/fast_path.rs`).

pub mod composition;
pub mod coupled;
pub mod general_memory;
pub mod integrator;
pub mod memory;

pub use composition::{Composed, Composition};
pub use general_memory::GeneralMemory;
pub use integrator::{GeneralStepper, Integrator, MethodInfo, Stepper, SymmetricAt};
pub use memory::{Memory, Recall};
pub use prk::tableau::TableauChoice;

use crate::model::mechanical::Mechanical;
use crate::model::params::resolve_params;
use crate::model::system::System;
use crate::{InputError, State, StepFailure};

/// What [`Method::visit`] hands a method to: code generic over the stepped type (a run's
/// loop), given each method as its own type, class and general steps both.
pub trait Visitor {
    /// What the visit returns.
    type Output;
    /// Takes the method.
    fn visit<M: Stepper + GeneralStepper>(self, method: &M) -> Self::Output;
}

impl From<BaseMethod> for Method {
    fn from(base: BaseMethod) -> Self {
        Method { base, composition: None }
    }
}

macro_rules! methods {
    ($($module:ident :: $variant:ident),* $(,)?) => {
        $(pub mod $module; pub use self::$module::$variant;)*

        /// A method of the list with its parameters, before any composition.
        #[derive(Debug, Clone, Copy, PartialEq)]
        #[allow(
            clippy::large_enum_variant,
            reason = "a prk method holds its tableau inline, so that a method stays a Copy value; \
                      a run copies it once, never per step"
        )]
        pub enum BaseMethod {
            $(
                #[doc = concat!("[`", stringify!($variant), "`]")]
                $variant($variant),
            )*
        }

        $(
            impl From<$variant> for Method {
                fn from(m: $variant) -> Self {
                    Method { base: BaseMethod::$variant(m), composition: None }
                }
            }
        )*

        /// The memory of a [`Method`], for code that steps a method chosen at run time
        /// (tests, tools); a run keeps its method's own memory type.
        #[derive(Debug, Clone, Copy)]
        pub enum MethodMemory<const N: usize, const R: usize> {
            $(
                #[doc = concat!("[`", stringify!($variant), "`]'s")]
                $variant(<$variant as Stepper>::Memory<N, R>),
            )*
        }

        impl<const N: usize, const R: usize> Recall<N, R> for MethodMemory<N, R> {
            fn driver_terms_at(&self, zeta: f64) -> Option<(f64, crate::Matrix<R, N>)> {
                match self { $(MethodMemory::$variant(m) => m.driver_terms_at(zeta)),* }
            }
            fn moved(&mut self, from: &crate::Vector<N>, to: &crate::Vector<N>) {
                match self { $(MethodMemory::$variant(m) => m.moved(from, to)),* }
            }
        }

        /// Every method's description, in listing order.
        pub fn method_infos() -> Vec<&'static MethodInfo> {
            vec![$(<$variant as Integrator>::info()),*]
        }

        impl BaseMethod {
            fn build(spec: &MethodSpec, params: &[f64]) -> Option<Result<Self, InputError>> {
                $(
                    if spec.id == <$variant as Integrator>::info().id {
                        let built = $variant::from_parts(params, spec.tableau.as_ref(), spec.constraint.as_deref());
                        return Some(built.map(BaseMethod::$variant));
                    }
                )*
                None
            }
            /// Its description.
            pub fn info(&self) -> &'static MethodInfo {
                match self { $(BaseMethod::$variant(_) => <$variant as Integrator>::info()),* }
            }
            /// Short label, e.g. `DLA^0.4`.
            pub fn label(&self) -> String {
                match self { $(BaseMethod::$variant(m) => m.label()),* }
            }
            /// Order of convergence.
            pub fn order(&self) -> u32 {
                match self { $(BaseMethod::$variant(m) => m.order()),* }
            }
            /// Whether its step is symmetric (see [`Integrator::symmetric`]).
            pub fn symmetric(&self) -> bool {
                match self { $(BaseMethod::$variant(m) => m.symmetric()),* }
            }
            fn params(&self) -> Vec<f64> {
                match self { $(BaseMethod::$variant(m) => m.params()),* }
            }
            fn general_path(&self) -> Option<BaseMethod> {
                match self { $(BaseMethod::$variant(m) => m.general_path().map(BaseMethod::$variant)),* }
            }
            fn memory<const N: usize, const R: usize>(&self) -> MethodMemory<N, R> {
                match self {
                    $(BaseMethod::$variant(_) => MethodMemory::$variant(Memory::empty())),*
                }
            }
        }

        impl Method {
            /// One step on a system of the paper's class, with `memory` from
            /// [`Method::memory`] (a memory of another method is replaced by an empty one).
            pub fn step<S: System<N, R>, const N: usize, const R: usize>(
                &self, sys: &S, state: &mut State<N, R>, memory: &mut MethodMemory<N, R>, h: f64,
            ) -> Result<(), StepFailure> {
                match (self.base, &mut *memory) {
                    $((BaseMethod::$variant(m), MethodMemory::$variant(mem)) => match self.composition {
                        None => m.step(sys, state, mem, h),
                        Some(composition) => Composed { base: m, composition }.step(sys, state, mem, h),
                    },)*
                    #[allow(unreachable_patterns, reason = "reached with two or more methods")]
                    _ => {
                        *memory = self.memory();
                        self.step(sys, state, memory, h)
                    }
                }
            }
            /// One step on the general class (`docs/model.md` §1), the method's general step.
            pub fn step_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
                &self, sys: &S, state: &mut State<N, R>, memory: &mut GeneralMemory<N, R>, h: f64,
            ) -> Result<(), StepFailure> {
                match self.base {
                    $(BaseMethod::$variant(m) => match self.composition {
                        None => m.step_general(sys, state, memory, h),
                        Some(composition) => {
                            Composed { base: m, composition }.step_general(sys, state, memory, h)
                        }
                    }),*
                }
            }
            /// `n` steps from an empty memory with one dispatch, as a run takes them but
            /// without integrals: what the ns/step benchmarks time.
            pub fn steps<S: System<N, R>, const N: usize, const R: usize>(
                &self, sys: &S, state: &mut State<N, R>, h: f64, n: u64,
            ) -> Result<(), StepFailure> {
                fn repeat<M: Stepper, S: System<N, R>, const N: usize, const R: usize>(
                    m: &M, sys: &S, state: &mut State<N, R>, h: f64, n: u64,
                ) -> Result<(), StepFailure> {
                    let mut memory = Memory::empty();
                    (0..n).try_for_each(|_| m.step(sys, state, &mut memory, h))
                }
                match self.base {
                    $(BaseMethod::$variant(m) => match self.composition {
                        None => repeat(&m, sys, state, h, n),
                        Some(composition) => repeat(&Composed { base: m, composition }, sys, state, h, n),
                    }),*
                }
            }
            /// [`Method::steps`] on the general class.
            pub fn steps_general<S: Mechanical<N, R>, const N: usize, const R: usize>(
                &self, sys: &S, state: &mut State<N, R>, h: f64, n: u64,
            ) -> Result<(), StepFailure> {
                let mut memory = GeneralMemory::empty();
                (0..n).try_for_each(|_| self.step_general(sys, state, &mut memory, h))
            }
            /// Hands the method, with its composition, to `visitor` as the type it steps as:
            /// one dispatch, outside any loop the visitor runs (`measure::simulate` runs a
            /// method so).
            pub fn visit<V: Visitor>(&self, visitor: V) -> V::Output {
                match self.base {
                    $(BaseMethod::$variant(m) => match self.composition {
                        None => visitor.visit(&m),
                        Some(composition) => visitor.visit(&Composed { base: m, composition }),
                    }),*
                }
            }
        }
    };
}

methods!(
    dla::Dla,
    dla01::Dla01,
    leapfrog::Leapfrog,
    dd::Dd,
    dd_avf::DdAvf,
    rk4::Rk4,
    rattle::Rattle,
    spark::Spark,
    prk::Prk,
    reference_step::ReferenceStep,
    external::External,
);

/// A configured method: one of the list with its parameters, taken alone or as a symmetric
/// composition of its steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Method {
    /// The method of the list.
    pub base: BaseMethod,
    /// The composition it is taken in, if any (only for a symmetric base).
    pub composition: Option<Composition>,
}

impl Method {
    /// Its base method's description.
    pub fn info(&self) -> &'static MethodInfo {
        self.base.info()
    }
    /// Short label, e.g. `DLA^0.4` or `LF∘p4s3`.
    pub fn label(&self) -> String {
        match self.composition {
            None => self.base.label(),
            Some(c) => format!("{}∘{}", self.base.label(), c.id()),
        }
    }
    /// Order of convergence: a composition's, where its base method reaches it (see
    /// [`MethodInfo::composed_order_limit`]), and never below the base's own (sub-steps
    /// whose coefficients sum to 1 keep it).
    pub fn order(&self) -> u32 {
        let limit = self.info().composed_order_limit.unwrap_or(u32::MAX);
        let base = self.base.order();
        self.composition.map_or(base, |c| c.order().min(limit).max(base))
    }
    /// Sub-steps per step: 1, or the composition's stages.
    pub fn stages(&self) -> usize {
        self.composition.map_or(1, Composition::stages)
    }
    /// Parameter values with their names.
    pub fn params(&self) -> Vec<(&'static str, f64)> {
        self.info().params.iter().map(|p| p.name).zip(self.base.params()).collect()
    }
    /// The same method on its general path, for a method that has faster ones: what
    /// the fast paths are tested against and benchmarked beside. `None` for the others.
    pub fn general_path(&self) -> Option<Method> {
        self.base.general_path().map(|base| Method { base, ..*self })
    }
    /// An empty memory for this method.
    pub fn memory<const N: usize, const R: usize>(&self) -> MethodMemory<N, R> {
        self.base.memory()
    }
    /// The same method taken as `composition` of its steps; refused unless its step is
    /// symmetric (field `composition`).
    pub fn composed(self, composition: Composition) -> Result<Method, InputError> {
        if !self.base.symmetric() {
            let why = match self.base {
                BaseMethod::Dla(_) => "DLA^α is symmetric only for α = 0.5",
                BaseMethod::External(_) => "it does not declare itself symmetric",
                BaseMethod::Prk(p) => p.asymmetry().unwrap_or("its step is not symmetric"),
                _ => "its step is not symmetric",
            };
            return Err(InputError::Composition {
                field: "composition".into(),
                message: format!(
                    "{} cannot be composed: {why}, and a composition raises the order of a \
                     symmetric method only; composable are {}",
                    self.base.label(),
                    composable().join(", ")
                ),
            });
        }
        Ok(Method { composition: Some(composition), ..self })
    }
}

/// The ids of the methods a composition may take (DLA^α at α = ½ only).
pub fn composable() -> Vec<&'static str> {
    // `all()` lists each method once with its defaults and DLA^α again at 0.4.
    Method::all().into_iter().filter(|m| m.base.symmetric()).map(|m| m.info().id).collect()
}

/// A method as a user names it: an id and parameter overrides.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MethodSpec {
    /// Method id.
    pub id: String,
    /// Parameters by name.
    pub params: Vec<(String, f64)>,
    /// Composition id (`p4s3`, …), if any.
    pub composition: Option<String>,
    /// A `prk` method's tableau, if given.
    pub tableau: Option<TableauChoice>,
    /// A `prk` method's constraint (`stage`, `end`, `midpoint`), if given.
    pub constraint: Option<String>,
}

impl MethodSpec {
    /// A spec with no parameters.
    pub fn new(id: &str) -> Self {
        Self { id: id.into(), ..Self::default() }
    }
    /// Takes it as a composition.
    pub fn composed(mut self, composition: &str) -> Self {
        self.composition = Some(composition.into());
        self
    }
    /// Adds a parameter.
    pub fn with(mut self, name: &str, value: f64) -> Self {
        self.params.push((name.into(), value));
        self
    }
}

/// The description of the method with this id.
pub fn method_info(id: &str) -> Option<&'static MethodInfo> {
    method_infos().into_iter().find(|m| m.id == id)
}

impl Method {
    /// Builds a method from a spec, checking its parameters (field paths are relative to
    /// the method object, e.g. `alpha`).
    pub fn from_spec(spec: &MethodSpec) -> Result<Self, InputError> {
        let info = method_info(&spec.id).ok_or_else(|| InputError::UnknownMethod {
            field: "id".into(),
            id: spec.id.clone(),
            valid: method_infos().iter().map(|m| m.id).collect::<Vec<_>>().join(", "),
        })?;
        let given = spec.params.iter().map(|(name, value)| (name.as_str(), *value, true));
        let owner = format!("method {}", info.id);
        let values = resolve_params(info.params, given, "", &owner)?;
        let method = Method::from(BaseMethod::build(spec, &values).expect("found the id")?);
        let Some(id) = &spec.composition else { return Ok(method) };
        let composition = Composition::from_id(id).ok_or_else(|| InputError::Composition {
            field: "composition".into(),
            message: format!(
                "unknown composition '{id}'; valid compositions: {}",
                Composition::ALL.map(Composition::id).join(", ")
            ),
        })?;
        method.composed(composition)
    }

    /// The paper's five: DLA^0.5, DLA^0.4, DLA^{0,1}, LF, DD.
    pub fn paper_five() -> [Method; 5] {
        [
            Method::from(Dla { alpha: 0.5, ..Dla::default() }),
            Method::from(Dla { alpha: 0.4, ..Dla::default() }),
            Method::from(Dla01::default()),
            Method::from(Leapfrog),
            Method::from(Dd::default()),
        ]
    }

    /// Every method of the list with its default parameters, the paper's five first (so
    /// DLA^α twice, at α = ½ and 0.4): what the scorecard, the benchmarks and the tools run.
    /// The instruments ([`MethodInfo::instrument`]: the reference), the methods written
    /// outside nhlab ([`MethodInfo::external`]) and the family given by tableaux
    /// ([`MethodInfo::by_tableau`]) are not among them.
    pub fn all() -> Vec<Method> {
        let mut out = Self::paper_five().to_vec();
        let listed = |info: &&MethodInfo| !info.instrument && !info.external && !info.by_tableau;
        for info in method_infos().into_iter().filter(listed) {
            if !out.iter().any(|m| m.info().id == info.id) {
                // A listed id with its defaults always builds.
                out.extend(Self::from_spec(&MethodSpec::new(info.id)));
            }
        }
        out
    }
}
