//! Whether formulas run as machine code in this process, and if not, why
//! ([`native_code_status`]). They fall back to the tape's interpreter when the JIT is left
//! out of the build (cargo feature `jit`), when the environment turns it off
//! (`NHLAB_JIT=off`: the interpreter alone, without a second build), or when Cranelift fails
//! (`Jitted::compile` returns a [`JitError`]: a host it does not support, memory it cannot map
//! executable).
//! The numbers are the same, only slower, so nothing else would show it. The core does no
//! logging: a caller registers [`on_interpreter_fallback`] to say it once (the server logs a
//! warning) and reads the status where it reports its health.

use super::error::JitError;
use std::sync::{Mutex, MutexGuard, OnceLock, PoisonError};

/// The environment variable that turns machine code off: `NHLAB_JIT=off`.
const JIT_VARIABLE: &str = "NHLAB_JIT";

/// How formulas run in this process; see the module's doc.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NativeCodeStatus {
    /// Whether the JIT is built in (cargo feature `jit`).
    pub compiled_in: bool,
    /// Whether the environment turns it off (`NHLAB_JIT=off`).
    pub turned_off: bool,
    /// Cranelift's first failure in this process, if it has failed.
    pub failure: Option<JitError>,
}

impl NativeCodeStatus {
    /// Whether formulas are compiled to machine code (those of at most
    /// [`MAX_NATIVE`](super::function::MAX_NATIVE) instructions; longer ones are always
    /// interpreted): the JIT is built in, not turned off, and has never failed.
    pub fn native(&self) -> bool {
        self.compiled_in && !self.turned_off && self.failure.is_none()
    }

    /// Why formulas run on the interpreter, as a sentence; `None` when they do not.
    pub fn why_not(&self) -> Option<String> {
        if !self.compiled_in {
            Some("built without the `jit` feature: formulas run on the interpreter".into())
        } else if self.turned_off {
            Some(format!("{JIT_VARIABLE}=off in the environment: formulas run on the interpreter"))
        } else {
            let failure = self.failure.as_ref()?;
            Some(format!("{failure}: formulas run on the interpreter"))
        }
    }
}

/// What a caller does with the sentence saying why formulas run on the interpreter.
type Report = fn(&str);

/// What this process has seen: Cranelift's first failure, and the caller's report and
/// whether it was made.
struct Record {
    failure: Option<JitError>,
    report: Option<Report>,
    reported: bool,
}

static RECORD: Mutex<Record> = Mutex::new(Record { failure: None, report: None, reported: false });

/// The record. A panic while it is held (none can happen: no code that can panic runs
/// under it) would leave it consistent, so a poisoned lock is taken as it is.
fn record() -> MutexGuard<'static, Record> {
    RECORD.lock().unwrap_or_else(PoisonError::into_inner)
}

fn status_of(record: &Record) -> NativeCodeStatus {
    NativeCodeStatus {
        compiled_in: cfg!(feature = "jit"),
        turned_off: turned_off(),
        failure: record.failure.clone(),
    }
}

/// Whether `NHLAB_JIT=off` is set (read once per process; any other value leaves the JIT on).
fn turned_off() -> bool {
    static OFF: OnceLock<bool> = OnceLock::new();
    *OFF.get_or_init(|| std::env::var_os(JIT_VARIABLE).is_some_and(|v| v == "off"))
}

/// The report to make now, marked made: when formulas have fallen back, a report is
/// registered and none was made yet. Called under the lock, made outside it.
fn due(record: &mut Record) -> Option<(Report, String)> {
    if record.reported {
        return None;
    }
    let why = status_of(record).why_not()?;
    let report = record.report?;
    record.reported = true;
    Some((report, why))
}

/// How formulas run in this process. With the JIT built in, the first call compiles a small
/// formula, so that a host Cranelift does not support shows here before any formula of a
/// user's.
pub fn native_code_status() -> NativeCodeStatus {
    #[cfg(feature = "jit")]
    probe();
    status_of(&record())
}

/// Registers `report`, called once in this process with [`NativeCodeStatus::why_not`]'s
/// sentence when formulas fall back to the interpreter: at once if they already have (the
/// JIT is not built in, or Cranelift has failed, which the small formula of
/// [`native_code_status`] tries now), otherwise at Cranelift's first failure, if it ever
/// fails. A later registration replaces the report if it has not been made yet. `report`
/// runs on the thread that compiled the formula; it must not call back into this module.
pub fn on_interpreter_fallback(report: fn(&str)) {
    let due = {
        let mut record = record();
        record.report = Some(report);
        due(&mut record)
    };
    if let Some((report, why)) = due {
        report(&why);
    }
    #[cfg(feature = "jit")]
    probe();
}

/// `tape` as machine code, or `None` where Cranelift fails (the failure recorded) or the
/// environment turns it off.
#[cfg(feature = "jit")]
pub(super) fn compile(tape: &super::Tape) -> Option<super::Jitted> {
    if turned_off() {
        return None;
    }
    super::Jitted::compile(tape).map_err(fail).ok()
}

/// Records Cranelift's failure if it is the first, and reports it.
#[cfg(feature = "jit")]
fn fail(failure: JitError) {
    let due = {
        let mut record = record();
        if record.failure.is_some() {
            return;
        }
        record.failure = Some(failure);
        due(&mut record)
    };
    if let Some((report, why)) = due {
        report(&why);
    }
}

/// Compiles `x·sin x + x²` once per process: the whole path a formula takes (the host's
/// ISA, code with a call, executable memory), so that a failure is recorded at once.
#[cfg(feature = "jit")]
fn probe() {
    use super::{Func, Graph, Tape};
    static PROBE: std::sync::Once = std::sync::Once::new();
    PROBE.call_once(|| {
        let mut g = Graph::new();
        let x = g.var(0);
        let sin = g.call(Func::Sin, x);
        let term = g.mul(x, sin);
        let square = g.powi(x, 2);
        let sum = g.add(term, square);
        let _ = compile(&Tape::compile(&g, &[sum], 1));
    });
}
