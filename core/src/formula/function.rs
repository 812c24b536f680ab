//! [`Function`]: a compiled tape with, where the build and the host allow, its machine code
//! (`Jitted`, cargo feature `jit`): the fast path, run when present; the tape is the general
//! path, kept to fall back on and to test the fast one against.

#[cfg(feature = "jit")]
use super::jit::Jitted;
use super::tape::Tape;
use std::mem::MaybeUninit;

/// Most instructions of a tape compiled to machine code.
pub const MAX_NATIVE: usize = 4096;

/// A tape and its machine code; see the module's doc.
#[derive(Debug)]
pub struct Function {
    tape: Tape,
    #[cfg(feature = "jit")]
    native: Option<Jitted>,
}

impl Function {
    /// `tape`, compiled to machine code too when `native`, the JIT is built in, the host
    /// supports it and the tape has at most [`MAX_NATIVE`] instructions (compiling takes
    /// time in their number, and a tape that long is dominated by its own arithmetic
    /// anyway). Cranelift's failure is recorded ([`super::native_code_status`]), not
    /// returned: the tape runs instead.
    #[cfg(feature = "jit")]
    pub fn new(tape: Tape, native: bool) -> Self {
        let native = native && tape.len() <= MAX_NATIVE;
        let native = if native { super::native::compile(&tape) } else { None };
        Self { tape, native }
    }

    /// `tape`, interpreted: the JIT is not built in, so `native` is not heeded.
    #[cfg(not(feature = "jit"))]
    pub fn new(tape: Tape, native: bool) -> Self {
        let _ = native;
        Self { tape }
    }

    /// Whether machine code runs.
    #[cfg(feature = "jit")]
    pub fn is_native(&self) -> bool {
        self.native.is_some()
    }

    /// Whether machine code runs: never, the JIT is not built in.
    #[cfg(not(feature = "jit"))]
    pub fn is_native(&self) -> bool {
        false
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
        #[cfg(feature = "jit")]
        if let Some(code) = &self.native {
            return code.eval(vars, out);
        }
        self.tape.eval(vars, out);
    }

    /// [`eval`](Self::eval) into memory that need not be initialized (at least
    /// [`outputs`](Self::outputs) long); the outputs, written.
    #[inline]
    pub fn eval_uninit<'a>(&self, vars: &[f64], out: &'a mut [MaybeUninit<f64>]) -> &'a [f64] {
        #[cfg(feature = "jit")]
        if let Some(code) = &self.native {
            return code.eval_uninit(vars, out);
        }
        self.interpreted_uninit(vars, out)
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
        #[cfg(feature = "jit")]
        if let Some(code) = &self.native {
            return code.eval(vars, out);
        }
        self.tape.eval_with(vars, slots, out);
    }
}
