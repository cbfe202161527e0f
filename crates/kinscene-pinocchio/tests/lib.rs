//! Integration tests of the Pinocchio binding (one test binary; see `Cargo.toml`).
//!
//! Expected values come from independent computations written out in each test: nalgebra
//! products of the joint transforms (for URDF models: of the document's origins and axes),
//! finite differences, the closed-form SE(2) exponential.

mod support;

mod configuration;
mod errors;
mod forward_kinematics;
mod jacobian;
mod threads;
mod urdf;
