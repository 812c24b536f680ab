//! [`Function`]: a compiled tape with, where the host allows, its machine code
//! ([`Jitted`]): the fast path, run when present; the tape is the general path, kept to
//! fall back on and to test the fast one against.

use super::jit::Jitted;
use super::tape::Tape;
use std::mem::MaybeUninit;

/// Most instructions of a tape compiled to machine code.
pub const MAX_NATIVE: usize = 4096;

/// A tape and its machine code; see the module's doc.
#[derive(Debug)]
pub struct Function {
    tape: Tape,
    native: Option<Jitted>,
}

impl Function {
    /// `tape`, compiled to machine code too when `native`, the host supports it and the tape
    /// has at most [`MAX_NATIVE`] instructions (compiling takes time in their number, and a
    /// tape that long is dominated by its own arithmetic anyway).
    pub fn new(tape: Tape, native: bool) -> Self {
        let native = native && tape.len() <= MAX_NATIVE;
        let native = if native { Jitted::compile(&tape).ok() } else { None };
        Self { tape, native }
    }

    /// Whether machine code runs.
    pub fn is_native(&self) -> bool {
        self.native.is_some()
    }

    /// The tape.
    pub fn tape(&self) -> &Tape {
        &self.tape
    }

    /// Number of outputs.
    pub fn outputs(&self) -> usize {
        self.tape.outputs()
    }

    /// The outputs at `vars` into `out`.
    #[inline]
    pub fn eval(&self, vars: &[f64], out: &mut [f64]) {
        match &self.native {
            Some(code) => code.eval(vars, out),
            None => self.tape.eval(vars, out),
        }
    }

    /// [`eval`](Self::eval) into memory that need not be initialized (at least
    /// [`outputs`](Self::outputs) long); the outputs, written.
    #[inline]
    pub fn eval_uninit<'a>(&self, vars: &[f64], out: &'a mut [MaybeUninit<f64>]) -> &'a [f64] {
        match &self.native {
            Some(code) => code.eval_uninit(vars, out),
            None => self.interpreted_uninit(vars, out),
        }
    }

    /// [`eval_uninit`](Self::eval_uninit) by the interpreter.
    fn interpreted_uninit<'a>(&self, vars: &[f64], out: &'a mut [MaybeUninit<f64>]) -> &'a [f64] {
        let out = &mut out[..self.outputs()];
        for o in out.iter_mut() {
            o.write(f64::NAN);
        }
        // SAFETY: every element was just written, and `MaybeUninit<f64>` is laid out as `f64`.
        let out = unsafe { &mut *(std::ptr::from_mut(out) as *mut [f64]) };
        self.tape.eval(vars, out);
        out
    }

    /// [`eval`](Self::eval), the tape (if it runs) with the caller's slots.
    #[inline]
    pub fn eval_with(&self, vars: &[f64], slots: &mut Vec<f64>, out: &mut [f64]) {
        match &self.native {
            Some(code) => code.eval(vars, out),
            None => self.tape.eval_with(vars, slots, out),
        }
    }
}
