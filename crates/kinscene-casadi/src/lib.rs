//! Nonlinear programs for kinscene, written as symbolic expressions in Rust and solved by IPOPT
//! through CasADi.
//!
//! # What it wraps
//! [CasADi](https://web.casadi.org) 3.8 (from the PyPI wheel `casadi`) and the IPOPT 3.14
//! plugin it ships. An [`Nlp`] is built in Rust from [`Expr`] values: decision variables with
//! bounds, parameters, an objective and constraints. [`Nlp::build`] linearises the expression
//! DAG into a tape (each shared subexpression once), and the C++ shim rebuilds it as CasADi
//! `SX` and calls `casadi::nlpsol("…", "ipopt", …)` once; CasADi derives exact gradients,
//! Jacobians and Hessians. [`NlpSolver::solve`] then runs IPOPT for any initial guess and
//! parameter values, returning the solution, the multipliers and IPOPT's status.
//!
//! `Expr` supports nalgebra matrices (`Matrix4<Expr>` products, `Vector3<Expr>` dot and cross),
//! so kinematic chains are written as products of transforms whose entries are expressions in
//! `sin`/`cos` of the joint variables. [`Nlp::eval`] and [`NlpSolver::eval`] evaluate the same
//! expressions in pure Rust, to check a solution independently of CasADi.
//!
//! # Isolation
//! The shim (`cpp/shim.cpp`, C ABI in `cpp/shim.h`) is compiled by `build.rs` into its own
//! shared object with an RPATH into the CasADi wheel, and loaded on first use with
//! `dlopen(RTLD_LOCAL | RTLD_DEEPBIND)` (crate `kinscene-shim`), so CasADi's symbols do not
//! meet other backends'. Every C++ exception is caught in the shim and returned as
//! [`Error::Backend`] with CasADi's message. Build-time override of the CasADi location:
//! `KINSCENE_CASADI_PREFIX`; run-time override of the shim: `KINSCENE_CASADI_SHIM`.
//!
//! # Errors and outcomes
//! Bad input (NaN, inverted bounds, wrong lengths, an expression of another `Nlp`) and backend
//! failures are [`Error`]s. A problem that is infeasible or does not converge is `Ok` with an
//! [`NlpStatus`] other than success.

#![warn(missing_docs)]

mod arith;
mod error;
mod expr;
mod ffi;
mod nlp;
mod ops;
mod settings;
mod solution;
mod solver;
mod tape;

pub use error::Error;
pub use expr::Expr;
pub use ffi::casadi_version;
pub use kinscene_shim::{CallError, LoadError};
pub use nlp::Nlp;
pub use settings::{Hessian, IpoptOption, LinearSolver, NlpSettings, OptionValue};
pub use solution::{NlpSolution, NlpStatus};
pub use solver::{Evaluation, NlpSolver};
