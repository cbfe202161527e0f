//! Integration tests of kinscene-casadi: expressions, IPOPT solves against analytic optima,
//! error paths, and a planar-arm IK written with nalgebra transforms.

mod analytic;
mod arm;
mod errors;
mod expr;
mod outcomes;
