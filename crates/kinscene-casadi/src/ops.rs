//! The elementary operations of an expression and the methods that apply them.

use crate::expr::Expr;

/// One-argument operations. The codes match `ks_casadi_op` in `cpp/shim.h`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Unary {
    Neg,
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sqrt,
    Exp,
    Ln,
    Abs,
    Tanh,
    Sq,
    Sinh,
    Cosh,
}

/// Two-argument operations. The codes match `ks_casadi_op` in `cpp/shim.h`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Binary {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    /// `atan2(y = first, x = second)`.
    Atan2,
    Min,
    Max,
}

impl Unary {
    pub(crate) fn code(self) -> i32 {
        10 + self as i32
    }

    pub(crate) fn apply(self, a: f64) -> f64 {
        match self {
            Unary::Neg => -a,
            Unary::Sin => a.sin(),
            Unary::Cos => a.cos(),
            Unary::Tan => a.tan(),
            Unary::Asin => a.asin(),
            Unary::Acos => a.acos(),
            Unary::Atan => a.atan(),
            Unary::Sqrt => a.sqrt(),
            Unary::Exp => a.exp(),
            Unary::Ln => a.ln(),
            Unary::Abs => a.abs(),
            Unary::Tanh => a.tanh(),
            Unary::Sq => a * a,
            Unary::Sinh => a.sinh(),
            Unary::Cosh => a.cosh(),
        }
    }

    pub(crate) fn name(self) -> &'static str {
        match self {
            Unary::Neg => "-",
            Unary::Sin => "sin",
            Unary::Cos => "cos",
            Unary::Tan => "tan",
            Unary::Asin => "asin",
            Unary::Acos => "acos",
            Unary::Atan => "atan",
            Unary::Sqrt => "sqrt",
            Unary::Exp => "exp",
            Unary::Ln => "ln",
            Unary::Abs => "abs",
            Unary::Tanh => "tanh",
            Unary::Sq => "sq",
            Unary::Sinh => "sinh",
            Unary::Cosh => "cosh",
        }
    }
}

impl Binary {
    pub(crate) fn code(self) -> i32 {
        40 + self as i32
    }

    pub(crate) fn apply(self, a: f64, b: f64) -> f64 {
        match self {
            Binary::Add => a + b,
            Binary::Sub => a - b,
            Binary::Mul => a * b,
            Binary::Div => a / b,
            Binary::Pow => a.powf(b),
            Binary::Atan2 => a.atan2(b),
            Binary::Min => a.min(b),
            Binary::Max => a.max(b),
        }
    }

    pub(crate) fn infix(self) -> Option<&'static str> {
        match self {
            Binary::Add => Some("+"),
            Binary::Sub => Some("-"),
            Binary::Mul => Some("*"),
            Binary::Div => Some("/"),
            _ => None,
        }
    }

    pub(crate) fn name(self) -> &'static str {
        match self {
            Binary::Pow => "pow",
            Binary::Atan2 => "atan2",
            Binary::Min => "min",
            Binary::Max => "max",
            _ => self.infix().unwrap_or("?"),
        }
    }
}

macro_rules! unary_methods {
    ($($(#[$doc:meta])* $name:ident => $op:ident;)*) => {
        impl Expr {
            $(
                $(#[$doc])*
                pub fn $name(&self) -> Expr {
                    Expr::unary(Unary::$op, self)
                }
            )*
        }
    };
}

unary_methods! {
    /// Sine (radians).
    sin => Sin;
    /// Cosine (radians).
    cos => Cos;
    /// Tangent (radians).
    tan => Tan;
    /// Arcsine, in radians in [-π/2, π/2].
    asin => Asin;
    /// Arccosine, in radians in [0, π].
    acos => Acos;
    /// Arctangent, in radians in (-π/2, π/2).
    atan => Atan;
    /// Square root (NaN below 0; its derivative is infinite at 0).
    sqrt => Sqrt;
    /// Exponential.
    exp => Exp;
    /// Natural logarithm.
    #[doc(alias = "log")]
    ln => Ln;
    /// Absolute value (not differentiable at 0).
    abs => Abs;
    /// Hyperbolic tangent.
    tanh => Tanh;
    /// Hyperbolic sine.
    sinh => Sinh;
    /// Hyperbolic cosine.
    cosh => Cosh;
    /// Square, `self * self` as one node.
    sq => Sq;
}

impl Expr {
    /// `self` raised to a real power, `exp(e * ln(self))` for derivatives: use
    /// [`powi`](Expr::powi) for integer exponents of possibly negative bases.
    pub fn pow(&self, e: impl Into<Expr>) -> Expr {
        Expr::binary(Binary::Pow, self, &e.into())
    }

    /// Four-quadrant arctangent of `self / x` (`self` is y, as in `f64::atan2`), in radians in
    /// (-π, π].
    pub fn atan2(&self, x: impl Into<Expr>) -> Expr {
        Expr::binary(Binary::Atan2, self, &x.into())
    }

    /// The smaller of `self` and `other` (not differentiable where they are equal).
    pub fn min(&self, other: impl Into<Expr>) -> Expr {
        Expr::binary(Binary::Min, self, &other.into())
    }

    /// The larger of `self` and `other` (not differentiable where they are equal).
    pub fn max(&self, other: impl Into<Expr>) -> Expr {
        Expr::binary(Binary::Max, self, &other.into())
    }
}
