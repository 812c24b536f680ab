//! [`Function`]: a compiled tape with, where the build and the host allow, its machine code
//! (`Jitted`, cargo feature `jit`): the fast path, run when present; the tape is the general path, kept to
//! fall back on and to test the fast one against.
//!
//! A system's parameters are usually constants folded into its code. Where one compilation
//! serves many parameter values (a sweep over them), they are inputs instead: variables from
//! [`PARAM_VAR`] on, after the coordinates and velocities, and a function is *bound* to one
//! set of values ([`Function::bind`]), which it appends to the caller's variables at each
//! evaluation. Bound copies share the tape and the machine code.

#[cfg(feature = "jit")]
use super::jit::Jitted;
use super::tape::Tape;
use std::mem::MaybeUninit;
use std::sync::Arc;

/// Most instructions of a tape compiled to machine code.
pub const MAX_NATIVE: usize = 4096;

/// The variable of a system's first parameter where parameters are inputs of its code: after
/// at most 12 coordinates and their 12 velocities.
pub const PARAM_VAR: u16 = 24;

/// Most parameters that can be inputs of code.
pub const MAX_PARAM_INPUTS: usize = 16;

/// A tape and its machine code, and the parameter values it is bound to; see the module's
/// doc.
#[derive(Debug, Clone)]
pub struct Function {
    code: Arc<Code>,
    params: Option<Arc<[f64]>>,
}

#[derive(Debug)]
struct Code {
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
        Self { code: Arc::new(Code { tape, native }), params: None }
    }

    /// `tape`, interpreted: the JIT is not built in, so `native` is not heeded.
    #[cfg(not(feature = "jit"))]
    pub fn new(tape: Tape, native: bool) -> Self {
        let _ = native;
        Self { code: Arc::new(Code { tape }), params: None }
    }

    /// The same code bound to the parameter values `params` (at most [`MAX_PARAM_INPUTS`]),
    /// read as the variables from [`PARAM_VAR`] on.
    pub fn bind(&self, params: &Arc<[f64]>) -> Self {
        debug_assert!(params.len() <= MAX_PARAM_INPUTS);
        Self { code: self.code.clone(), params: Some(params.clone()) }
    }

    /// Whether machine code runs (never without the `jit` feature).
    pub fn is_native(&self) -> bool {
        #[cfg(feature = "jit")]
        return self.code.native.is_some();
        #[cfg(not(feature = "jit"))]
        false
    }

    /// The tape.
    pub fn tape(&self) -> &Tape {
        &self.code.tape
    }

    /// Number of outputs.
    pub fn outputs(&self) -> usize {
        self.code.tape.outputs()
    }

    /// `f` of the variables the code reads: the caller's, and the bound parameters after
    /// them where there are any.
    #[inline(always)]
    fn with_inputs<T>(&self, vars: &[f64], f: impl FnOnce(&[f64]) -> T) -> T {
        match &self.params {
            None => f(vars),
            Some(params) => {
                const BASE: usize = PARAM_VAR as usize;
                let mut all = [0.0; BASE + MAX_PARAM_INPUTS];
                let k = vars.len().min(BASE);
                all[..k].copy_from_slice(&vars[..k]);
                let p = params.len().min(MAX_PARAM_INPUTS);
                all[BASE..BASE + p].copy_from_slice(&params[..p]);
                f(&all[..BASE + p])
            }
        }
    }

    /// The outputs at `vars` into `out`.
    #[inline]
    pub fn eval(&self, vars: &[f64], out: &mut [f64]) {
        self.with_inputs(vars, |vars| {
            #[cfg(feature = "jit")]
            if let Some(code) = &self.code.native {
                return code.eval(vars, out);
            }
            self.code.tape.eval(vars, out)
        })
    }

    /// [`eval`](Self::eval) into memory that need not be initialized (at least
    /// [`outputs`](Self::outputs) long); the outputs, written.
    #[inline]
    pub fn eval_uninit<'a>(&self, vars: &[f64], out: &'a mut [MaybeUninit<f64>]) -> &'a [f64] {
        self.with_inputs(vars, |vars| {
            #[cfg(feature = "jit")]
            if let Some(code) = &self.code.native {
                return code.eval_uninit(vars, out);
            }
            self.interpreted_uninit(vars, out)
        })
    }

    /// [`eval_uninit`](Self::eval_uninit) by the interpreter.
    fn interpreted_uninit<'a>(&self, vars: &[f64], out: &'a mut [MaybeUninit<f64>]) -> &'a [f64] {
        let out = &mut out[..self.outputs()];
        for o in out.iter_mut() {
            o.write(f64::NAN);
        }
        // SAFETY: every element was just written, and `MaybeUninit<f64>` is laid out as `f64`.
        let out = unsafe { &mut *(std::ptr::from_mut(out) as *mut [f64]) };
        self.code.tape.eval(vars, out);
        out
    }

    /// [`eval`](Self::eval), the tape (if it runs) with the caller's slots.
    #[inline]
    pub fn eval_with(&self, vars: &[f64], slots: &mut Vec<f64>, out: &mut [f64]) {
        self.with_inputs(vars, |vars| {
            #[cfg(feature = "jit")]
            if let Some(code) = &self.code.native {
                return code.eval(vars, out);
            }
            self.code.tape.eval_with(vars, slots, out)
        })
    }
}
