//! [`FormulaError`]: what is wrong with a formula, and where; [`Limits`]: the bounds a
//! formula must stay within; [`JitError`]: why a formula could not be compiled to machine
//! code (it then runs on the interpreter: nothing a user wrote is wrong).

use thiserror::Error;

/// Bounds on one formula, so that parsing, differentiating and evaluating stay small.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Characters per formula.
    pub max_chars: usize,
    /// Nesting depth: parentheses, function calls, unary signs and exponents.
    pub max_depth: usize,
    /// Nodes of a compiled system's graphs, derivatives included.
    pub max_nodes: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self { max_chars: 2000, max_depth: 64, max_nodes: 200_000 }
    }
}

/// Something wrong with a formula. Positions count characters from 1.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum FormulaError {
    /// A character or token where it cannot stand.
    #[error("unexpected {found} at {at}; expected {expected}")]
    Unexpected {
        /// What was found (`')'`, `end of formula`).
        found: String,
        /// Position.
        at: usize,
        /// What could stand there.
        expected: &'static str,
    },
    /// A call of a function nhlab does not know.
    #[error("unknown function '{name}' at {at}; known: {known}")]
    UnknownFunction {
        /// The name.
        name: String,
        /// Position.
        at: usize,
        /// The known functions.
        known: String,
    },
    /// A name that is neither a variable nor a parameter here.
    #[error("unknown variable '{name}' at {at}; {allowed}")]
    UnknownName {
        /// The name.
        name: String,
        /// Position.
        at: usize,
        /// What may be named here.
        allowed: String,
    },
    /// A name that exists but may not appear in this formula.
    #[error("'{name}' at {at} is not allowed here: {reason}")]
    Forbidden {
        /// The name.
        name: String,
        /// Position.
        at: usize,
        /// Why.
        reason: String,
    },
    /// A function name used without its argument.
    #[error("function '{name}' at {at} needs an argument in parentheses, as in {name}(x)")]
    BareFunction {
        /// The name.
        name: String,
        /// Position.
        at: usize,
    },
    /// A number literal that is not a finite number.
    #[error("number '{text}' at {at} is not a finite number")]
    BadNumber {
        /// The literal.
        text: String,
        /// Position.
        at: usize,
    },
    /// The formula is empty.
    #[error("the formula is empty")]
    Empty,
    /// More characters than [`Limits::max_chars`].
    #[error("the formula has {chars} characters; at most {limit} are allowed")]
    TooLong {
        /// Its length.
        chars: usize,
        /// The limit.
        limit: usize,
    },
    /// Nested deeper than [`Limits::max_depth`].
    #[error("the formula nests deeper than {limit} levels at {at}")]
    TooDeep {
        /// Where the limit was passed.
        at: usize,
        /// The limit.
        limit: usize,
    },
    /// Its derivatives grew beyond [`Limits::max_nodes`].
    #[error("the system's formulas and their derivatives need more than {limit} nodes")]
    TooLarge {
        /// The limit.
        limit: usize,
    },
}

/// Why Cranelift could not compile a tape to machine code (`Jitted::compile`, with the
/// cargo feature `jit`). Not the user's fault: the tape's interpreter runs the formula
/// instead, and [`native_code_status`](super::native_code_status) keeps the first of these.
/// Cranelift's own errors are kept as their messages, so that the record can be cloned and
/// compared.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum JitError {
    /// Cranelift does not support this host (its instruction set, or its flags).
    #[error("Cranelift does not support this host: {0}")]
    Host(String),
    /// A tape that breaks its own invariants (a slot read before it is written, a function
    /// outside [`Func::ALL`](super::Func::ALL)): a bug of the tape's compiler.
    #[error("a malformed tape: {0}")]
    Tape(&'static str),
    /// Cranelift failed on the code or could not map it executable.
    #[error("Cranelift could not compile the code: {0}")]
    Compile(String),
}
