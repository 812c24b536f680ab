//! [`Graph`]: expressions as shared nodes. Every constructor folds constants, drops the
//! neutral elements (`x + 0`, `1·x`, `x^1`) and returns the existing node for an expression
//! already built, so equal subexpressions (as in a function and its derivatives) are
//! computed once. `0·x` is taken as 0 for any x: derivatives are full of such products, and
//! they are 0 wherever x is finite.

use std::collections::HashMap;

/// A node of a [`Graph`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Id(pub(crate) u32);

/// The functions a formula may call.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Func {
    /// Sine.
    Sin,
    /// Cosine.
    Cos,
    /// Tangent.
    Tan,
    /// Exponential.
    Exp,
    /// Natural logarithm.
    Log,
    /// Square root.
    Sqrt,
    /// Hyperbolic sine.
    Sinh,
    /// Hyperbolic cosine.
    Cosh,
    /// Hyperbolic tangent.
    Tanh,
    /// Arctangent.
    Atan,
}

impl Func {
    /// Every function, with its name in formulas.
    pub const ALL: [(&'static str, Func); 10] = [
        ("sin", Func::Sin),
        ("cos", Func::Cos),
        ("tan", Func::Tan),
        ("exp", Func::Exp),
        ("log", Func::Log),
        ("sqrt", Func::Sqrt),
        ("sinh", Func::Sinh),
        ("cosh", Func::Cosh),
        ("tanh", Func::Tanh),
        ("atan", Func::Atan),
    ];

    /// The function of this name.
    pub fn named(name: &str) -> Option<Func> {
        Self::ALL.iter().find(|(n, _)| *n == name).map(|(_, f)| *f)
    }

    /// Its value at x.
    #[inline]
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Exp => x.exp(),
            Func::Log => x.ln(),
            Func::Sqrt => x.sqrt(),
            Func::Sinh => x.sinh(),
            Func::Cosh => x.cosh(),
            Func::Tanh => x.tanh(),
            Func::Atan => x.atan(),
        }
    }
}

/// An expression node. Constants are kept as bits so that nodes can be hashed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Node {
    /// A number.
    Const(u64),
    /// The caller's variable of this index.
    Var(u16),
    /// `a + b`.
    Add(Id, Id),
    /// `a − b`.
    Sub(Id, Id),
    /// `a · b`.
    Mul(Id, Id),
    /// `a / b`.
    Div(Id, Id),
    /// `−a`.
    Neg(Id),
    /// `a^k` for an integer k.
    PowI(Id, i32),
    /// `a^b`.
    Pow(Id, Id),
    /// `f(a)`.
    Call(Func, Id),
}

impl Node {
    /// The nodes it is computed from.
    pub fn children(self) -> [Option<Id>; 2] {
        match self {
            Node::Const(_) | Node::Var(_) => [None, None],
            Node::Neg(a) | Node::PowI(a, _) | Node::Call(_, a) => [Some(a), None],
            Node::Add(a, b)
            | Node::Sub(a, b)
            | Node::Mul(a, b)
            | Node::Div(a, b)
            | Node::Pow(a, b) => [Some(a), Some(b)],
        }
    }
}

/// Largest integer exponent written as repeated products (`PowI`) rather than `powf`.
const MAX_POWI: f64 = 64.0;

/// Shared expression nodes; see the module's doc.
#[derive(Debug, Default, Clone)]
pub struct Graph {
    nodes: Vec<Node>,
    index: HashMap<Node, Id>,
}

impl Graph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether it has no node.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node of `id`.
    pub fn node(&self, id: Id) -> Node {
        self.nodes[id.0 as usize]
    }

    /// The value of `id` when it is a constant.
    pub fn constant(&self, id: Id) -> Option<f64> {
        match self.node(id) {
            Node::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.index.get(&node) {
            return id;
        }
        let id = Id(self.nodes.len() as u32);
        self.nodes.push(node);
        self.index.insert(node, id);
        id
    }

    /// The number `x` (`-0.0` is kept as `0`).
    pub fn num(&mut self, x: f64) -> Id {
        let x = if x == 0.0 { 0.0 } else { x };
        self.intern(Node::Const(x.to_bits()))
    }

    /// Variable `i`.
    pub fn var(&mut self, i: u16) -> Id {
        self.intern(Node::Var(i))
    }

    fn is(&self, id: Id, x: f64) -> bool {
        self.constant(id) == Some(x)
    }

    /// `a + b`.
    pub fn add(&mut self, a: Id, b: Id) -> Id {
        match (self.constant(a), self.constant(b)) {
            (Some(x), Some(y)) => self.num(x + y),
            (Some(0.0), _) => b,
            (_, Some(0.0)) => a,
            _ => match (self.node(a), self.node(b)) {
                (_, Node::Neg(c)) => self.sub(a, c),
                (Node::Neg(c), _) => self.sub(b, c),
                // Sorted, so that `x + y` and `y + x` are one node (addition commutes in
                // floating point too).
                _ => self.intern(Node::Add(a.min(b), a.max(b))),
            },
        }
    }

    /// `a − b`.
    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        match (self.constant(a), self.constant(b)) {
            (Some(x), Some(y)) => self.num(x - y),
            (Some(0.0), _) => self.neg(b),
            (_, Some(0.0)) => a,
            _ if a == b => self.num(0.0),
            _ => match self.node(b) {
                Node::Neg(c) => self.add(a, c),
                _ => self.intern(Node::Sub(a, b)),
            },
        }
    }

    /// `a · b`.
    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        match (self.constant(a), self.constant(b)) {
            (Some(x), Some(y)) => self.num(x * y),
            (Some(0.0), _) | (_, Some(0.0)) => self.num(0.0),
            (Some(1.0), _) => b,
            (_, Some(1.0)) => a,
            (Some(-1.0), _) => self.neg(b),
            (_, Some(-1.0)) => self.neg(a),
            _ if a == b => self.intern(Node::PowI(a, 2)),
            // A constant times a constant times x: one product (within one rounding, where
            // the constants' product is a normal number).
            (Some(x), _) | (_, Some(x))
                if self
                    .scaled(if self.is(a, x) { b } else { a })
                    .is_some_and(|(y, _)| (x * y).is_normal()) =>
            {
                let other = if self.is(a, x) { b } else { a };
                let (y, c) = self.scaled(other).unwrap_or((1.0, other));
                let k = self.num(x * y);
                self.mul(k, c)
            }
            _ => match (self.node(a), self.node(b)) {
                (Node::Neg(c), Node::Neg(d)) => self.mul(c, d),
                (Node::Neg(c), _) => {
                    let m = self.mul(c, b);
                    self.neg(m)
                }
                (_, Node::Neg(d)) => {
                    let m = self.mul(a, d);
                    self.neg(m)
                }
                _ => self.intern(Node::Mul(a.min(b), a.max(b))),
            },
        }
    }

    /// `(k, x)` where `id` is `k·x` with a constant k.
    fn scaled(&self, id: Id) -> Option<(f64, Id)> {
        match self.node(id) {
            Node::Mul(p, q) => match (self.constant(p), self.constant(q)) {
                (Some(k), None) => Some((k, q)),
                (None, Some(k)) => Some((k, p)),
                _ => None,
            },
            _ => None,
        }
    }

    /// `a / b`.
    pub fn div(&mut self, a: Id, b: Id) -> Id {
        match (self.constant(a), self.constant(b)) {
            (Some(x), Some(y)) => self.num(x / y),
            // k·x / c: one product.
            (None, Some(y)) if self.scaled(a).is_some_and(|(k, _)| (k / y).is_normal()) => {
                let (k, x) = self.scaled(a).unwrap_or((1.0, a));
                let k = self.num(k / y);
                self.mul(k, x)
            }
            (Some(0.0), _) => self.num(0.0),
            (_, Some(1.0)) => a,
            (_, Some(-1.0)) => self.neg(a),
            _ => self.intern(Node::Div(a, b)),
        }
    }

    /// `−a`.
    pub fn neg(&mut self, a: Id) -> Id {
        match self.node(a) {
            Node::Const(bits) => self.num(-f64::from_bits(bits)),
            Node::Neg(b) => b,
            Node::Sub(b, c) => self.sub(c, b),
            _ => self.intern(Node::Neg(a)),
        }
    }

    /// `a^k`.
    pub fn powi(&mut self, a: Id, k: i32) -> Id {
        match (self.constant(a), k) {
            (Some(x), _) => self.num(x.powi(k)),
            (_, 0) => self.num(1.0),
            (_, 1) => a,
            _ => match self.node(a) {
                Node::PowI(b, j) if (j as i64 * k as i64).abs() <= MAX_POWI as i64 => {
                    self.powi(b, j * k)
                }
                _ => self.intern(Node::PowI(a, k)),
            },
        }
    }

    /// `a^b`; an integer constant b of at most [`MAX_POWI`] in magnitude is a [`Node::PowI`].
    pub fn pow(&mut self, a: Id, b: Id) -> Id {
        match (self.constant(a), self.constant(b)) {
            (Some(x), Some(y)) => self.num(x.powf(y)),
            (_, Some(y)) if y.fract() == 0.0 && y.abs() <= MAX_POWI => self.powi(a, y as i32),
            (_, Some(0.5)) => self.call(Func::Sqrt, a),
            _ => self.intern(Node::Pow(a, b)),
        }
    }

    /// `f(a)`. The double angle is written through `sin a` and `cos a`
    /// (`sin 2a = 2 sin a cos a`, `cos 2a = cos²a − sin²a`), so that a formula with both
    /// needs one sine and cosine.
    pub fn call(&mut self, f: Func, a: Id) -> Id {
        if let Some(x) = self.constant(a) {
            return self.num(f.apply(x));
        }
        if let (Func::Sin | Func::Cos, Node::Mul(c, d)) = (f, self.node(a)) {
            let half = if self.is(c, 2.0) {
                Some(d)
            } else if self.is(d, 2.0) {
                Some(c)
            } else {
                None
            };
            if let Some(b) = half {
                let (s, co) = (self.call(Func::Sin, b), self.call(Func::Cos, b));
                return match f {
                    Func::Sin => {
                        let two = self.num(2.0);
                        let sc = self.mul(s, co);
                        self.mul(two, sc)
                    }
                    _ => {
                        let (c2, s2) = (self.powi(co, 2), self.powi(s, 2));
                        self.sub(c2, s2)
                    }
                };
            }
        }
        match (f, self.node(a)) {
            (Func::Cos | Func::Cosh, Node::Neg(b)) => self.call(f, b),
            (Func::Sin | Func::Tan | Func::Sinh | Func::Tanh | Func::Atan, Node::Neg(b)) => {
                let c = self.call(f, b);
                self.neg(c)
            }
            _ => self.intern(Node::Call(f, a)),
        }
    }

    /// `root` of `src` built again in this graph, each variable `i` of `src` replaced by the
    /// node `var(self, i)` of this one, through the constructors (so constants fold anew).
    /// `done` remembers the nodes already built, so that calls for several roots share them.
    /// Iterative (children first), so a deep expression cannot overflow the stack.
    pub fn import(
        &mut self,
        src: &Graph,
        root: Id,
        var: &mut dyn FnMut(&mut Graph, u16) -> Id,
        done: &mut HashMap<Id, Id>,
    ) -> Id {
        let mut stack = vec![(root, false)];
        while let Some((n, children_done)) = stack.pop() {
            if done.contains_key(&n) {
                continue;
            }
            let node = src.node(n);
            if !children_done {
                stack.push((n, true));
                stack.extend(node.children().iter().flatten().map(|&c| (c, false)));
                continue;
            }
            let at = |c: Id| done[&c];
            let built = match node {
                Node::Const(bits) => self.num(f64::from_bits(bits)),
                Node::Var(i) => var(self, i),
                Node::Add(a, b) => self.add(at(a), at(b)),
                Node::Sub(a, b) => self.sub(at(a), at(b)),
                Node::Mul(a, b) => self.mul(at(a), at(b)),
                Node::Div(a, b) => self.div(at(a), at(b)),
                Node::Neg(a) => self.neg(at(a)),
                Node::PowI(a, k) => self.powi(at(a), k),
                Node::Pow(a, b) => self.pow(at(a), at(b)),
                Node::Call(f, a) => self.call(f, at(a)),
            };
            done.insert(n, built);
        }
        done[&root]
    }

    /// The variables `id` depends on, as a sorted list.
    pub fn variables(&self, id: Id) -> Vec<u16> {
        let mut seen = vec![false; id.0 as usize + 1];
        let mut vars = Vec::new();
        let mut stack = vec![id];
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut seen[n.0 as usize], true) {
                continue;
            }
            let node = self.node(n);
            if let Node::Var(v) = node {
                vars.push(v);
            }
            stack.extend(node.children().into_iter().flatten());
        }
        vars.sort_unstable();
        vars
    }

    /// Whether `id` depends on variable `var`.
    pub fn depends_on(&self, id: Id, var: u16) -> bool {
        let mut seen = vec![false; id.0 as usize + 1];
        let mut stack = vec![id];
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut seen[n.0 as usize], true) {
                continue;
            }
            let node = self.node(n);
            if node == Node::Var(var) {
                return true;
            }
            stack.extend(node.children().into_iter().flatten());
        }
        false
    }

    /// The value of `id` with the variables at `vars`: the reference the tapes are tested
    /// against.
    pub fn eval(&self, id: Id, vars: &[f64]) -> f64 {
        let mut values = vec![f64::NAN; id.0 as usize + 1];
        for i in 0..=id.0 as usize {
            values[i] = match self.nodes[i] {
                Node::Const(bits) => f64::from_bits(bits),
                Node::Var(v) => vars[v as usize],
                Node::Add(a, b) => values[a.0 as usize] + values[b.0 as usize],
                Node::Sub(a, b) => values[a.0 as usize] - values[b.0 as usize],
                Node::Mul(a, b) => values[a.0 as usize] * values[b.0 as usize],
                Node::Div(a, b) => values[a.0 as usize] / values[b.0 as usize],
                Node::Neg(a) => -values[a.0 as usize],
                Node::PowI(a, k) => values[a.0 as usize].powi(k),
                Node::Pow(a, b) => values[a.0 as usize].powf(values[b.0 as usize]),
                Node::Call(f, a) => f.apply(values[a.0 as usize]),
            };
        }
        values[id.0 as usize]
    }
}
