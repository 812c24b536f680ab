//! [`Jitted`]: a [`Tape`](super::Tape) compiled to machine code with Cranelift, the fast
//! path beside the tape's interpreter (the general path, which it is tested against: the
//! same instructions in the same order, so the same numbers bit for bit).
//!
//! An interpreter pays a dispatch and a trip through memory per instruction, several times
//! the arithmetic itself; compiled, the values stay in registers. The code is a straight
//! line of arithmetic and calls to the elementary functions: it reads its inputs, writes its
//! outputs, and cannot loop or touch other memory. Where Cranelift does not support the host,
//! compilation fails and the interpreter runs ([`super::native`] keeps the first failure).
//! Built with the cargo feature `jit` (on by default) only.

use super::error::JitError;
use super::graph::Func;
use super::tape::{Op, Out, Tape};
use cranelift_codegen::Context;
use cranelift_codegen::ir::{AbiParam, InstBuilder, MemFlags, StackSlotData, StackSlotKind, types};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{Linkage, Module, default_libcall_names};
use std::mem::MaybeUninit;

/// Variables of a tape compiled to machine code passed in registers; the others are read
/// from memory.
pub const REGISTER_VARS: usize = 6;

/// Compiled code: `f(x₀, …, x₅, out, rest)`, the first variables in registers (unused ones
/// are ignored), the others from `rest` (`x₆, x₇, …`): a step calls the driver's code on its
/// Newton chain, where a trip through memory for the inputs would add a store and a load to
/// each iteration's latency; a system of more coordinates reads the rest from memory.
type Code = unsafe extern "C" fn(f64, f64, f64, f64, f64, f64, *mut f64, *const f64);

/// A tape as machine code; see the module's doc.
pub struct Jitted {
    code: Code,
    vars: usize,
    outputs: usize,
    /// Owns the code's memory, freed on drop.
    module: Option<JITModule>,
}

// SAFETY: after `finalize_definitions` the module is never mutated again, only dropped; the
// code it holds is immutable and reads and writes only the buffers passed to each call.
unsafe impl Send for Jitted {}
// SAFETY: as above; calling the code from several threads at once shares nothing.
unsafe impl Sync for Jitted {}

impl Drop for Jitted {
    fn drop(&mut self) {
        if let Some(module) = self.module.take() {
            // SAFETY: the function pointer dies with `self`; nothing calls it after this.
            unsafe { module.free_memory() };
        }
    }
}

impl std::fmt::Debug for Jitted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Jitted").field("vars", &self.vars).field("outputs", &self.outputs).finish()
    }
}

extern "C" fn powi(x: f64, k: i32) -> f64 {
    x.powi(k)
}
extern "C" fn powf(x: f64, y: f64) -> f64 {
    x.powf(y)
}
extern "C" fn call(f: i32, x: f64) -> f64 {
    Func::ALL[f as usize].1.apply(x)
}
/// `sin x` and `cos x` into `out[0]`, `out[1]`.
///
/// # Safety
/// `out` points to two writable doubles (a stack slot of the compiled code).
unsafe extern "C" fn sin_cos(x: f64, out: *mut f64) {
    let (s, c) = x.sin_cos();
    // SAFETY: by the contract above.
    unsafe {
        *out = s;
        *out.add(1) = c;
    }
}

impl Jitted {
    /// Compiles `tape`, or says why it could not.
    pub fn compile(tape: &Tape) -> Result<Self, JitError> {
        let host = |e: &dyn std::fmt::Display| JitError::Host(e.to_string());
        let compile = |e: &dyn std::fmt::Display| JitError::Compile(e.to_string());
        let mut flags = settings::builder();
        // `speed`, though the tape comes with its constants folded and its subexpressions
        // merged: on the tapes of a 2,000-character potential (600 to 800 instructions),
        // `none` took twice as long to compile and ran no faster.
        flags.set("opt_level", "speed").map_err(|e| host(&e))?;
        // Cranelift checks its IR between passes unless told not to: up to a quarter of the
        // time those tapes took to compile, for a translation the tests check against the
        // interpreter bit for bit. Kept where debug assertions are (tests, debug builds).
        let verify = if cfg!(debug_assertions) { "true" } else { "false" };
        flags.set("enable_verifier", verify).map_err(|e| host(&e))?;
        let isa = cranelift_native::builder()
            .map_err(|e| host(&e))?
            .finish(settings::Flags::new(flags))
            .map_err(|e| host(&e))?;
        let mut module = JITModule::new(JITBuilder::with_isa(isa, default_libcall_names()));
        let ptr = module.target_config().pointer_type();
        let mut sig = module.make_signature();
        sig.params.extend([AbiParam::new(types::F64); REGISTER_VARS]);
        sig.params.extend([AbiParam::new(ptr), AbiParam::new(ptr)]);
        let id = module.declare_function("tape", Linkage::Local, &sig).map_err(|e| compile(&e))?;
        let mut ctx = Context::new();
        ctx.func.signature = sig;
        let mut fctx = FunctionBuilderContext::new();
        {
            let mut b = FunctionBuilder::new(&mut ctx.func, &mut fctx);
            let block = b.create_block();
            b.append_block_params_for_function_params(block);
            b.switch_to_block(block);
            b.seal_block(block);
            let params = b.block_params(block);
            let (vars, out, rest) = (
                params[..REGISTER_VARS].to_vec(),
                params[REGISTER_VARS],
                params[REGISTER_VARS + 1],
            );
            let f64t = types::F64;
            let mut s1 = module.make_signature();
            s1.params.push(AbiParam::new(f64t));
            s1.params.push(AbiParam::new(types::I32));
            s1.returns.push(AbiParam::new(f64t));
            let powi_sig = b.import_signature(s1.clone());
            let mut s2 = module.make_signature();
            s2.params.extend([AbiParam::new(f64t), AbiParam::new(f64t)]);
            s2.returns.push(AbiParam::new(f64t));
            let powf_sig = b.import_signature(s2);
            let mut s3 = module.make_signature();
            s3.params.extend([AbiParam::new(types::I32), AbiParam::new(f64t)]);
            s3.returns.push(AbiParam::new(f64t));
            let call_sig = b.import_signature(s3);
            let mut s4 = module.make_signature();
            s4.params.extend([AbiParam::new(f64t), AbiParam::new(ptr)]);
            let sin_cos_sig = b.import_signature(s4);
            let pair =
                b.create_sized_stack_slot(StackSlotData::new(StackSlotKind::ExplicitSlot, 16, 3));
            let flags = MemFlags::trusted();
            let mut slot = vec![None; tape.slots()];
            let get = |slot: &Vec<Option<_>>, k: u32| {
                slot[k as usize].ok_or(JitError::Tape("a slot read before written"))
            };
            for ins in tape.instructions() {
                let v = match ins.op {
                    Op::Const(c) => b.ins().f64const(c),
                    Op::Var(i) if (i as usize) < REGISTER_VARS => vars[i as usize],
                    Op::Var(i) => {
                        let offset = 8 * (i as usize - REGISTER_VARS) as i32;
                        b.ins().load(f64t, flags, rest, offset)
                    }
                    Op::Add(x, y) => {
                        let (x, y) = (get(&slot, x)?, get(&slot, y)?);
                        b.ins().fadd(x, y)
                    }
                    Op::Sub(x, y) => {
                        let (x, y) = (get(&slot, x)?, get(&slot, y)?);
                        b.ins().fsub(x, y)
                    }
                    Op::Mul(x, y) => {
                        let (x, y) = (get(&slot, x)?, get(&slot, y)?);
                        b.ins().fmul(x, y)
                    }
                    Op::Div(x, y) => {
                        let (x, y) = (get(&slot, x)?, get(&slot, y)?);
                        b.ins().fdiv(x, y)
                    }
                    Op::AddK(x, k) => {
                        let (x, k) = (get(&slot, x)?, b.ins().f64const(k));
                        b.ins().fadd(x, k)
                    }
                    Op::SubK(x, k) => {
                        let (x, k) = (get(&slot, x)?, b.ins().f64const(k));
                        b.ins().fsub(x, k)
                    }
                    Op::KSub(k, x) => {
                        let (x, k) = (get(&slot, x)?, b.ins().f64const(k));
                        b.ins().fsub(k, x)
                    }
                    Op::MulK(x, k) => {
                        let (x, k) = (get(&slot, x)?, b.ins().f64const(k));
                        b.ins().fmul(x, k)
                    }
                    Op::DivK(x, k) => {
                        let (x, k) = (get(&slot, x)?, b.ins().f64const(k));
                        b.ins().fdiv(x, k)
                    }
                    Op::KDiv(k, x) => {
                        let (x, k) = (get(&slot, x)?, b.ins().f64const(k));
                        b.ins().fdiv(k, x)
                    }
                    Op::Neg(x) => {
                        let x = get(&slot, x)?;
                        b.ins().fneg(x)
                    }
                    Op::Square(x) => {
                        let x = get(&slot, x)?;
                        b.ins().fmul(x, x)
                    }
                    Op::PowI(x, k) => {
                        let x = get(&slot, x)?;
                        let k = b.ins().iconst(types::I32, k as i64);
                        let f = b.ins().iconst(ptr, powi as *const () as usize as i64);
                        let c = b.ins().call_indirect(powi_sig, f, &[x, k]);
                        b.inst_results(c)[0]
                    }
                    Op::Pow(x, y) => {
                        let (x, y) = (get(&slot, x)?, get(&slot, y)?);
                        let f = b.ins().iconst(ptr, powf as *const () as usize as i64);
                        let c = b.ins().call_indirect(powf_sig, f, &[x, y]);
                        b.inst_results(c)[0]
                    }
                    Op::Call(func, x) => {
                        let x = get(&slot, x)?;
                        let index = Func::ALL
                            .iter()
                            .position(|(_, f)| *f == func)
                            .ok_or(JitError::Tape("a function outside Func::ALL"))?;
                        let which = b.ins().iconst(types::I32, index as i64);
                        let f = b.ins().iconst(ptr, call as *const () as usize as i64);
                        let c = b.ins().call_indirect(call_sig, f, &[which, x]);
                        b.inst_results(c)[0]
                    }
                    Op::SinCos(x, cos) => {
                        let x = get(&slot, x)?;
                        let at = b.ins().stack_addr(ptr, pair, 0);
                        let f = b.ins().iconst(ptr, sin_cos as *const () as usize as i64);
                        b.ins().call_indirect(sin_cos_sig, f, &[x, at]);
                        let c = b.ins().stack_load(f64t, pair, 8);
                        slot[cos as usize] = Some(c);
                        b.ins().stack_load(f64t, pair, 0)
                    }
                };
                slot[ins.dst as usize] = Some(v);
            }
            for (k, o) in tape.output_sources().iter().enumerate() {
                let v = match *o {
                    Out::Slot(s) => get(&slot, s)?,
                    Out::Const(c) => b.ins().f64const(c),
                };
                b.ins().store(flags, v, out, 8 * k as i32);
            }
            b.ins().return_(&[]);
            b.finalize();
        }
        module.define_function(id, &mut ctx).map_err(|e| compile(&e))?;
        module.finalize_definitions().map_err(|e| compile(&e))?;
        let raw = module.get_finalized_function(id);
        // SAFETY: `raw` is the function just defined, with the signature of `Code`.
        let code = unsafe { std::mem::transmute::<*const u8, Code>(raw) };
        Ok(Self { code, vars: tape.vars(), outputs: tape.outputs(), module: Some(module) })
    }

    /// Evaluates the outputs at `vars` into `out`, as [`Tape::eval`] does.
    #[inline]
    pub fn eval(&self, vars: &[f64], out: &mut [f64]) {
        self.call(vars, out.as_mut_ptr(), out.len());
    }

    /// [`eval`](Self::eval) into memory that need not be initialized; the outputs, written.
    #[inline]
    pub fn eval_uninit<'a>(&self, vars: &[f64], out: &'a mut [MaybeUninit<f64>]) -> &'a [f64] {
        self.call(vars, out.as_mut_ptr().cast(), out.len());
        // SAFETY: `call` wrote the first `self.outputs` doubles of `out`.
        unsafe { std::slice::from_raw_parts(out.as_ptr().cast(), self.outputs) }
    }

    /// Runs the code on `vars`, writing the outputs to `out`, which has room for `room`.
    #[inline]
    fn call(&self, vars: &[f64], out: *mut f64, room: usize) {
        assert!(vars.len() >= self.vars && room >= self.outputs, "a tape's inputs and outputs");
        // Unused arguments are ignored: any value will do, and a known length drops the test.
        let x = |i: usize| vars.get(i).copied().unwrap_or(0.0);
        let rest = vars.get(REGISTER_VARS..).map_or(std::ptr::null(), <[f64]>::as_ptr);
        // SAFETY: the code writes `self.outputs` doubles to `out`, which has room for them
        // (asserted above), and reads nothing but its arguments and, for a tape of more than
        // REGISTER_VARS variables, `vars[REGISTER_VARS..self.vars]` through `rest`.
        unsafe { (self.code)(x(0), x(1), x(2), x(3), x(4), x(5), out, rest) }
    }
}
