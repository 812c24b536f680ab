//! [`Tape`]: the nodes some outputs need, compiled into a straight-line list of
//! instructions over numbered slots. Evaluating runs each instruction once, in order: no
//! parsing, no recursion, no loop but the one over the list, and no allocation (the slots
//! live in a per-thread buffer that grows once to the largest tape). A sine and a cosine of
//! the same argument are one `sin_cos`.

use super::graph::{Func, Graph, Id, Node};
use std::cell::RefCell;
use std::collections::HashMap;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Op {
    Const(f64),
    Var(u16),
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    Div(u32, u32),
    /// `a + k`, `a − k`, `k − a`, `a·k`, `a / k`, `k / a` with a constant k: a constant
    /// operand costs no instruction of its own.
    AddK(u32, f64),
    SubK(u32, f64),
    KSub(f64, u32),
    MulK(u32, f64),
    DivK(u32, f64),
    KDiv(f64, u32),
    Neg(u32),
    Square(u32),
    PowI(u32, i32),
    Pow(u32, u32),
    Call(Func, u32),
    /// `sin` into `dst`, `cos` into the second slot.
    SinCos(u32, u32),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Instr {
    pub(crate) op: Op,
    pub(crate) dst: u32,
}

/// Where an output is read: a slot, or a constant known at compilation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Out {
    Slot(u32),
    Const(f64),
}

/// Compiled outputs of a graph; see the module's doc.
#[derive(Debug, Clone, PartialEq)]
pub struct Tape {
    code: Vec<Instr>,
    outputs: Vec<Out>,
    slots: usize,
    vars: usize,
}

thread_local! {
    static SLOTS: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
}

impl Tape {
    /// Compiles `outputs` of `g`, which reads variables `0..vars`.
    pub fn compile(g: &Graph, outputs: &[Id], vars: usize) -> Self {
        Self::compile_reading(g, outputs, vars, &[])
    }

    /// [`compile`](Self::compile), each node of `inputs` read from its variable rather than
    /// computed (`sin ζ` and `cos ζ` given by the caller, say).
    /// The tape reads at least as many variables as its nodes and `inputs` name, whatever
    /// `vars` says, so that evaluation checks its inputs' length against all of them.
    pub fn compile_reading(g: &Graph, outputs: &[Id], vars: usize, inputs: &[(Id, u16)]) -> Self {
        let input = |n: Id| inputs.iter().find(|(i, _)| *i == n).map(|p| p.1);
        // The nodes the outputs need, in the graph's order (children first).
        let mut needed = vec![false; g.len()];
        let mut stack: Vec<Id> = outputs.to_vec();
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut needed[n.0 as usize], true) || input(n).is_some() {
                continue;
            }
            stack.extend(g.node(n).children().into_iter().flatten());
        }
        let mut slot = HashMap::new();
        let mut order = Vec::new();
        for (i, _) in needed.iter().enumerate().filter(|(_, n)| **n) {
            slot.insert(Id(i as u32), order.len() as u32);
            order.push(Id(i as u32));
        }
        // The sine and cosine of each argument, where both are needed.
        let mut trig: HashMap<Id, [Option<Id>; 2]> = HashMap::new();
        for &n in order.iter().filter(|&&n| input(n).is_none()) {
            match g.node(n) {
                Node::Call(Func::Sin, a) => trig.entry(a).or_default()[0] = Some(n),
                Node::Call(Func::Cos, a) => trig.entry(a).or_default()[1] = Some(n),
                _ => {}
            }
        }
        let s = |id: Id| slot[&id];
        let k = |id: Id| g.constant(id);
        let mut code = Vec::with_capacity(order.len());
        for &n in &order {
            if let Some(var) = input(n) {
                code.push(Instr { op: Op::Var(var), dst: s(n) });
                continue;
            }
            let op = match g.node(n) {
                Node::Const(bits) => Op::Const(f64::from_bits(bits)),
                Node::Var(i) => Op::Var(i),
                Node::Add(a, b) => match (k(a), k(b)) {
                    (Some(x), _) => Op::AddK(s(b), x),
                    (_, Some(y)) => Op::AddK(s(a), y),
                    _ => Op::Add(s(a), s(b)),
                },
                Node::Sub(a, b) => match (k(a), k(b)) {
                    (Some(x), _) => Op::KSub(x, s(b)),
                    (_, Some(y)) => Op::SubK(s(a), y),
                    _ => Op::Sub(s(a), s(b)),
                },
                Node::Mul(a, b) => match (k(a), k(b)) {
                    (Some(x), _) => Op::MulK(s(b), x),
                    (_, Some(y)) => Op::MulK(s(a), y),
                    _ => Op::Mul(s(a), s(b)),
                },
                Node::Div(a, b) => match (k(a), k(b)) {
                    (Some(x), _) => Op::KDiv(x, s(b)),
                    (_, Some(y)) => Op::DivK(s(a), y),
                    _ => Op::Div(s(a), s(b)),
                },
                Node::Neg(a) => Op::Neg(s(a)),
                Node::PowI(a, 2) => Op::Square(s(a)),
                Node::PowI(a, k) => Op::PowI(s(a), k),
                Node::Pow(a, b) => Op::Pow(s(a), s(b)),
                // Where both are needed, one SinCos at the first of the two computes both
                // (each needs only `a`, computed before either).
                Node::Call(f @ (Func::Sin | Func::Cos), a) => match trig[&a] {
                    [Some(sin), Some(cos)] if n == sin.min(cos) => {
                        code.push(Instr { op: Op::SinCos(s(a), s(cos)), dst: s(sin) });
                        continue;
                    }
                    [Some(_), Some(_)] => continue,
                    _ => Op::Call(f, s(a)),
                },
                Node::Call(f, a) => Op::Call(f, s(a)),
            };
            code.push(Instr { op, dst: s(n) });
        }
        // Constants read by no instruction (taken as operands above, or outputs) need none.
        let mut read = vec![false; order.len()];
        for ins in &code {
            for k in operands(ins.op).into_iter().flatten() {
                read[k as usize] = true;
            }
        }
        let fixed: Vec<Instr> = code
            .into_iter()
            .filter(|i| read[i.dst as usize] || !matches!(i.op, Op::Const(_)))
            .collect();
        let outputs = outputs
            .iter()
            .map(|&o| match k(o) {
                Some(c) => Out::Const(c),
                None => Out::Slot(s(o)),
            })
            .collect();
        let read = fixed.iter().filter_map(|i| match i.op {
            Op::Var(v) => Some(v as usize + 1),
            _ => None,
        });
        let vars = read.fold(vars, usize::max);
        Self { code: schedule(fixed), outputs, slots: order.len(), vars }
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

    /// The instructions, in order: what the JIT (`jit.rs`) translates and the cost model
    /// (`catalogue::cost`) counts.
    pub(crate) fn instructions(&self) -> &[Instr] {
        &self.code
    }

    /// Where each output is read, for the JIT.
    #[cfg(feature = "jit")]
    pub(crate) fn output_sources(&self) -> &[Out] {
        &self.outputs
    }

    /// Number of slots, for the JIT.
    #[cfg(feature = "jit")]
    pub(crate) fn slots(&self) -> usize {
        self.slots
    }

    /// Number of variables read, for the JIT.
    #[cfg(feature = "jit")]
    pub(crate) fn vars(&self) -> usize {
        self.vars
    }

    /// Number of outputs.
    pub fn outputs(&self) -> usize {
        self.outputs.len()
    }

    /// Evaluates the outputs at `vars` (at least the tape's number of variables) into `out`
    /// (one per output), with this thread's slots. Out of line: inlined, the interpreter's loop
    /// made the callers of [`Function`](super::function::Function) too large to be inlined in
    /// turn, and with them the call to the machine code beside it.
    #[inline(never)]
    pub fn eval(&self, vars: &[f64], out: &mut [f64]) {
        SLOTS.with_borrow_mut(|slots| self.eval_with(vars, slots, out));
    }

    /// [`eval`](Self::eval) with the caller's slots (grown to fit if needed).
    #[inline]
    pub fn eval_with(&self, vars: &[f64], slots: &mut Vec<f64>, out: &mut [f64]) {
        if slots.len() < self.slots {
            slots.resize(self.slots, 0.0);
        }
        self.run(vars, slots);
        for (o, k) in out.iter_mut().zip(&self.outputs) {
            *o = match *k {
                Out::Slot(k) => slots[k as usize],
                Out::Const(c) => c,
            };
        }
    }

    #[inline]
    fn run(&self, vars: &[f64], x: &mut [f64]) {
        assert!(vars.len() >= self.vars && x.len() >= self.slots, "a tape's inputs and slots");
        macro_rules! at {
            ($k:expr) => {
                // SAFETY: `compile` numbers every operand and destination below `self.slots`
                // (they are positions in `order`), and `x` has at least that many (asserted
                // above); likewise every variable index is below `self.vars`.
                unsafe { *x.get_unchecked($k as usize) }
            };
        }
        for ins in &self.code {
            let v = match ins.op {
                Op::Const(c) => c,
                // SAFETY: as for `at!`.
                Op::Var(i) => unsafe { *vars.get_unchecked(i as usize) },
                Op::Add(a, b) => at!(a) + at!(b),
                Op::Sub(a, b) => at!(a) - at!(b),
                Op::Mul(a, b) => at!(a) * at!(b),
                Op::Div(a, b) => at!(a) / at!(b),
                Op::AddK(a, k) => at!(a) + k,
                Op::SubK(a, k) => at!(a) - k,
                Op::KSub(k, a) => k - at!(a),
                Op::MulK(a, k) => at!(a) * k,
                Op::DivK(a, k) => at!(a) / k,
                Op::KDiv(k, a) => k / at!(a),
                Op::Neg(a) => -at!(a),
                Op::Square(a) => at!(a) * at!(a),
                Op::PowI(a, k) => at!(a).powi(k),
                Op::Pow(a, b) => at!(a).powf(at!(b)),
                Op::Call(f, a) => f.apply(at!(a)),
                Op::SinCos(a, cos) => {
                    let (s, c) = at!(a).sin_cos();
                    // SAFETY: as for `at!`.
                    unsafe { *x.get_unchecked_mut(cos as usize) = c };
                    s
                }
            };
            // SAFETY: as for `at!`.
            unsafe { *x.get_unchecked_mut(ins.dst as usize) = v };
        }
    }
}

/// The instructions reordered, dependencies kept, so that instructions of one kind follow
/// each other where they can: evaluation dispatches on each instruction's kind, and a
/// dispatch to the same place as the last one is one the processor predicts. Among the ready
/// instructions: the first of the last one's kind, else the first of any kind.
fn schedule(code: Vec<Instr>) -> Vec<Instr> {
    use std::collections::BTreeSet;
    let n = code.len();
    let mut writer: HashMap<u32, usize> = HashMap::with_capacity(n);
    for (i, ins) in code.iter().enumerate() {
        writer.insert(ins.dst, i);
        if let Op::SinCos(_, cos) = ins.op {
            writer.insert(cos, i);
        }
    }
    let mut waiting = vec![0usize; n];
    let mut dependents: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, ins) in code.iter().enumerate() {
        let mut deps: Vec<usize> = operands(ins.op)
            .into_iter()
            .flatten()
            .filter_map(|k| writer.get(&k).copied())
            .collect();
        deps.dedup();
        waiting[i] = deps.len();
        for d in deps {
            dependents[d].push(i);
        }
    }
    let kind = |i: usize| kind(code[i].op);
    let mut ready: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); KINDS];
    for i in (0..n).filter(|&i| waiting[i] == 0) {
        ready[kind(i)].insert(i);
    }
    let mut out = Vec::with_capacity(n);
    let mut last = None;
    while out.len() < n {
        let same = last.and_then(|k: usize| ready[k].first().copied());
        let Some(next) = same.or_else(|| ready.iter().filter_map(|r| r.first().copied()).min())
        else {
            break; // unreachable for straight-line code: every instruction's writers precede it
        };
        ready[kind(next)].remove(&next);
        out.push(code[next]);
        last = Some(kind(next));
        for &d in &dependents[next] {
            waiting[d] -= 1;
            if waiting[d] == 0 {
                ready[kind(d)].insert(d);
            }
        }
    }
    out
}

/// Number of instruction kinds.
const KINDS: usize = 18;

/// An instruction's kind, `0..KINDS`.
fn kind(op: Op) -> usize {
    match op {
        Op::Const(_) => 0,
        Op::Var(_) => 1,
        Op::Add(..) => 2,
        Op::Sub(..) => 3,
        Op::Mul(..) => 4,
        Op::Div(..) => 5,
        Op::AddK(..) => 6,
        Op::SubK(..) => 7,
        Op::KSub(..) => 8,
        Op::MulK(..) => 9,
        Op::DivK(..) => 10,
        Op::KDiv(..) => 11,
        Op::Neg(_) => 12,
        Op::Square(_) => 13,
        Op::PowI(..) => 14,
        Op::Pow(..) => 15,
        Op::Call(..) => 16,
        Op::SinCos(..) => 17,
    }
}

/// The slots `op` reads.
fn operands(op: Op) -> [Option<u32>; 2] {
    match op {
        Op::Const(_) | Op::Var(_) => [None, None],
        Op::Neg(a)
        | Op::Square(a)
        | Op::PowI(a, _)
        | Op::Call(_, a)
        | Op::SinCos(a, _)
        | Op::AddK(a, _)
        | Op::SubK(a, _)
        | Op::KSub(_, a)
        | Op::MulK(a, _)
        | Op::DivK(a, _)
        | Op::KDiv(_, a) => [Some(a), None],
        Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) | Op::Pow(a, b) => {
            [Some(a), Some(b)]
        }
    }
}
