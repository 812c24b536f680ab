//! Formulas: the small compiler behind systems given as text (`docs/model.md` §7).
//!
//! A formula is parsed ([`parse`]) into a graph of shared nodes ([`graph::Graph`]) whose
//! constructors fold constants and merge equal subexpressions, differentiated there
//! symbolically ([`derive`]: exact derivatives, never finite differences), and compiled
//! into a straight-line [`tape::Tape`] evaluated without parsing or allocating. Evaluation
//! cannot loop: a tape is a list of instructions run once each, in order.
//!
//! The language: numbers, `+ - * / ^`, unary minus, parentheses, the functions of
//! [`graph::Func`] and the constant `pi`; names are the variables and parameters a caller
//! declares, each resolved by the caller ([`parse::Names`]) so that it can refuse a name
//! with a reason.

pub mod derive;
pub mod error;
pub mod graph;
pub mod parse;
pub mod tape;

pub use error::{FormulaError, Limits};
pub use graph::{Func, Graph, Id};
pub use tape::Tape;
