//! Scene layer: model building and validation, forward kinematics, one-joint motions,
//! collision queries and sweeps, navigation footprints, and property tests on generated scene
//! graphs.

mod collision;
mod fixtures;
mod footprint;
pub mod generators;
mod kinematics;
mod kitchen;
mod nested_bound;
mod properties;
mod route;
mod state;
mod sweep;
mod sweep_soundness;
mod trajectory;
mod urdf;
#[cfg(feature = "pinocchio")]
mod urdf_pinocchio;
mod validation;
