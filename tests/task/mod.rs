//! Task layer: goals, the lattice search, baselines, the validator.

mod anytime;
mod baselines;
mod basic;
mod boundary;
mod brute_force;
mod cases;
pub mod generators;
mod reduction;
mod refiner;
pub mod rooms;
mod validate;
