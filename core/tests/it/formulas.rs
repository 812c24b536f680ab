//! The formula compiler: symbolic derivatives against finite differences at random points
//! for random well-formed formulas; tapes against the graph they were compiled from; and
//! the parser against hostile input, which gets typed errors and never a panic.

use crate::common;
use nhlab_core::formula::derive::Derivative;
use nhlab_core::formula::parse::{Name, Names, parse};
use nhlab_core::formula::{FormulaError, Function, Graph, Limits, Tape};
use proptest::prelude::*;

/// Three variables `x`, `y`, `z` and a parameter `k = 0.7`.
struct Xyz;

impl Names for Xyz {
    fn resolve(&self, name: &str) -> Option<Name> {
        match name {
            "x" => Some(Name::Var(0)),
            "y" => Some(Name::Var(1)),
            "z" => Some(Name::Var(2)),
            "k" => Some(Name::Value(0.7)),
            "w" => Some(Name::Forbidden("w is the driver".into())),
            _ => None,
        }
    }
    fn allowed(&self) -> String {
        "x, y, z, k".into()
    }
}

fn compile(text: &str) -> Result<(Graph, nhlab_core::formula::Id), FormulaError> {
    let mut g = Graph::new();
    let e = parse(&mut g, text, &Xyz, &Limits::default())?;
    Ok((g, e))
}

/// Random formulas that are smooth and finite near the points below: sums, products,
/// quotients by `2 + sin` or `1 + e²`, small integer powers and the functions on arguments
/// where they are defined.
fn formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        Just("x".to_string()),
        Just("y".to_string()),
        Just("z".to_string()),
        Just("k".to_string()),
        (1u32..9).prop_map(|n| format!("{}.5", n)),
    ];
    leaf.prop_recursive(5, 40, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} + {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} - {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("{a}*{b}")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("{a}/(2 + sin({b}))")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("{a}/(1 + ({b})^2)")),
            (inner.clone(), 2i32..4).prop_map(|(a, k)| format!("({a})^{k}")),
            inner.clone().prop_map(|a| format!("-{a}")),
            inner.clone().prop_map(|a| format!("sin({a})")),
            inner.clone().prop_map(|a| format!("cos(2*{a})")),
            inner.clone().prop_map(|a| format!("exp(sin({a}))")),
            inner.clone().prop_map(|a| format!("log(1 + ({a})^2)")),
            inner.clone().prop_map(|a| format!("sqrt(1 + ({a})^2)")),
            inner.clone().prop_map(|a| format!("atan({a})")),
            inner.clone().prop_map(|a| format!("tanh({a}) + cosh(sin({a})) + sinh(cos({a}))")),
            inner.prop_map(|a| format!("(2 + cos({a}))^k")),
        ]
    })
}

/// Central difference of `f` along variable `i`, and its error estimate from two steps.
fn central(f: &dyn Fn(&[f64; 3]) -> f64, p: &[f64; 3], i: usize) -> (f64, f64) {
    let d = |h: f64| {
        let (mut a, mut b) = (*p, *p);
        a[i] += h;
        b[i] -= h;
        (f(&a) - f(&b)) / (2.0 * h)
    };
    let (coarse, fine) = (d(1e-4), d(5e-5));
    (fine, (coarse - fine).abs())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 300,
        failure_persistence: common::regressions(),
        ..ProptestConfig::default()
    })]

    /// ∂f/∂xᵢ and ∂²f/∂xᵢ∂xⱼ against central differences of the graph's own evaluation, and
    /// the tapes against the graph.
    #[test]
    fn derivatives_match_finite_differences(
        text in formula(),
        p in prop::array::uniform3(-1.5f64..1.5),
    ) {
        let (mut g, e) = compile(&text).expect("well-formed");
        let mut by_var: Vec<Derivative> = (0..3).map(Derivative::new).collect();
        let grad: Vec<_> = by_var.iter_mut().map(|d| d.of(&mut g, e)).collect();
        let second: Vec<Vec<_>> = grad
            .iter()
            .map(|&gi| by_var.iter_mut().map(|d| d.of(&mut g, gi)).collect())
            .collect();
        let g = g;
        let value = g.eval(e, &p);
        prop_assume!(value.is_finite() && value.abs() < 1e6);
        let f = |x: &[f64; 3]| g.eval(e, x);
        for i in 0..3 {
            let exact = g.eval(grad[i], &p);
            let (fd, err) = central(&f, &p, i);
            let tol = 1e-6 * (1.0 + exact.abs()) + 10.0 * err;
            prop_assert!((exact - fd).abs() <= tol, "{text}: ∂{i} {exact} vs {fd}");
            for (j, &dij) in second[i].iter().enumerate() {
                let gi = |x: &[f64; 3]| g.eval(grad[i], x);
                let (fd, err) = central(&gi, &p, j);
                let exact = g.eval(dij, &p);
                let tol = 1e-5 * (1.0 + exact.abs()) + 10.0 * err;
                prop_assert!((exact - fd).abs() <= tol, "{text}: ∂{i}∂{j} {exact} vs {fd}");
            }
        }
        let mut outputs = vec![e];
        outputs.extend(&grad);
        let tape = Tape::compile(&g, &outputs, 3);
        let mut out = vec![0.0; outputs.len()];
        tape.eval(&p, &mut out);
        // The machine code computes what the tape does, bit for bit (without the JIT, both
        // are the tape: the evaluations into uninitialized memory are still checked).
        let native = Function::new(tape.clone(), true);
        prop_assert_eq!(native.is_native(), crate::common::machine_code());
        let mut fast = vec![0.0; outputs.len()];
        native.eval(&p, &mut fast);
        // So do both into uninitialized memory, as the steps call them.
        let interpreted = Function::new(tape.clone(), false);
        let mut spare = [std::mem::MaybeUninit::uninit(); 4];
        let fast_uninit = native.eval_uninit(&p, &mut spare).to_vec();
        let slow_uninit = interpreted.eval_uninit(&p, &mut spare).to_vec();
        prop_assert!(fast_uninit.len() == out.len() && slow_uninit.len() == out.len());
        for ((a, b), (c, d)) in fast.iter().zip(&out).zip(fast_uninit.iter().zip(&slow_uninit)) {
            for x in [a, c, d] {
                prop_assert!(x.to_bits() == b.to_bits() || (x.is_nan() && b.is_nan()), "{text}: {x} vs {b}");
            }
        }
        for (k, &o) in outputs.iter().enumerate() {
            let want = g.eval(o, &p);
            prop_assert!(out[k] == want || (out[k] - want).abs() <= 1e-13 * want.abs().max(1.0),
                "{text}: tape {} vs graph {want}", out[k]);
        }
    }

    /// Any text: a formula or a typed error, never a panic.
    #[test]
    fn any_text_parses_or_fails_cleanly(text in "[-+*/^() xyzkw0-9.esincoqrtlgpa_,]{0,80}") {
        let _ = compile(&text);
    }
}

fn error(text: &str) -> FormulaError {
    compile(text).err().unwrap_or_else(|| panic!("{text} should not parse"))
}

#[test]
fn errors_say_what_and_where() {
    assert_eq!(
        error("k*(x^2 + y^2))").to_string(),
        "unexpected ')' at 14; expected an operator or the end of the formula"
    );
    assert!(matches!(error("sinn(x)"), FormulaError::UnknownFunction { at: 1, .. }));
    assert!(matches!(error("x + q"), FormulaError::UnknownName { at: 5, .. }));
    assert!(matches!(error("x*w"), FormulaError::Forbidden { at: 3, .. }));
    assert!(matches!(error("sin + 1"), FormulaError::BareFunction { .. }));
    assert!(matches!(error("2 ** x"), FormulaError::Unexpected { at: 4, .. }));
    assert!(matches!(error("(x"), FormulaError::Unexpected { .. }));
    assert!(matches!(error("1e400"), FormulaError::BadNumber { .. }));
    assert!(matches!(error("   "), FormulaError::Empty));
    assert!(matches!(error("NaN"), FormulaError::UnknownName { .. }));
    assert!(matches!(error("x−1"), FormulaError::Unexpected { at: 2, .. }), "a unicode minus");
}

#[test]
fn hostile_input_is_refused_without_a_panic() {
    // Deep nesting of every kind, far beyond the limit: refused at the limit, no recursion.
    for text in [
        format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000)),
        format!("{}x", "-".repeat(100_000)),
        format!("x{}", "^x".repeat(50_000)),
        format!("{}x{}", "sin(".repeat(50_000), ")".repeat(50_000)),
    ] {
        let limits = Limits { max_chars: usize::MAX, ..Limits::default() };
        let mut g = Graph::new();
        let e = parse(&mut g, &text, &Xyz, &limits).unwrap_err();
        assert!(matches!(e, FormulaError::TooDeep { limit: 64, .. }), "{e}");
    }
    // 10⁵ characters: refused before parsing.
    let long = format!("x{}", "+x".repeat(50_000));
    assert!(matches!(error(&long), FormulaError::TooLong { chars: 100_001, limit: 2000 }));
    // A long flat sum within the limits parses, and its derivative is small.
    let (mut g, e) = compile(&format!("x{}", "+x*y".repeat(399))).unwrap();
    let d = Derivative::new(0).of(&mut g, e);
    assert_eq!(g.eval(d, &[1.0, 2.0, 0.0]), 1.0 + 399.0 * 2.0);
    // Division by zero and overflow evaluate to inf or NaN: the runs report them.
    let (g, e) = compile("1/(x - x*1)").unwrap();
    assert!(!g.eval(e, &[1.0, 0.0, 0.0]).is_finite());
    // Nesting exactly at the limit is fine.
    compile(&format!("{}x{}", "(".repeat(63), ")".repeat(63))).unwrap();
}

#[test]
fn sine_and_cosine_of_one_argument_are_one_sin_cos_and_double_angles_share_it() {
    let (mut g, e) = compile("1 - cos(x) - k*sin(2*x)/2").unwrap();
    let d1 = Derivative::new(0).of(&mut g, e);
    let tape = Tape::compile(&g, &[e, d1], 1);
    let mut out = [0.0; 2];
    tape.eval(&[0.3], &mut out);
    let (s, c) = 0.3f64.sin_cos();
    assert!((out[0] - (1.0 - c - 0.7 * s * c)).abs() < 1e-15);
    assert!((out[1] - (s - 0.7 * (c * c - s * s))).abs() < 1e-15);
    // sin x and cos x: one sin_cos, shared by V, V′ and the double angles.
    assert_eq!(tape.calls(), 1, "{tape:?}");
}

/// The largest system the limits allow compiles: six passengers, a U of nearly 2,000
/// characters (its Hessian has 21 entries), five constraints. Its tapes are scheduled and
/// compiled in time linear-logarithmic in their length, and one evaluation agrees with the
/// graph it came from.
#[test]
fn the_largest_system_the_limits_allow_compiles() {
    use nhlab_core::{CustomLimits, CustomSystem, FormulaSpec};
    let names = ["a", "b", "c", "d", "e", "f"];
    let mut u = String::from("0");
    let mut i = 0;
    while u.len() < 1900 {
        let (x, y) = (names[i % 6], names[(i + 1) % 6]);
        u.push_str(&format!("+sin({x}*{y}+{i})*exp(cos({y})/3)"));
        i += 1;
    }
    let spec = FormulaSpec {
        name: "large".into(),
        passenger: names.iter().map(|s| s.to_string()).collect(),
        driver: "z".into(),
        parameters: Vec::new(),
        passenger_potential: u,
        driver_potential: "1 - cos(z)".into(),
        constraints: (0..5)
            .map(|r| {
                (0..6).map(|j| if j == r { "1".into() } else { format!("sin({j}*z)") }).collect()
            })
            .collect(),
    };
    let c = CustomSystem::compile(&spec, &[], &CustomLimits::default()).unwrap();
    assert!(!c.class_compiled().unwrap().quadratic_passenger);
    c.check_start(&[0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.0]).unwrap();
}

/// A constant power's derivative is `c a^(c−1) a'`, finite where a = 0 (the general rule for
/// `a^b` would give 0·(…/0) there).
#[test]
fn a_constant_powers_derivative_is_finite_at_zero() {
    let (mut g, e) = compile("(x^2 + y^2)^1.5").unwrap();
    let d = Derivative::new(0).of(&mut g, e);
    assert_eq!(g.eval(d, &[0.0, 0.0, 0.0]), 0.0);
    assert!((g.eval(d, &[1.0, 0.0, 0.0]) - 3.0).abs() < 1e-15);
}

/// A tape of more variables than the machine code takes in registers reads the rest from
/// memory: the same numbers as the interpreter, bit for bit.
#[test]
#[cfg_attr(not(feature = "jit"), ignore = "no machine code without the `jit` feature")]
fn machine_code_reads_variables_beyond_the_registers() {
    use nhlab_core::formula::{Function, Graph, Tape};
    if !crate::common::machine_code() {
        eprintln!("skipped: NHLAB_JIT=off");
        return;
    }
    let mut g = Graph::new();
    let vars: Vec<_> = (0..9).map(|i| g.var(i)).collect();
    let mut sum = g.num(0.0);
    for (i, &v) in vars.iter().enumerate() {
        let k = g.num(i as f64 + 0.5);
        let s = g.call(nhlab_core::formula::Func::Sin, v);
        let term = g.mul(k, s);
        sum = g.add(sum, term);
    }
    let last = g.mul(vars[8], vars[6]);
    let tape = Tape::compile(&g, &[sum, last, vars[7]], 9);
    let (native, interpreted) = (Function::new(tape.clone(), true), Function::new(tape, false));
    assert!(native.is_native(), "nine variables compile to machine code");
    let x: Vec<f64> = (0..9).map(|i| 0.3 * i as f64 - 1.1).collect();
    let (mut a, mut b) = ([0.0; 3], [0.0; 3]);
    native.eval(&x, &mut a);
    interpreted.eval(&x, &mut b);
    assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
    assert_eq!(a[2], x[7]);
}

/// Where formulas run is told: as machine code with the `jit` feature (this host is one
/// Cranelift supports) unless `NHLAB_JIT=off`, on the interpreter otherwise, with the reason;
/// and a registered report is made once, at registration, exactly when they fall back.
#[test]
fn native_code_status_says_where_formulas_run() {
    use nhlab_core::formula::{native_code_status, on_interpreter_fallback};
    use std::sync::atomic::{AtomicUsize, Ordering};
    static REPORTS: AtomicUsize = AtomicUsize::new(0);
    let status = native_code_status();
    assert_eq!(status.compiled_in, cfg!(feature = "jit"));
    assert_eq!(status.native(), crate::common::machine_code(), "{status:?}");
    assert_eq!(status.why_not().is_some(), !status.native());
    if let Some(why) = status.why_not() {
        assert!(why.contains("interpreter"), "{why}");
        let turned_off = cfg!(feature = "jit") && status.turned_off;
        assert_eq!(why.contains("NHLAB_JIT=off"), turned_off, "{why}");
    }
    // The only registration in this process.
    on_interpreter_fallback(|why| {
        assert!(why.contains("interpreter"), "{why}");
        REPORTS.fetch_add(1, Ordering::SeqCst);
    });
    on_interpreter_fallback(|_| {
        REPORTS.fetch_add(1, Ordering::SeqCst);
    });
    assert_eq!(REPORTS.load(Ordering::SeqCst), usize::from(!status.native()));
}
