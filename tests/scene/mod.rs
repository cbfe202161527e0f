//! Scene layer: model building and validation, forward kinematics, one-joint motions,
//! collision queries and sweeps, navigation footprints, and property tests on generated scene
//! graphs.

mod collision;
mod fixtures;
mod footprint;
pub mod generators;
mod kinematics;
mod properties;
mod state;
mod sweep;
mod sweep_soundness;
mod trajectory;
mod validation;
