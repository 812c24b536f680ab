//! Methods given as tableaux (`prk`, `docs/model.md` §3): on the Lobatto IIIA–IIIB pairs with
//! the `stage` constraint the same steps as SPARK to round-off; every stored tableau with
//! every constraint it takes at its declared order on the knife edge's exact solution and on
//! the Chaplygin sleigh; symmetry where declared; bad tableaux refused at their field.

use crate::common::knife_exact;
use crate::spark::{observed, sleigh, sleigh_error};
use nhlab_core::measure::reference::reference;
use nhlab_core::methods::prk::stored::stored;
use nhlab_core::methods::{Prk, TableauChoice};
use nhlab_core::systems::KnifeEdge;
use nhlab_core::{BuiltIn, GeneralMemory, Mechanical, Method, MethodSpec, State};

fn prk(tableau: &str, constraint: &str) -> Option<Method> {
    let spec = MethodSpec {
        tableau: Some(TableauChoice::Stored(tableau.into())),
        constraint: Some(constraint.into()),
        ..MethodSpec::new("prk")
    };
    Method::from_spec(&spec).ok()
}

#[test]
fn prk_on_the_lobatto_pairs_is_spark() {
    let (sys, start) = sleigh();
    for s in 2..=5u8 {
        let p = prk(&format!("lobatto{s}"), "stage").expect("builds");
        let spark =
            Method::from_spec(&MethodSpec::new("spark").with("stages", f64::from(s))).unwrap();
        assert_eq!(p.order(), spark.order());
        assert!(p.base.symmetric());
        for h in [0.05, 0.5] {
            let (mut a, mut b) = (start, start);
            let (mut ma, mut mb) = (GeneralMemory::empty(), GeneralMemory::empty());
            for _ in 0..40 {
                p.step_general(&sys, &mut a, &mut ma, h).unwrap();
                spark.step_general(&sys, &mut b, &mut mb, h).unwrap();
            }
            let size = 1.0 + b.q.amax().max(b.v.amax());
            let off = (a.q - b.q).amax().max((a.v - b.v).amax()) / size;
            assert!(off < 1e-11, "lobatto{s} h = {h}: PRK and SPARK differ by {off:e}");
        }
    }
}

/// Every stored tableau with every constraint it takes, and the order measured.
fn each(mut f: impl FnMut(&str, &str, Method)) {
    for t in stored() {
        for c in ["stage", "end", "midpoint"] {
            if let Some(m) = prk(t.id, c) {
                f(t.id, c, m);
            }
        }
    }
}

#[test]
fn every_stored_tableau_reaches_its_declared_order_on_the_knife_edge() {
    let sys = KnifeEdge::new(&[0.0]);
    let (start, end) = (knife_exact(0.0), knife_exact(10.0));
    let mut failures = Vec::new();
    each(|id, c, m| {
        let order = m.order();
        for (what, pick) in [("q", 0), ("q̇", 1)] {
            let err = |n: u32| {
                let mut st = State::with_continuous_multiplier(&sys, start.0, start.1).unwrap();
                let mut memory = m.memory();
                for _ in 0..n {
                    m.step(&sys, &mut st, &mut memory, 10.0 / n as f64).unwrap();
                }
                if pick == 0 { (st.q - end.0).amax() } else { (st.v - end.1).amax() }
            };
            let (p, shown) = observed(order, 10.0, err);
            println!("knife_edge {id} {c} in {what}: declared {order}, measured {p:.2}, {shown:?}");
            if p.is_finite() && p < order as f64 - 0.2 - 0.05 * order as f64 {
                failures.push(format!("{id} {c} in {what}: {p:.2} < {order}"));
            }
        }
    });
    assert!(failures.is_empty(), "{failures:?}");
}

#[test]
fn every_stored_tableau_reaches_its_declared_order_on_the_chaplygin_sleigh() {
    let (sys, start) = sleigh();
    let t_end = 5.0;
    let r = reference(&sys, &start.q, &start.v, t_end, 1e-15).unwrap();
    let mut failures = Vec::new();
    each(|id, c, m| {
        let order = m.order();
        let err = |n| sleigh_error(&sys, &m, &start, (&r.q, &r.v), t_end, n);
        let (p, shown) = observed(order, t_end, err);
        println!("chaplygin_sleigh {id} {c}: declared {order}, measured {p:.2}, {shown:?}");
        if p < order as f64 - 0.2 - 0.05 * order as f64 {
            failures.push(format!("{id} {c}: {p:.2} < {order}"));
        }
    });
    assert!(failures.is_empty(), "{failures:?}");
}

#[test]
fn symmetric_where_declared() {
    let (sys, start) = sleigh();
    each(|id, c, m| {
        let step = |st: &mut State<3, 1>, h: f64| {
            m.step_general(&sys, st, &mut GeneralMemory::empty(), h).unwrap();
        };
        let h = 0.2;
        let mut st = start;
        step(&mut st, h);
        let mut back = st;
        step(&mut back, -h);
        let off = (back.q - start.q).amax().max((back.v - start.v).amax());
        println!("{id} {c}: declared symmetric {}, Φ₋ₕ∘Φₕ off by {off:.1e}", m.base.symmetric());
        if m.base.symmetric() {
            assert!(off < 1e-13, "{id} {c}: declared symmetric, Φ₋ₕ∘Φₕ off by {off:e}");
        } else {
            assert!(off > 1e-12, "{id} {c}: symmetric but not declared so ({off:e})");
        }
        if c != "midpoint" {
            assert!((sys.constraint(&st.q) * st.v).amax() < 1e-14, "{id} {c}: off the constraint");
        }
    });
}

#[test]
fn the_default_is_gauss2_with_stage_conditions() {
    let m = Method::from_spec(&MethodSpec::new("prk")).unwrap();
    assert_eq!(m.label(), "PRK[gauss2]");
    assert_eq!(m.base, Method::from(Prk::default()).base);
}
