//! The parser: a formula's text into nodes of a [`Graph`], by recursive descent with a
//! depth bound, every error with its position (characters counted from 1).
//!
//! ```text
//! sum     = product (("+" | "-") product)*
//! product = unary (("*" | "/") unary)*
//! unary   = ("-" | "+") unary | power          -x^2 is −(x²)
//! power   = atom ("^" unary)?                  right-associative: 2^3^2 = 2^9
//! atom    = number | "pi" | name | function "(" sum ")" | "(" sum ")"
//! ```

use super::error::{FormulaError, Limits};
use super::graph::{Func, Graph, Id};

/// What a name stands for in one formula, as the caller decides.
#[derive(Debug, Clone, PartialEq)]
pub enum Name {
    /// The caller's variable of this index.
    Var(u16),
    /// A parameter, at this value.
    Value(f64),
    /// A name the caller knows but refuses here, with the reason.
    Forbidden(String),
}

/// How a caller resolves the names of a formula.
pub trait Names {
    /// What `name` stands for, or `None` when it is unknown.
    fn resolve(&self, name: &str) -> Option<Name>;
    /// What may be named, for the message about an unknown name.
    fn allowed(&self) -> String;
}

/// Parses `text` into `g`.
pub fn parse(
    g: &mut Graph,
    text: &str,
    names: &dyn Names,
    limits: &Limits,
) -> Result<Id, FormulaError> {
    let chars: Vec<char> = text.chars().collect();
    if chars.len() > limits.max_chars {
        return Err(FormulaError::TooLong { chars: chars.len(), limit: limits.max_chars });
    }
    let mut p = Parser { chars, at: 0, depth: 0, limits, names, g };
    p.skip_space();
    if p.peek().is_none() {
        return Err(FormulaError::Empty);
    }
    let e = p.sum()?;
    p.skip_space();
    match p.peek() {
        None => Ok(e),
        Some(c) => Err(p.unexpected(c, "an operator or the end of the formula")),
    }
}

struct Parser<'a> {
    chars: Vec<char>,
    at: usize,
    depth: usize,
    limits: &'a Limits,
    names: &'a dyn Names,
    g: &'a mut Graph,
}

fn describe(c: char) -> String {
    format!("'{c}'")
}

impl Parser<'_> {
    fn peek(&self) -> Option<char> {
        self.chars.get(self.at).copied()
    }

    fn skip_space(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.at += 1;
        }
    }

    fn unexpected(&self, c: char, expected: &'static str) -> FormulaError {
        FormulaError::Unexpected { found: describe(c), at: self.at + 1, expected }
    }

    fn end(&self, expected: &'static str) -> FormulaError {
        FormulaError::Unexpected { found: "end of formula".into(), at: self.at + 1, expected }
    }

    /// Enters one level of nesting.
    fn deeper(&mut self) -> Result<(), FormulaError> {
        self.depth += 1;
        if self.depth > self.limits.max_depth {
            return Err(FormulaError::TooDeep { at: self.at + 1, limit: self.limits.max_depth });
        }
        Ok(())
    }

    fn sum(&mut self) -> Result<Id, FormulaError> {
        let mut e = self.product()?;
        loop {
            self.skip_space();
            match self.peek() {
                Some('+') => {
                    self.at += 1;
                    let r = self.product()?;
                    e = self.g.add(e, r);
                }
                Some('-') => {
                    self.at += 1;
                    let r = self.product()?;
                    e = self.g.sub(e, r);
                }
                _ => return Ok(e),
            }
        }
    }

    fn product(&mut self) -> Result<Id, FormulaError> {
        let mut e = self.unary()?;
        loop {
            self.skip_space();
            match self.peek() {
                Some('*') => {
                    self.at += 1;
                    let r = self.unary()?;
                    e = self.g.mul(e, r);
                }
                Some('/') => {
                    self.at += 1;
                    let r = self.unary()?;
                    e = self.g.div(e, r);
                }
                _ => return Ok(e),
            }
        }
    }

    fn unary(&mut self) -> Result<Id, FormulaError> {
        self.skip_space();
        match self.peek() {
            Some(sign @ ('-' | '+')) => {
                self.at += 1;
                self.deeper()?;
                let e = self.unary()?;
                self.depth -= 1;
                Ok(if sign == '-' { self.g.neg(e) } else { e })
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Id, FormulaError> {
        let base = self.atom()?;
        self.skip_space();
        if self.peek() != Some('^') {
            return Ok(base);
        }
        self.at += 1;
        self.deeper()?;
        let exponent = self.unary()?;
        self.depth -= 1;
        Ok(self.g.pow(base, exponent))
    }

    fn atom(&mut self) -> Result<Id, FormulaError> {
        const WANT: &str = "a number, a name or '('";
        self.skip_space();
        let Some(c) = self.peek() else { return Err(self.end(WANT)) };
        if c.is_ascii_digit() || c == '.' {
            return self.number();
        }
        if c == '(' {
            self.at += 1;
            let e = self.parenthesized()?;
            return Ok(e);
        }
        if c.is_alphabetic() || c == '_' {
            return self.name();
        }
        Err(self.unexpected(c, WANT))
    }

    /// After an opening parenthesis: the sum and its closing parenthesis.
    fn parenthesized(&mut self) -> Result<Id, FormulaError> {
        self.deeper()?;
        let e = self.sum()?;
        self.skip_space();
        match self.peek() {
            Some(')') => self.at += 1,
            Some(c) => return Err(self.unexpected(c, "an operator or ')'")),
            None => return Err(self.end("')'")),
        }
        self.depth -= 1;
        Ok(e)
    }

    fn number(&mut self) -> Result<Id, FormulaError> {
        let start = self.at;
        let digits = |p: &mut Self| {
            while p.peek().is_some_and(|c| c.is_ascii_digit()) {
                p.at += 1;
            }
        };
        digits(self);
        if self.peek() == Some('.') {
            self.at += 1;
            digits(self);
        }
        if matches!(self.peek(), Some('e' | 'E')) {
            let mark = self.at;
            self.at += 1;
            if matches!(self.peek(), Some('+' | '-')) {
                self.at += 1;
            }
            if self.peek().is_some_and(|c| c.is_ascii_digit()) {
                digits(self);
            } else {
                self.at = mark; // `2e` is 2 followed by the name `e`
            }
        }
        let text: String = self.chars[start..self.at].iter().collect();
        match text.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(self.g.num(x)),
            _ => Err(FormulaError::BadNumber { text, at: start + 1 }),
        }
    }

    fn name(&mut self) -> Result<Id, FormulaError> {
        let start = self.at;
        while self.peek().is_some_and(|c| c.is_alphanumeric() || c == '_') {
            self.at += 1;
        }
        let name: String = self.chars[start..self.at].iter().collect();
        let at = start + 1;
        self.skip_space();
        let called = self.peek() == Some('(');
        if let Some(f) = Func::named(&name) {
            if !called {
                return Err(FormulaError::BareFunction { name, at });
            }
            self.at += 1;
            let arg = self.parenthesized()?;
            return Ok(self.g.call(f, arg));
        }
        if called {
            let known = Func::ALL.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ");
            return Err(FormulaError::UnknownFunction { name, at, known });
        }
        if name == "pi" {
            return Ok(self.g.num(std::f64::consts::PI));
        }
        match self.names.resolve(&name) {
            Some(Name::Var(i)) => Ok(self.g.var(i)),
            Some(Name::Value(x)) => Ok(self.g.num(x)),
            Some(Name::Forbidden(reason)) => Err(FormulaError::Forbidden { name, at, reason }),
            None => Err(FormulaError::UnknownName { name, at, allowed: self.names.allowed() }),
        }
    }
}
