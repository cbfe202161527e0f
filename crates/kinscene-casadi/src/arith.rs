//! Arithmetic operators and the numeric traits nalgebra needs.

use std::iter::{Product, Sum};
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::expr::Expr;
use crate::ops::{Binary, Unary};

macro_rules! binary_op {
    ($trait:ident, $method:ident, $assign_trait:ident, $assign:ident, $op:ident) => {
        impl $trait<&Expr> for &Expr {
            type Output = Expr;
            fn $method(self, rhs: &Expr) -> Expr {
                Expr::binary(Binary::$op, self, rhs)
            }
        }
        impl $trait<Expr> for &Expr {
            type Output = Expr;
            fn $method(self, rhs: Expr) -> Expr {
                Expr::binary(Binary::$op, self, &rhs)
            }
        }
        impl $trait<&Expr> for Expr {
            type Output = Expr;
            fn $method(self, rhs: &Expr) -> Expr {
                Expr::binary(Binary::$op, &self, rhs)
            }
        }
        impl $trait<Expr> for Expr {
            type Output = Expr;
            fn $method(self, rhs: Expr) -> Expr {
                Expr::binary(Binary::$op, &self, &rhs)
            }
        }
        impl $trait<f64> for &Expr {
            type Output = Expr;
            fn $method(self, rhs: f64) -> Expr {
                Expr::binary(Binary::$op, self, &Expr::constant(rhs))
            }
        }
        impl $trait<f64> for Expr {
            type Output = Expr;
            fn $method(self, rhs: f64) -> Expr {
                Expr::binary(Binary::$op, &self, &Expr::constant(rhs))
            }
        }
        impl $trait<&Expr> for f64 {
            type Output = Expr;
            fn $method(self, rhs: &Expr) -> Expr {
                Expr::binary(Binary::$op, &Expr::constant(self), rhs)
            }
        }
        impl $trait<Expr> for f64 {
            type Output = Expr;
            fn $method(self, rhs: Expr) -> Expr {
                Expr::binary(Binary::$op, &Expr::constant(self), &rhs)
            }
        }
        impl $assign_trait<&Expr> for Expr {
            fn $assign(&mut self, rhs: &Expr) {
                *self = Expr::binary(Binary::$op, self, rhs);
            }
        }
        impl $assign_trait<Expr> for Expr {
            fn $assign(&mut self, rhs: Expr) {
                *self = Expr::binary(Binary::$op, self, &rhs);
            }
        }
        impl $assign_trait<f64> for Expr {
            fn $assign(&mut self, rhs: f64) {
                *self = Expr::binary(Binary::$op, self, &Expr::constant(rhs));
            }
        }
    };
}

binary_op!(Add, add, AddAssign, add_assign, Add);
binary_op!(Sub, sub, SubAssign, sub_assign, Sub);
binary_op!(Mul, mul, MulAssign, mul_assign, Mul);
binary_op!(Div, div, DivAssign, div_assign, Div);

impl Neg for &Expr {
    type Output = Expr;
    fn neg(self) -> Expr {
        Expr::unary(Unary::Neg, self)
    }
}

impl Neg for Expr {
    type Output = Expr;
    fn neg(self) -> Expr {
        Expr::unary(Unary::Neg, &self)
    }
}

impl num_traits::Zero for Expr {
    fn zero() -> Expr {
        Expr::constant(0.0)
    }
    /// True only for the constant 0 (a symbolic expression is never known to be zero).
    fn is_zero(&self) -> bool {
        self.as_constant() == Some(0.0)
    }
}

impl num_traits::One for Expr {
    fn one() -> Expr {
        Expr::constant(1.0)
    }
}

impl Sum for Expr {
    fn sum<I: Iterator<Item = Expr>>(iter: I) -> Expr {
        iter.fold(Expr::constant(0.0), |acc, e| acc + e)
    }
}

impl<'a> Sum<&'a Expr> for Expr {
    fn sum<I: Iterator<Item = &'a Expr>>(iter: I) -> Expr {
        iter.fold(Expr::constant(0.0), |acc, e| acc + e)
    }
}

impl Product for Expr {
    fn product<I: Iterator<Item = Expr>>(iter: I) -> Expr {
        iter.fold(Expr::constant(1.0), |acc, e| acc * e)
    }
}

impl<'a> Product<&'a Expr> for Expr {
    fn product<I: Iterator<Item = &'a Expr>>(iter: I) -> Expr {
        iter.fold(Expr::constant(1.0), |acc, e| acc * e)
    }
}
