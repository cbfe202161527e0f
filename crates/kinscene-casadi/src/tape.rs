//! Linearising an expression DAG into a topologically ordered tape, and evaluating the tape.
//!
//! The same tape is evaluated in Rust ([`Tape::eval`]) and sent to the shim, which rebuilds it
//! node by node as CasADi SX; each shared node appears once.

use std::collections::HashMap;

use crate::Error;
use crate::expr::{Expr, Kind, Node};
use crate::ops::{Binary, Unary};

/// One tape entry; arguments are indices of earlier entries.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Step {
    Const(f64),
    Var(usize),
    Param(usize),
    Unary(Unary, usize),
    Binary(Binary, usize, usize),
    Powi(usize, i32),
}

/// The tape of a set of output expressions.
#[derive(Debug, Clone)]
pub(crate) struct Tape {
    pub(crate) steps: Vec<Step>,
    /// The entry computing each output, in the order given to [`Tape::new`].
    pub(crate) outputs: Vec<usize>,
}

/// The tape as the parallel arrays of the C ABI (`ks_casadi_nlp_new`).
pub(crate) struct CTape {
    pub(crate) op: Vec<i32>,
    pub(crate) arg0: Vec<i32>,
    pub(crate) arg1: Vec<i32>,
    pub(crate) value: Vec<f64>,
}

fn children(e: &Expr) -> [Option<&Expr>; 2] {
    match &e.0.kind {
        Kind::Unary(_, a) | Kind::Powi(a, _) => [Some(a), None],
        Kind::Binary(_, a, b) => [Some(a), Some(b)],
        Kind::Const(_) | Kind::Var(_) | Kind::Param(_) => [None, None],
    }
}

impl Tape {
    /// Post-order traversal without recursion (expression chains can be thousands deep).
    pub(crate) fn new<'a>(roots: impl IntoIterator<Item = &'a Expr>) -> Tape {
        let mut index: HashMap<*const Node, usize> = HashMap::new();
        let mut steps = Vec::new();
        let mut outputs = Vec::new();
        let mut stack: Vec<(&Expr, bool)> = Vec::new();
        for root in roots {
            stack.push((root, false));
            while let Some((e, expanded)) = stack.pop() {
                if index.contains_key(&e.ptr()) {
                    continue;
                }
                if !expanded {
                    stack.push((e, true));
                    for c in children(e).into_iter().flatten() {
                        if !index.contains_key(&c.ptr()) {
                            stack.push((c, false));
                        }
                    }
                    continue;
                }
                let at = |c: &Expr| index[&c.ptr()];
                let step = match &e.0.kind {
                    Kind::Const(v) => Step::Const(*v),
                    Kind::Var(i) => Step::Var(*i),
                    Kind::Param(i) => Step::Param(*i),
                    Kind::Unary(op, a) => Step::Unary(*op, at(a)),
                    Kind::Binary(op, a, b) => Step::Binary(*op, at(a), at(b)),
                    Kind::Powi(a, n) => Step::Powi(at(a), *n),
                };
                index.insert(e.ptr(), steps.len());
                steps.push(step);
            }
            outputs.push(index[&root.ptr()]);
        }
        Tape { steps, outputs }
    }

    /// Evaluates every output at variables `x` and parameters `p`.
    ///
    /// The caller guarantees that every variable and parameter index is in range.
    pub(crate) fn eval(&self, x: &[f64], p: &[f64]) -> Vec<f64> {
        let mut v = Vec::with_capacity(self.steps.len());
        for step in &self.steps {
            let value = match *step {
                Step::Const(c) => c,
                Step::Var(i) => x[i],
                Step::Param(i) => p[i],
                Step::Unary(op, a) => op.apply(v[a]),
                Step::Binary(op, a, b) => op.apply(v[a], v[b]),
                Step::Powi(a, n) => v[a].powi(n),
            };
            v.push(value);
        }
        self.outputs.iter().map(|&i| v[i]).collect()
    }

    /// Fails on a NaN or infinite constant: CasADi would propagate it into every derivative.
    pub(crate) fn check_constants(&self) -> Result<(), Error> {
        match self.steps.iter().find_map(|s| match *s {
            Step::Const(c) if !c.is_finite() => Some(c),
            _ => None,
        }) {
            Some(c) => Err(Error::NonFinite {
                what: format!("a constant ({c}) in an expression"),
            }),
            None => Ok(()),
        }
    }

    pub(crate) fn to_c(&self) -> Result<CTape, Error> {
        let too_large = |what| Error::TooLarge {
            what,
            len: self.steps.len(),
        };
        i32::try_from(self.steps.len()).map_err(|_| too_large("tape"))?;
        let idx = |i: usize| i32::try_from(i).map_err(|_| too_large("leaf index"));
        let n = self.steps.len();
        let mut t = CTape {
            op: Vec::with_capacity(n),
            arg0: Vec::with_capacity(n),
            arg1: Vec::with_capacity(n),
            value: Vec::with_capacity(n),
        };
        for step in &self.steps {
            let (op, a0, a1, value) = match *step {
                Step::Const(c) => (0, -1, -1, c),
                Step::Var(i) => (1, idx(i)?, -1, 0.0),
                Step::Param(i) => (2, idx(i)?, -1, 0.0),
                Step::Unary(op, a) => (op.code(), idx(a)?, -1, 0.0),
                Step::Binary(op, a, b) => (op.code(), idx(a)?, idx(b)?, 0.0),
                Step::Powi(a, n) => (60, idx(a)?, -1, f64::from(n)),
            };
            t.op.push(op);
            t.arg0.push(a0);
            t.arg1.push(a1);
            t.value.push(value);
        }
        Ok(t)
    }
}
