//! Symbolic scalar expressions: an immutable DAG of reference-counted nodes.

use std::fmt;
use std::sync::Arc;

use crate::ops::{Binary, Unary};

/// Which [`Nlp`](crate::Nlp) the symbols of an expression belong to: 0 for none (constants),
/// [`MIXED`] when they come from two different instances.
pub(crate) type Owner = u64;
pub(crate) const NO_OWNER: Owner = 0;
pub(crate) const MIXED: Owner = u64::MAX;

/// A symbolic scalar: a cheap-to-clone handle to an immutable node of an expression DAG.
///
/// Leaves are constants, decision variables ([`Nlp::variable`](crate::Nlp::variable)) and
/// parameters ([`Nlp::parameter`](crate::Nlp::parameter)). Arithmetic (`+ - * /`, unary `-`,
/// with `Expr`, `&Expr` or `f64` on either side) and the methods below build new nodes that
/// share their arguments, so a subexpression used many times (e.g. the entries of a transform
/// product) is stored once and sent to CasADi once.
///
/// Trivial cases fold on construction: constant arguments are evaluated, `x + 0`, `x - 0`,
/// `x * 1`, `x / 1` return `x`, `x * 0` and `0 / x` return `0` (as CasADi does, even where IEEE
/// would give NaN for `x = inf` or `x = 0`), `--x` is `x`.
///
/// `Expr` implements what nalgebra needs for matrix algebra (`Scalar`, `Zero`, `One`, the
/// assigning operators), so `Matrix4<Expr>` products and `Vector3<Expr>` dot and cross products
/// work.
///
/// Equality (`==`) is *identity*: two handles to the same node, or two constants with the same
/// value. It is not mathematical equivalence.
#[derive(Clone)]
pub struct Expr(pub(crate) Arc<Node>);

pub(crate) struct Node {
    pub(crate) kind: Kind,
    pub(crate) owner: Owner,
}

pub(crate) enum Kind {
    Const(f64),
    Var(usize),
    Param(usize),
    Unary(Unary, Expr),
    Binary(Binary, Expr, Expr),
    Powi(Expr, i32),
}

impl Kind {
    /// Moves the children out (replacing the node by a constant) for iterative dropping.
    fn take_children(&mut self, out: &mut Vec<Expr>) {
        if matches!(self, Kind::Const(_) | Kind::Var(_) | Kind::Param(_)) {
            return;
        }
        match std::mem::replace(self, Kind::Const(0.0)) {
            Kind::Unary(_, a) | Kind::Powi(a, _) => out.push(a),
            Kind::Binary(_, a, b) => {
                out.push(a);
                out.push(b);
            }
            Kind::Const(_) | Kind::Var(_) | Kind::Param(_) => {}
        }
    }
}

impl Drop for Node {
    /// Drops long chains (a sum of thousands of terms) without recursion.
    fn drop(&mut self) {
        let mut stack = Vec::new();
        self.kind.take_children(&mut stack);
        while let Some(e) = stack.pop() {
            if let Ok(mut node) = Arc::try_unwrap(e.0) {
                node.kind.take_children(&mut stack);
            }
        }
    }
}

fn merge(a: Owner, b: Owner) -> Owner {
    if a == NO_OWNER || a == b {
        b
    } else if b == NO_OWNER {
        a
    } else {
        MIXED
    }
}

impl Expr {
    pub(crate) fn leaf(kind: Kind, owner: Owner) -> Expr {
        Expr(Arc::new(Node { kind, owner }))
    }

    /// A constant.
    pub fn constant(value: f64) -> Expr {
        Expr::leaf(Kind::Const(value), NO_OWNER)
    }

    /// The value if this is a constant node.
    pub fn as_constant(&self) -> Option<f64> {
        match self.0.kind {
            Kind::Const(v) => Some(v),
            _ => None,
        }
    }

    /// The index of the decision variable if this is a variable leaf (variables are numbered in
    /// creation order; the index addresses `x`, `lam_x` and `x0`).
    pub fn variable_index(&self) -> Option<usize> {
        match self.0.kind {
            Kind::Var(i) => Some(i),
            _ => None,
        }
    }

    /// The index of the parameter if this is a parameter leaf (numbered in creation order).
    pub fn parameter_index(&self) -> Option<usize> {
        match self.0.kind {
            Kind::Param(i) => Some(i),
            _ => None,
        }
    }

    pub(crate) fn owner(&self) -> Owner {
        self.0.owner
    }

    pub(crate) fn ptr(&self) -> *const Node {
        Arc::as_ptr(&self.0)
    }

    fn is_const(&self, v: f64) -> bool {
        self.as_constant() == Some(v)
    }

    pub(crate) fn unary(op: Unary, a: &Expr) -> Expr {
        match (&a.0.kind, op) {
            (Kind::Const(v), _) => Expr::constant(op.apply(*v)),
            (Kind::Unary(Unary::Neg, inner), Unary::Neg) => inner.clone(),
            _ => Expr::leaf(Kind::Unary(op, a.clone()), a.owner()),
        }
    }

    pub(crate) fn binary(op: Binary, a: &Expr, b: &Expr) -> Expr {
        if let (Some(x), Some(y)) = (a.as_constant(), b.as_constant()) {
            return Expr::constant(op.apply(x, y));
        }
        let folded = match op {
            Binary::Add if a.is_const(0.0) => Some(b.clone()),
            Binary::Add | Binary::Sub if b.is_const(0.0) => Some(a.clone()),
            Binary::Sub if a.is_const(0.0) => Some(-b),
            Binary::Mul if a.is_const(0.0) || b.is_const(0.0) => Some(Expr::constant(0.0)),
            Binary::Mul if a.is_const(1.0) => Some(b.clone()),
            Binary::Mul | Binary::Div if b.is_const(1.0) => Some(a.clone()),
            Binary::Mul if a.is_const(-1.0) => Some(-b),
            Binary::Mul if b.is_const(-1.0) => Some(-a),
            Binary::Div if a.is_const(0.0) => Some(Expr::constant(0.0)),
            _ => None,
        };
        folded.unwrap_or_else(|| {
            Expr::leaf(
                Kind::Binary(op, a.clone(), b.clone()),
                merge(a.owner(), b.owner()),
            )
        })
    }

    /// `self` raised to the integer power `n` (CasADi's constant power: differentiable for
    /// negative bases, unlike [`pow`](Expr::pow)).
    pub fn powi(&self, n: i32) -> Expr {
        match (n, self.as_constant()) {
            (_, Some(v)) => Expr::constant(v.powi(n)),
            (0, None) => Expr::constant(1.0),
            (1, None) => self.clone(),
            (2, None) => self.sq(),
            _ => Expr::leaf(Kind::Powi(self.clone(), n), self.owner()),
        }
    }
}

impl From<f64> for Expr {
    fn from(value: f64) -> Expr {
        Expr::constant(value)
    }
}

impl From<&Expr> for Expr {
    fn from(e: &Expr) -> Expr {
        e.clone()
    }
}

impl PartialEq for Expr {
    /// Identity: the same node, or constants of equal value.
    fn eq(&self, other: &Expr) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
            || matches!((self.as_constant(), other.as_constant()), (Some(a), Some(b)) if a == b)
    }
}

impl fmt::Debug for Expr {
    /// Infix form, abbreviated below a depth of 4 (a shared DAG can be exponentially large
    /// as a tree).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_infix(self, f, 4)
    }
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_infix(self, f, 4)
    }
}

fn write_infix(e: &Expr, f: &mut fmt::Formatter<'_>, depth: usize) -> fmt::Result {
    match &e.0.kind {
        Kind::Const(v) => write!(f, "{v:?}"),
        Kind::Var(i) => write!(f, "x[{i}]"),
        Kind::Param(i) => write!(f, "p[{i}]"),
        _ if depth == 0 => write!(f, "…"),
        Kind::Unary(op, a) => {
            write!(f, "{}(", op.name())?;
            write_infix(a, f, depth - 1)?;
            write!(f, ")")
        }
        Kind::Powi(a, n) => {
            write!(f, "powi(")?;
            write_infix(a, f, depth - 1)?;
            write!(f, ", {n})")
        }
        Kind::Binary(op, a, b) => match op.infix() {
            Some(sym) => {
                write!(f, "(")?;
                write_infix(a, f, depth - 1)?;
                write!(f, " {sym} ")?;
                write_infix(b, f, depth - 1)?;
                write!(f, ")")
            }
            None => {
                write!(f, "{}(", op.name())?;
                write_infix(a, f, depth - 1)?;
                write!(f, ", ")?;
                write_infix(b, f, depth - 1)?;
                write!(f, ")")
            }
        },
    }
}
