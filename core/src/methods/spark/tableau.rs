//! The Lobatto IIIA–IIIB pairs of the SPARK methods (`docs/model.md` §3): nodes c, weights b,
//! the IIIA matrix `a` (positions, and the weights of the stage conditions) and the IIIB matrix
//! `ā` (velocities and the multipliers), for s = 2 … 5 stages. Their exact values lie in
//! ℚ(√5) and ℚ(√21); they are written here rounded once from 50-digit values (building them
//! in f64 from the simplifying conditions would lose up to 3·10⁻¹⁵). The tests check them:
//! the simplifying conditions C(s) for IIIA and D(s) for IIIB, IIIB as the symplectic
//! conjugate of IIIA, the quadrature of order 2s − 2, the symmetry a_ij + a_{s+1−i,s+1−j} = b_j.

/// One pair: `S` stages.
#[derive(Debug)]
pub(crate) struct Lobatto<const S: usize> {
    /// Nodes c.
    pub c: [f64; S],
    /// Weights b.
    pub b: [f64; S],
    /// Lobatto IIIA: row 1 is zero, row s is b.
    pub a: [[f64; S]; S],
    /// Lobatto IIIB: its last column is zero.
    pub abar: [[f64; S]; S],
    /// The products (aā)_im = Σ_l a_il ā_lm, which the step's Jacobian takes
    /// ([`Lobatto::with_products`]).
    pub aa: [[f64; S]; S],
}

impl<const S: usize> Lobatto<S> {
    /// The pair with its products `aa` filled in.
    const fn with_products(mut self) -> Self {
        let mut i = 0;
        while i < S {
            let mut m = 0;
            while m < S {
                let (mut sum, mut l) = (0.0, 0);
                while l < S {
                    sum += self.a[i][l] * self.abar[l][m];
                    l += 1;
                }
                self.aa[i][m] = sum;
                m += 1;
            }
            i += 1;
        }
        self
    }
}

#[allow(clippy::excessive_precision, reason = "rounded once from 50 digits; kept as printed")]
pub(crate) const LOBATTO2: Lobatto<2> = Lobatto {
    aa: [[0.0; 2]; 2],
    c: [0.0, 1.00000000000000000000],
    b: [5.00000000000000000000e-1, 5.00000000000000000000e-1],
    a: [
    [0.0, 0.0],
    [5.00000000000000000000e-1, 5.00000000000000000000e-1],
],
    abar: [
    [5.00000000000000000000e-1, 0.0],
    [5.00000000000000000000e-1, 0.0],
],
}
.with_products();

#[allow(clippy::excessive_precision, reason = "rounded once from 50 digits; kept as printed")]
pub(crate) const LOBATTO3: Lobatto<3> = Lobatto {
    aa: [[0.0; 3]; 3],
    c: [0.0, 5.00000000000000000000e-1, 1.00000000000000000000],
    b: [1.66666666666666666667e-1, 6.66666666666666666667e-1, 1.66666666666666666667e-1],
    a: [
    [0.0, 0.0, 0.0],
    [2.08333333333333333333e-1, 3.33333333333333333333e-1, -4.16666666666666666667e-2],
    [1.66666666666666666667e-1, 6.66666666666666666667e-1, 1.66666666666666666667e-1],
],
    abar: [
    [1.66666666666666666667e-1, -1.66666666666666666667e-1, 0.0],
    [1.66666666666666666667e-1, 3.33333333333333333333e-1, 0.0],
    [1.66666666666666666667e-1, 8.33333333333333333333e-1, 0.0],
],
}
.with_products();

#[allow(clippy::excessive_precision, reason = "rounded once from 50 digits; kept as printed")]
pub(crate) const LOBATTO4: Lobatto<4> = Lobatto {
    aa: [[0.0; 4]; 4],
    c: [0.0, 2.76393202250021030359e-1, 7.23606797749978969641e-1, 1.00000000000000000000],
    b: [8.33333333333333333333e-2, 4.16666666666666666667e-1, 4.16666666666666666667e-1, 8.33333333333333333333e-2],
    a: [
    [0.0, 0.0, 0.0, 0.0],
    [1.10300566479164914137e-1, 1.89699433520835085863e-1, -3.39073642291438837777e-2, 1.03005664791649141367e-2],
    [7.30327668541684191966e-2, 4.50574030895810550444e-1, 2.26967233145831580803e-1, -2.69672331458315808034e-2],
    [8.33333333333333333333e-2, 4.16666666666666666667e-1, 4.16666666666666666667e-1, 8.33333333333333333333e-2],
],
    abar: [
    [8.33333333333333333333e-2, -1.34836165729157904017e-1, 5.15028323958245706837e-2, 0.0],
    [8.33333333333333333333e-2, 2.26967233145831580803e-1, -3.39073642291438837777e-2, 0.0],
    [8.33333333333333333333e-2, 4.50574030895810550444e-1, 1.89699433520835085863e-1, 0.0],
    [8.33333333333333333333e-2, 3.65163834270842095983e-1, 5.51502832395824570684e-1, 0.0],
],
}
.with_products();

#[allow(clippy::excessive_precision, reason = "rounded once from 50 digits; kept as printed")]
pub(crate) const LOBATTO5: Lobatto<5> = Lobatto {
    aa: [[0.0; 5]; 5],
    c: [0.0, 1.72673164646011428101e-1, 5.00000000000000000000e-1, 8.27326835353988571899e-1, 1.00000000000000000000],
    b: [5.00000000000000000000e-2, 2.72222222222222222222e-1, 3.55555555555555555556e-1, 2.72222222222222222222e-1, 5.00000000000000000000e-2],
    a: [
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [6.77284321861568979693e-2, 1.19744769343411682516e-1, -2.17357218665581136655e-2, 1.06358242254154918831e-2, -3.70013924241453060216e-3],
    [4.06250000000000000000e-2, 3.03184183323042778018e-1, 1.77777777777777777778e-1, -3.09619611008205557957e-2, 9.37500000000000000000e-3],
    [5.37001392424145306022e-2, 2.61586397996806730339e-1, 3.77291277422113669221e-1, 1.52477452878810539706e-1, -1.77284321861568979693e-2],
    [5.00000000000000000000e-2, 2.72222222222222222222e-1, 3.55555555555555555556e-1, 2.72222222222222222222e-1, 5.00000000000000000000e-2],
],
    abar: [
    [5.00000000000000000000e-2, -9.65214641246320000549e-2, 6.66666666666666666667e-2, -2.01452025420346666118e-2, 0.0],
    [5.00000000000000000000e-2, 1.52477452878810539706e-1, -4.04401124582146034883e-2, 1.06358242254154918831e-2, 0.0],
    [5.00000000000000000000e-2, 2.88863634276305777997e-1, 1.77777777777777777778e-1, -1.66414120540835557752e-2, 0.0],
    [5.00000000000000000000e-2, 2.61586397996806730339e-1, 3.95995668013770159044e-1, 1.19744769343411682516e-1, 0.0],
    [5.00000000000000000000e-2, 2.92367424764256888834e-1, 2.88888888888888888889e-1, 3.68743686346854222277e-1, 0.0],
],
}
.with_products();

#[cfg(test)]
mod tests {
    use super::*;

    fn check<const S: usize>(t: &Lobatto<S>) {
        let (a, abar, b, c) = (&t.a, &t.abar, &t.b, &t.c);
        let close = |x: f64, y: f64, what: &str| assert!((x - y).abs() < 4e-16, "s = {S}: {what}: {x} vs {y}");
        for k in 1..=(2 * S - 2) {
            let quadrature: f64 = (0..S).map(|j| b[j] * c[j].powi(k as i32 - 1)).sum();
            close(quadrature, 1.0 / k as f64, "B(2s − 2)");
        }
        for i in 0..S {
            close(a[0][i], 0.0, "IIIA's first row");
            close(a[S - 1][i], b[i], "IIIA's last row is b");
            close(abar[i][S - 1], 0.0, "IIIB's last column");
            for k in 1..=S {
                let ck: f64 = (0..S).map(|j| a[i][j] * c[j].powi(k as i32 - 1)).sum();
                close(ck, c[i].powi(k as i32) / k as f64, "C(s)");
                let dk: f64 = (0..S).map(|l| b[l] * c[l].powi(k as i32 - 1) * abar[l][i]).sum();
                close(dk, b[i] * (1.0 - c[i].powi(k as i32)) / k as f64, "D(s)");
            }
            for j in 0..S {
                close(abar[i][j], b[j] * (1.0 - a[j][i] / b[i]), "IIIB conjugate to IIIA");
                close(a[i][j] + a[S - 1 - i][S - 1 - j], b[j], "IIIA symmetric");
            }
            close(c[i] + c[S - 1 - i], 1.0, "nodes symmetric");
        }
    }

    #[test]
    fn the_tables_satisfy_their_conditions() {
        check(&LOBATTO2);
        check(&LOBATTO3);
        check(&LOBATTO4);
        check(&LOBATTO5);
    }
}
