//! The driver's terms of a system given as formulas, remembered per thread for the last ζ.
//!
//! A step asks for `A(ζ)`, `∇V` and `V_d(ζ)` at one ζ through separate calls; a built-in
//! system's are inlined and share one `sin_cos`, but compiled formulas compute them all at
//! once. So the first call at a ζ runs the driver's code and keeps every output, and the
//! next calls at the same ζ (same bits, same compilation) read them. (Where ζ is an angle
//! the code reads `sin ζ` and `cos ζ` too, `sin_cos(ζ)` here; a Newton iteration that carries
//! them by rotation calls the code directly, `System::driver_terms_trig`.)

use super::compile::Compiled;
use std::cell::RefCell;

/// Most outputs of a driver's code: `V_d`, `V_d′`, `V_d″`, and `A`, `dA/dζ` of at most 5 × 6.
pub(crate) const MAX_OUTPUTS: usize = 3 + 2 * 5 * 6;

struct Last {
    id: u64,
    /// ζ's bits.
    zeta: u64,
    values: [f64; MAX_OUTPUTS],
    /// The tape's slots, where it is interpreted: with the values, so that one thread-local
    /// access serves both.
    slots: Vec<f64>,
}

thread_local! {
    static LAST: RefCell<Last> = const {
        RefCell::new(Last {
            id: 0,
            zeta: 0,
            values: [0.0; MAX_OUTPUTS],
            slots: Vec::new(),
        })
    };
}

/// `f` of the driver's outputs at ζ.
#[inline]
pub(crate) fn with_driver_terms<T>(c: &Compiled, zeta: f64, f: impl FnOnce(&[f64]) -> T) -> T {
    LAST.with_borrow_mut(|last| {
        let k = c.driver.outputs();
        if last.id != c.id || last.zeta != zeta.to_bits() {
            let (s, co) = if c.angle { zeta.sin_cos() } else { (0.0, 0.0) };
            let Last { values, slots, .. } = last;
            c.driver.eval_with(&[zeta, s, co], slots, &mut values[..k]);
            (last.id, last.zeta) = (c.id, zeta.to_bits());
        }
        f(&last.values[..k])
    })
}
