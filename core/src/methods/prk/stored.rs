//! The tableaux nhlab stores, by id: the Lobatto IIIA–IIIB pairs of the SPARK methods, Gauss
//! and Radau IIA (`docs/model.md` §3). Gauss and Radau are built from their closed forms
//! (square roots of 3, 15 and 6, each rounded once); the Lobatto pairs are the SPARK tables.

use super::order::classical_order;
use super::tableau::{MAX_STAGES, Tableau, TableauSpec};
use crate::methods::spark::tableau::{LOBATTO2, LOBATTO3, LOBATTO4, LOBATTO5, Lobatto};
use std::sync::LazyLock;

/// A stored tableau with what `GET /systems` says of it.
#[derive(Debug)]
pub struct StoredTableau {
    /// Id, as a request names it (`"tableau": "gauss2"`).
    pub id: &'static str,
    /// Human name.
    pub name: &'static str,
    /// Where it comes from.
    pub reference: &'static str,
    /// The tableau.
    pub tableau: Tableau,
    /// Its classical order ([`classical_order`]).
    pub order: u32,
}

/// Every stored tableau.
pub fn stored() -> &'static [StoredTableau] {
    static STORED: LazyLock<Vec<StoredTableau>> = LazyLock::new(build);
    &STORED
}

/// The stored tableau `id`.
pub fn stored_tableau(id: &str) -> Option<&'static StoredTableau> {
    stored().iter().find(|t| t.id == id)
}

const HLW: &str = "Hairer & Wanner, Solving ODEs II, IV.5; Hairer, Lubich & Wanner, GNI II.1";

/// A stiffly accurate Runge–Kutta method (b is a's last row), not partitioned.
fn stiffly_accurate(id: &'static str, name: &'static str, a: Vec<Vec<f64>>) -> StoredTableau {
    let b = a[a.len() - 1].clone();
    entry_of(id, name, HLW, &TableauSpec { a, b, ..TableauSpec::default() })
}

fn entry_of(id: &'static str, name: &'static str, reference: &'static str, spec: &TableauSpec) -> StoredTableau {
    let tableau = Tableau::checked(spec).unwrap_or_else(|e| panic!("stored tableau {id}: {e}"));
    StoredTableau { id, name, reference, tableau, order: classical_order(&tableau) }
}

fn lobatto<const S: usize>(id: &'static str, t: &Lobatto<S>) -> StoredTableau {
    let rows = |m: &[[f64; S]; S]| m.iter().map(|r| r.to_vec()).collect();
    let spec = TableauSpec {
        a: rows(&t.a),
        b: t.b.to_vec(),
        c: Some(t.c.to_vec()),
        a_hat: Some(rows(&t.abar)),
        b_hat: Some(t.b.to_vec()),
    };
    entry_of(id, "Lobatto IIIA–IIIB", "Jay, BIT 43 (2003); Hairer & Wanner, Solving ODEs II, IV.5", &spec)
}

fn build() -> Vec<StoredTableau> {
    const _: () = assert!(MAX_STAGES >= 5);
    let (r3, r15, r6) = (3f64.sqrt(), 15f64.sqrt(), 6f64.sqrt());
    let gauss = |b: &[f64], a: Vec<Vec<f64>>| TableauSpec { a, b: b.to_vec(), ..TableauSpec::default() };
    vec![
        lobatto("lobatto2", &LOBATTO2),
        lobatto("lobatto3", &LOBATTO3),
        lobatto("lobatto4", &LOBATTO4),
        lobatto("lobatto5", &LOBATTO5),
        entry_of("gauss1", "Gauss (implicit midpoint)", HLW, &gauss(&[1.0], vec![vec![0.5]])),
        entry_of(
            "gauss2",
            "Gauss, 2 stages",
            HLW,
            &gauss(&[0.5, 0.5], vec![vec![0.25, 0.25 - r3 / 6.0], vec![0.25 + r3 / 6.0, 0.25]]),
        ),
        entry_of(
            "gauss3",
            "Gauss, 3 stages",
            HLW,
            &gauss(
                &[5.0 / 18.0, 4.0 / 9.0, 5.0 / 18.0],
                vec![
                    vec![5.0 / 36.0, 2.0 / 9.0 - r15 / 15.0, 5.0 / 36.0 - r15 / 30.0],
                    vec![5.0 / 36.0 + r15 / 24.0, 2.0 / 9.0, 5.0 / 36.0 - r15 / 24.0],
                    vec![5.0 / 36.0 + r15 / 30.0, 2.0 / 9.0 + r15 / 15.0, 5.0 / 36.0],
                ],
            ),
        ),
        stiffly_accurate("radau2", "Radau IIA, 2 stages", vec![vec![5.0 / 12.0, -1.0 / 12.0], vec![0.75, 0.25]]),
        stiffly_accurate(
            "radau3",
            "Radau IIA, 3 stages",
            vec![
                vec![(88.0 - 7.0 * r6) / 360.0, (296.0 - 169.0 * r6) / 1800.0, (-2.0 + 3.0 * r6) / 225.0],
                vec![(296.0 + 169.0 * r6) / 1800.0, (88.0 + 7.0 * r6) / 360.0, (-2.0 - 3.0 * r6) / 225.0],
                vec![(16.0 - r6) / 36.0, (16.0 + r6) / 36.0, 1.0 / 9.0],
            ],
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stored_tableaux_have_their_known_orders_and_symmetry() {
        let expected = [
            ("lobatto2", 2, true),
            ("lobatto3", 4, true),
            ("lobatto4", 6, true),
            ("lobatto5", 8, true),
            ("gauss1", 2, true),
            ("gauss2", 4, true),
            ("gauss3", 6, true),
            ("radau2", 3, false),
            ("radau3", 5, false),
        ];
        assert_eq!(stored().len(), expected.len());
        for (id, order, symmetric) in expected {
            let t = stored_tableau(id).expect("stored");
            assert_eq!((t.order, t.tableau.symmetric()), (order, symmetric), "{id}");
        }
    }
}
