//! Symbolic differentiation on a [`Graph`]: `∂e/∂x` as new nodes of the same graph, by the
//! rules of calculus, each node differentiated once ([`Derivative`] remembers them), so the
//! derivative of a graph of n nodes has O(n) nodes.

use super::graph::{Func, Graph, Id, Node};
use std::collections::HashMap;

/// Derivatives with respect to one variable, remembered node by node.
#[derive(Debug)]
pub struct Derivative {
    var: u16,
    done: HashMap<Id, Id>,
}

impl Derivative {
    /// Derivatives with respect to variable `var`.
    pub fn new(var: u16) -> Self {
        Self { var, done: HashMap::new() }
    }

    /// `∂e/∂x`. Iterative (children before parents), so a deep expression cannot overflow
    /// the stack.
    pub fn of(&mut self, g: &mut Graph, e: Id) -> Id {
        let mut stack = vec![(e, false)];
        while let Some((n, children_done)) = stack.pop() {
            if self.done.contains_key(&n) {
                continue;
            }
            let children = g.node(n).children();
            if !children_done {
                stack.push((n, true));
                stack.extend(children.iter().flatten().map(|&c| (c, false)));
                continue;
            }
            let d = self.rule(g, n);
            self.done.insert(n, d);
        }
        self.done[&e]
    }

    fn d(&self, c: Id) -> Id {
        self.done[&c]
    }

    /// The derivative of `n`, its children's known.
    fn rule(&self, g: &mut Graph, n: Id) -> Id {
        match g.node(n) {
            Node::Const(_) => g.num(0.0),
            Node::Var(i) => g.num(if i == self.var { 1.0 } else { 0.0 }),
            Node::Add(a, b) => g.add(self.d(a), self.d(b)),
            Node::Sub(a, b) => g.sub(self.d(a), self.d(b)),
            Node::Mul(a, b) => {
                let (l, r) = (g.mul(self.d(a), b), g.mul(a, self.d(b)));
                g.add(l, r)
            }
            Node::Div(a, b) => {
                // (a/b)' = a'/b − (a/b)·b'/b
                let first = g.div(self.d(a), b);
                let q = g.mul(n, self.d(b));
                let second = g.div(q, b);
                g.sub(first, second)
            }
            Node::Neg(a) => g.neg(self.d(a)),
            Node::PowI(a, k) => {
                let k1 = g.powi(a, k - 1);
                let kk = g.num(k as f64);
                let m = g.mul(kk, k1);
                g.mul(m, self.d(a))
            }
            // (a^c)' = c a^(c−1) a' for a constant c: defined at a = 0 too, where the
            // general rule below would give 0·(…/0).
            Node::Pow(a, b) if g.constant(b).is_some() => {
                let c = g.constant(b).unwrap_or(0.0);
                let c1 = g.num(c - 1.0);
                let p = g.pow(a, c1);
                let cc = g.num(c);
                let m = g.mul(cc, p);
                g.mul(m, self.d(a))
            }
            Node::Pow(a, b) => {
                // (a^b)' = a^b (b' log a + b a'/a)
                let (da, db) = (self.d(a), self.d(b));
                let log_a = g.call(Func::Log, a);
                let t1 = g.mul(db, log_a);
                let ba = g.mul(b, da);
                let t2 = g.div(ba, a);
                let s = g.add(t1, t2);
                g.mul(n, s)
            }
            Node::Call(f, a) => {
                let outer = match f {
                    Func::Sin => g.call(Func::Cos, a),
                    Func::Cos => {
                        let s = g.call(Func::Sin, a);
                        g.neg(s)
                    }
                    Func::Tan => {
                        // 1 + tan²a
                        let t2 = g.powi(n, 2);
                        let one = g.num(1.0);
                        g.add(one, t2)
                    }
                    Func::Exp => n,
                    Func::Log => {
                        let one = g.num(1.0);
                        g.div(one, a)
                    }
                    Func::Sqrt => {
                        let half = g.num(0.5);
                        g.div(half, n)
                    }
                    Func::Sinh => g.call(Func::Cosh, a),
                    Func::Cosh => g.call(Func::Sinh, a),
                    Func::Tanh => {
                        let t2 = g.powi(n, 2);
                        let one = g.num(1.0);
                        g.sub(one, t2)
                    }
                    Func::Atan => {
                        let a2 = g.powi(a, 2);
                        let one = g.num(1.0);
                        let s = g.add(one, a2);
                        g.div(one, s)
                    }
                };
                g.mul(outer, self.d(a))
            }
        }
    }
}
