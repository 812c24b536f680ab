//! The driver's terms of a system given as formulas, remembered per thread for the last ζ.
//!
//! A step asks for `A(ζ)`, `∇V` and `V_d(ζ)` at one ζ through separate calls; a built-in
//! system's are inlined and share one `sin_cos`, but a tape computes them all at once. So
//! the first call at a ζ runs the driver's tape and keeps every output, and the next calls
//! at the same ζ (same bits, same compilation) read them.

use super::compile::Compiled;
use std::cell::RefCell;

/// Most outputs of a driver tape: `V_d`, `V_d′`, `V_d″`, and `A`, `dA/dζ` of at most 5 × 6.
pub(crate) const MAX_OUTPUTS: usize = 3 + 2 * 5 * 6;

struct Last {
    id: u64,
    zeta: u64,
    values: [f64; MAX_OUTPUTS],
}

thread_local! {
    static LAST: RefCell<Last> =
        const { RefCell::new(Last { id: 0, zeta: 0, values: [0.0; MAX_OUTPUTS] }) };
}

/// `f` of the driver tape's outputs at ζ.
#[inline]
pub(crate) fn with_driver_terms<T>(c: &Compiled, zeta: f64, f: impl FnOnce(&[f64]) -> T) -> T {
    LAST.with_borrow_mut(|last| {
        let k = c.driver.outputs();
        if last.id != c.id || last.zeta != zeta.to_bits() {
            c.driver.eval(&[zeta], &mut last.values[..k]);
            (last.id, last.zeta) = (c.id, zeta.to_bits());
        }
        f(&last.values[..k])
    })
}
