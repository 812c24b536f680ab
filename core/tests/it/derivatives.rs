//! Every system's hand-written derivatives against central finite differences, its kernel
//! against its constraint, its presets against the constraints, the full rank of A that
//! `rank_is_constant` declares, the periodicity in ζ that
//! `zeta_is_angle` declares, the quadratic U and V_d that `quadratic_passenger` and
//! `quadratic_driver` declare, the absent U that `free_passenger` declares, and its driver
//! terms from sin/cos against the plain functions.

use nhlab_core::BuiltIn;
use nhlab_core::{Matrix, System, Vector};
use std::f64::consts::TAU;

const H: f64 = 1e-5;
const TOL: f64 = 1e-8;

fn sample_points<const N: usize>() -> Vec<Vector<N>> {
    (0..7)
        .map(|k| Vector::<N>::from_fn(|i, _| ((k * 7 + i * 3) as f64 * 0.37).sin() * 2.0))
        .collect()
}

fn check<S: BuiltIn<N, R>, const N: usize, const R: usize>() {
    let id = S::info().id;
    for eps in [0.0, 0.3] {
        let params: Vec<f64> = S::info().params.iter().map(|_| eps).collect();
        let sys = S::new(&params);
        for q in sample_points::<N>() {
            let g = sys.gradient(&q);
            let hess = sys.hessian(&q);
            for i in 0..N {
                let mut e = Vector::<N>::zeros();
                e[i] = H;
                let fd = (sys.potential(&(q + e)) - sys.potential(&(q - e))) / (2.0 * H);
                assert!((fd - g[i]).abs() < TOL, "{id}: dV/dq{i} {fd} vs {}", g[i]);
                let fd_col = (sys.gradient(&(q + e)) - sys.gradient(&(q - e))) / (2.0 * H);
                assert!((fd_col - hess.column(i)).amax() < TOL, "{id}: Hessian column {i}");
            }
            let z = q[N - 1];
            if sys.rank_is_constant() {
                // Declared of full rank everywhere: sampled over two turns.
                for k in 0..200 {
                    let a = sys.constraint(-TAU + k as f64 * 0.0628);
                    let smallest =
                        nalgebra::DMatrix::from_fn(R, N, |i, j| a[(i, j)]).singular_values().min();
                    assert!(
                        smallest > 1e-3,
                        "{id}: A loses rank near ζ = {}",
                        -TAU + k as f64 * 0.0628
                    );
                }
            }
            let fd_a = (sys.constraint(z + H) - sys.constraint(z - H)) / (2.0 * H);
            assert!((fd_a - sys.constraint_d(z)).amax() < TOL, "{id}: dA/dζ at {z}");
            // The driver's terms the implicit steps take from a tracked sin/cos are the same
            // functions, to the bit.
            let terms = sys.driver_terms(z);
            let (s, c) = z.sin_cos();
            assert_eq!(sys.driver_terms_trig(z, s, c), terms, "{id}: driver_terms_trig at {z}");
            assert_eq!(
                (terms.constraint, terms.constraint_d),
                (sys.constraint(z), sys.constraint_d(z)),
                "{id}: driver_terms' A at {z}"
            );
            assert_eq!(
                [terms.potential, terms.potential_d1, terms.potential_d2],
                [sys.driver_potential(z), sys.driver_potential_d1(z), sys.driver_potential_d2(z)],
                "{id}: driver_terms' V_d at {z}"
            );
            let a: Matrix<R, N> = sys.constraint(z);
            assert!(a.column(N - 1).amax() == 0.0, "{id}: A must not involve ζ̇");
            let k = sys.kernel(z);
            assert!((a * k).amax() < 1e-14, "{id}: A k ≠ 0");
            assert!((k.norm() - 1.0).abs() < 1e-14 && k[N - 1] == 0.0, "{id}: k not unit");
            if sys.quadratic_passenger() {
                // What the coupled fast paths and DD's and DD-AVF's shortcuts rely on.
                let (origin, k) = (Vector::<N>::zeros(), sys.passenger_hessian(&q));
                assert_eq!(k, sys.passenger_hessian(&origin), "{id}: ∇²U not constant");
                let affine = sys.passenger_gradient(&origin) + k * q;
                assert!((sys.passenger_gradient(&q) - affine).amax() < 1e-14, "{id}: ∇U at {q}");
            }
            if sys.free_passenger() {
                // What DD's solve for the driver's speed alone relies on.
                assert_eq!(sys.passenger_potential(&q), 0.0, "{id}: U ≠ 0");
                assert_eq!(sys.passenger_gradient(&q), Vector::<N>::zeros(), "{id}: ∇U ≠ 0");
                assert_eq!(sys.passenger_hessian(&q), Matrix::<N, N>::zeros(), "{id}: ∇²U ≠ 0");
            }
            if sys.quadratic_driver() {
                // What DLA^α's fast path relies on when it takes one Newton step for the
                // driver, and DD's and DD-AVF's shortcuts.
                let d2 = sys.driver_potential_d2(z);
                assert_eq!(d2, sys.driver_potential_d2(0.0), "{id}: V_d'' not constant");
                let affine = sys.driver_potential_d1(0.0) + d2 * z;
                assert!((sys.driver_potential_d1(z) - affine).abs() < 1e-14, "{id}: V_d' at {z}");
            }
            if sys.zeta_is_angle() {
                // What the reference solve relies on when it takes whole turns off ζ.
                let turned = q + Vector::<N>::from_fn(|i, _| if i == N - 1 { TAU } else { 0.0 });
                assert!((sys.constraint(z + TAU) - a).amax() < 1e-12, "{id}: A not 2π-periodic");
                assert!((sys.potential(&turned) - sys.potential(&q)).abs() < 1e-12, "{id}: V");
                assert!((sys.gradient(&turned) - sys.gradient(&q)).amax() < 1e-12, "{id}: ∇V");
            }
        }
    }
    for p in S::info().presets {
        let mut params: Vec<f64> = S::info().params.iter().map(|s| s.default).collect();
        for (name, value) in p.params {
            let i = S::info().params.iter().position(|s| s.name == *name).unwrap();
            params[i] = *value;
        }
        let sys = S::new(&params);
        let (q, v) = (Vector::<N>::from_column_slice(p.q), Vector::<N>::from_column_slice(p.v));
        assert!(sys.constraint_residual(&q, &v) < 1e-12, "{id}/{}: inconsistent preset", p.id);
    }
}

#[test]
fn derivatives_kernels_and_presets() {
    for_each_system!(check);
}

#[test]
fn paper_energies() {
    use nhlab_core::systems::CvtPendulum;
    // `docs/model.md` §2: the CVT presets have H(0) = 2.8 and 5.0 (correction 1).
    for eps in [0.0, 0.5] {
        let sys = CvtPendulum::new(&[eps]);
        for (zdot, h0) in [(1.897_366_6, 2.8), (2.828_427_12, 5.0)] {
            let e = sys.energy(&Vector::<3>::new(1.0, 1.0, 0.0), &Vector::<3>::new(0.0, 0.0, zdot));
            assert!((e - h0).abs() < 1e-7, "H(0) = {e}, paper {h0}");
        }
    }
}
