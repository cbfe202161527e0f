//! Kinematics layer: robot and scene kinematics on top of Pinocchio.
//!
//! [`pinocchio`] is the safe binding (models built from Rust or parsed from URDF with
//! `Model::from_urdf_str`, forward kinematics, frame Jacobians, configuration-space
//! `integrate`/`difference`). Higher layers
//! ([`crate::motion`]) import from here, never the other way round.

pub use kinscene_pinocchio as pinocchio;

/// Errors of the kinematics layer.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The Pinocchio backend rejected its input, failed to load, or threw.
    #[error("Pinocchio: {0}")]
    Pinocchio(#[from] kinscene_pinocchio::Error),
}
