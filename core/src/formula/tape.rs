//! [`Tape`]: the nodes some outputs need, compiled into a straight-line list of
//! instructions over numbered slots. Evaluating runs each instruction once, in order: no
//! parsing, no recursion, no loop but the one over the list, and no allocation (the slots
//! live in a per-thread buffer that grows once to the largest tape). A sine and a cosine of
//! the same argument are one `sin_cos`.

use super::graph::{Func, Graph, Id, Node};
use std::cell::RefCell;
use std::collections::HashMap;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Op {
    Const(f64),
    Var(u16),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    Neg(u32),
    Square(u32),
    PowI(u32, i32),
    Pow(u32, u32),
    Call(Func, u32),
    /// `sin` into `dst`, `cos` into the second slot.
    SinCos(u32, u32),
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Instr {
    op: Op,
    dst: u32,
}

/// Compiled outputs of a graph; see the module's doc.
#[derive(Debug, Clone, PartialEq)]
pub struct Tape {
    code: Vec<Instr>,
    outputs: Vec<u32>,
    slots: usize,
    vars: usize,
}

thread_local! {
    static SLOTS: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

impl Tape {
    /// Compiles `outputs` of `g`, which reads variables `0..vars`.
    pub fn compile(g: &Graph, outputs: &[Id], vars: usize) -> Self {
        // The nodes the outputs need, in the graph's order (children first).
        let mut needed = vec![false; g.len()];
        let mut stack: Vec<Id> = outputs.to_vec();
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut needed[n.0 as usize], true) {
                continue;
            }
            match g.node(n) {
                Node::Const(_) | Node::Var(_) => {}
                Node::Neg(a) | Node::PowI(a, _) | Node::Call(_, a) => stack.push(a),
                Node::Add(a, b)
                | Node::Sub(a, b)
                | Node::Mul(a, b)
                | Node::Div(a, b)
                | Node::Pow(a, b) => stack.extend([a, b]),
            }
        }
        let mut slot = HashMap::new();
        let mut order = Vec::new();
        for (i, _) in needed.iter().enumerate().filter(|(_, n)| **n) {
            slot.insert(Id(i as u32), order.len() as u32);
            order.push(Id(i as u32));
        }
        // The sine and cosine of each argument, where both are needed.
        let mut trig: HashMap<Id, [Option<Id>; 2]> = HashMap::new();
        for &n in &order {
            match g.node(n) {
                Node::Call(Func::Sin, a) => trig.entry(a).or_default()[0] = Some(n),
                Node::Call(Func::Cos, a) => trig.entry(a).or_default()[1] = Some(n),
                _ => {}
            }
        }
        let s = |id: Id| slot[&id];
        let mut code = Vec::with_capacity(order.len());
        for &n in &order {
            let op = match g.node(n) {
                Node::Const(bits) => Op::Const(f64::from_bits(bits)),
                Node::Var(i) => Op::Var(i),
                Node::Add(a, b) => Op::Add(s(a), s(b)),
                Node::Sub(a, b) => Op::Sub(s(a), s(b)),
                Node::Mul(a, b) => Op::Mul(s(a), s(b)),
                Node::Div(a, b) => Op::Div(s(a), s(b)),
                Node::Neg(a) => Op::Neg(s(a)),
                Node::PowI(a, 2) => Op::Square(s(a)),
                Node::PowI(a, k) => Op::PowI(s(a), k),
                Node::Pow(a, b) => Op::Pow(s(a), s(b)),
                Node::Call(f @ (Func::Sin | Func::Cos), a) => match trig[&a] {
                    [Some(_), Some(cos)] if f == Func::Sin => Op::SinCos(s(a), s(cos)),
                    [Some(_), Some(_)] => continue, // written by the sine's SinCos
                    _ => Op::Call(f, s(a)),
                },
                Node::Call(f, a) => Op::Call(f, s(a)),
            };
            code.push(Instr { op, dst: s(n) });
        }
        // A cosine written by a later sine's SinCos must not be read before it: move each
        // SinCos to the first of its pair.
        let mut fixed: Vec<Instr> = Vec::with_capacity(code.len());
        for ins in code {
            if let Op::SinCos(arg, cos) = ins.op {
                let at = fixed.iter().position(|i| reads(i.op, cos)).unwrap_or(fixed.len());
                fixed.insert(at, Instr { op: Op::SinCos(arg, cos), dst: ins.dst });
            } else {
                fixed.push(ins);
            }
        }
        Self {
            code: fixed,
            outputs: outputs.iter().map(|&o| s(o)).collect(),
            slots: order.len(),
            vars,
        }
    }

    /// Number of instructions.
    pub fn len(&self) -> usize {
        self.code.len()
    }

    /// Whether it has no instruction.
    pub fn is_empty(&self) -> bool {
        self.code.is_empty()
    }

    /// Number of calls of elementary functions per evaluation (a `sin_cos` counts once):
    /// what costs most in a tape.
    pub fn calls(&self) -> usize {
        self.code
            .iter()
            .filter(|i| matches!(i.op, Op::Call(..) | Op::SinCos(..) | Op::Pow(..)))
            .count()
    }

    /// Number of outputs.
    pub fn outputs(&self) -> usize {
        self.outputs.len()
    }

    /// Evaluates the outputs at `vars` (at least the tape's number of variables) into `out`
    /// (one per output).
    #[inline]
    pub fn eval(&self, vars: &[f64], out: &mut [f64]) {
        debug_assert!(vars.len() >= self.vars && out.len() == self.outputs.len());
        SLOTS.with_borrow_mut(|slots| {
            if slots.len() < self.slots {
                slots.resize(self.slots, 0.0);
            }
            self.run(vars, slots);
            for (o, &k) in out.iter_mut().zip(&self.outputs) {
                *o = slots[k as usize];
            }
        });
    }

    #[inline]
    fn run(&self, vars: &[f64], x: &mut [f64]) {
        for ins in &self.code {
            let v = match ins.op {
                Op::Const(c) => c,
                Op::Var(i) => vars[i as usize],
                Op::Add(a, b) => x[a as usize] + x[b as usize],
                Op::Sub(a, b) => x[a as usize] - x[b as usize],
                Op::Mul(a, b) => x[a as usize] * x[b as usize],
                Op::Div(a, b) => x[a as usize] / x[b as usize],
                Op::Neg(a) => -x[a as usize],
                Op::Square(a) => x[a as usize] * x[a as usize],
                Op::PowI(a, k) => x[a as usize].powi(k),
                Op::Pow(a, b) => x[a as usize].powf(x[b as usize]),
                Op::Call(f, a) => f.apply(x[a as usize]),
                Op::SinCos(a, cos) => {
                    let (s, c) = x[a as usize].sin_cos();
                    x[cos as usize] = c;
                    s
                }
            };
            x[ins.dst as usize] = v;
        }
    }
}

/// Whether `op` reads slot `k`.
fn reads(op: Op, k: u32) -> bool {
    match op {
        Op::Const(_) | Op::Var(_) => false,
        Op::Neg(a) | Op::Square(a) | Op::PowI(a, _) | Op::Call(_, a) | Op::SinCos(a, _) => a == k,
        Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) | Op::Pow(a, b) => {
            a == k || b == k
        }
    }
}
