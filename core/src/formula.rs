//! Formulas: the small compiler behind systems given as text (`docs/model.md` §7).
//!
//! A formula is parsed ([`parse`]) into a graph of shared nodes ([`graph::Graph`]) whose
//! constructors fold constants and merge equal subexpressions, differentiated there
//! symbolically ([`derive`]: exact derivatives, never finite differences), and compiled
//! into a straight-line [`tape::Tape`] evaluated without parsing or allocating, and from it
//! into machine code (`jit::Jitted`, Cranelift, with the cargo feature `jit`) where the host
//! allows; [`native_code_status`] says whether it does. Evaluation cannot loop: a tape is a
//! list of instructions run once each, in order, and so is its code.
//!
//! The language: numbers, `+ - * / ^`, unary minus, parentheses, the functions of
//! [`graph::Func`] and the constant `pi`; names are the variables and parameters a caller
//! declares, each resolved by the caller ([`parse::Names`]) so that it can refuse a name
//! with a reason.

pub mod derive;
pub mod error;
pub mod function;
pub mod graph;
#[cfg(feature = "jit")]
pub mod jit;
pub mod native;
pub mod parse;
pub mod tape;

pub use error::{FormulaError, JitError, Limits};
pub use function::{Function, MAX_PARAM_INPUTS, PARAM_VAR};
pub use graph::{Func, Graph, Id};
#[cfg(feature = "jit")]
pub use jit::Jitted;
pub use native::{NativeCodeStatus, native_code_status, on_interpreter_fallback};
pub use tape::Tape;
