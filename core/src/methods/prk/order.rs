//! The classical order of a tableau from its order conditions (`docs/model.md` §3): the
//! conditions of a partitioned Runge–Kutta method, one per bicoloured rooted tree (Hairer,
//! Lubich & Wanner, III.2), on the equations of motion without constraint, `q̇ = v`,
//! `v̇ = g(q, v)`. Black vertices stand for `q̇ = v`, white for `v̇ = g`; as `v` is linear and
//! free of q, a black vertex is a leaf or has exactly one white child, which leaves far fewer
//! trees than a general partitioned system has. The condition of a tree t is
//! `Σ_i w_i Ψ_i(t) = 1/γ(t)`, with w = b for a black root and b̂ for a white one,
//! `Ψ_i(t) = Π_children u (A_u Ψ(u))_i`, A_u = a for a black child and â for a white one, and
//! γ the tree's density.

use super::tableau::{MAX_STAGES, Tableau};

/// The highest order checked. An order found below it is exact; a tableau that meets every
/// condition up to it (Gauss with 5 stages, of order 10) is reported at it, as a lower bound.
/// The trees to order 9 are some 17,000, built in milliseconds; to order 11 they would be
/// a quarter of a million.
pub const MAX_ORDER: usize = 9;

/// A condition holds when its two sides differ by less than this.
const TOLERANCE: f64 = 1e-11;

/// One tree: its root's colour, its order, its density γ and its children (by index).
struct Tree {
    white: bool,
    order: usize,
    density: f64,
    children: Vec<usize>,
}

/// Every tree of the class up to [`MAX_ORDER`], by order (built once).
fn trees() -> &'static [Tree] {
    static TREES: std::sync::LazyLock<Vec<Tree>> = std::sync::LazyLock::new(build);
    &TREES
}

fn build() -> Vec<Tree> {
    let mut trees: Vec<Tree> = vec![Tree { white: false, order: 1, density: 1.0, children: vec![] }];
    trees.push(Tree { white: true, order: 1, density: 1.0, children: vec![] });
    for n in 2..=MAX_ORDER {
        let below = trees.len();
        let mut whites = Vec::new();
        multisets(&trees[..below], n - 1, 0, &mut Vec::new(), &mut whites);
        for children in whites {
            let density = n as f64 * children.iter().map(|&u| trees[u].density).product::<f64>();
            trees.push(Tree { white: true, order: n, density, children });
        }
        // A black root of order n has one white child of order n − 1.
        let blacks: Vec<usize> =
            (0..below).filter(|&u| trees[u].white && trees[u].order == n - 1).collect();
        for u in blacks {
            let density = n as f64 * trees[u].density;
            trees.push(Tree { white: false, order: n, density, children: vec![u] });
        }
    }
    trees
}

/// Every non-decreasing list of indices into `trees`, from `from` on, whose orders sum to
/// `left`: the children of one root, each multiset once.
fn multisets(trees: &[Tree], left: usize, from: usize, current: &mut Vec<usize>, out: &mut Vec<Vec<usize>>) {
    if left == 0 {
        out.push(current.clone());
        return;
    }
    for u in from..trees.len() {
        if trees[u].order <= left {
            current.push(u);
            multisets(trees, left - trees[u].order, u, current, out);
            current.pop();
        }
    }
}

/// The classical order of `t` on `q̇ = v`, `v̇ = g(q, v)`: the largest p such that every
/// condition of order ≤ p holds (0 if even Σb = 1 fails). The last few tableaux' orders are
/// kept, so that a sweep building one method per cell checks its conditions once.
pub fn classical_order(t: &Tableau) -> u32 {
    /// Tableaux whose order is kept.
    const KEPT: usize = 16;
    static RECENT: std::sync::Mutex<Vec<(Tableau, u32)>> = std::sync::Mutex::new(Vec::new());
    let lock = || RECENT.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some(&(_, p)) = lock().iter().find(|(k, _)| k == t) {
        return p;
    }
    let p = conditions_met(t);
    let mut recent = lock();
    if recent.len() == KEPT {
        recent.remove(0);
    }
    recent.push((*t, p));
    p
}

fn conditions_met(t: &Tableau) -> u32 {
    let s = t.stages;
    let trees = trees();
    let mut psi: Vec<[f64; MAX_STAGES]> = Vec::with_capacity(trees.len());
    let mut order = MAX_ORDER;
    for tree in trees {
        if tree.order > order {
            break;
        }
        let mut p = [0.0; MAX_STAGES];
        for (i, pi) in p.iter_mut().enumerate().take(s) {
            *pi = tree
                .children
                .iter()
                .map(|&u| {
                    let m = if trees[u].white { &t.a_hat } else { &t.a };
                    (0..s).map(|j| m[i][j] * psi[u][j]).sum::<f64>()
                })
                .product();
        }
        let w = if tree.white { &t.b_hat } else { &t.b };
        let lhs: f64 = (0..s).map(|i| w[i] * p[i]).sum();
        let holds = (lhs - 1.0 / tree.density).abs() <= TOLERANCE;
        if !holds {
            order = tree.order - 1;
        }
        psi.push(p);
    }
    order as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_trees_are_those_of_the_class() {
        // Of order 1: the two leaves; of order 2: white with a black or a white child, black
        // with a white child; of order 3 the white ones have children {b,b}, {b,w}, {w,w},
        // {[b]}, {[w]}, {black [w]} and one black with a white child of order 2 for each of
        // those 2 white trees.
        let count = |n: usize| trees().iter().filter(|t| t.order == n).count();
        assert_eq!((count(1), count(2)), (2, 3));
        assert_eq!(count(3), 6 + 2);
        assert!(trees().len() < 20_000, "{} trees", trees().len());
    }
}
