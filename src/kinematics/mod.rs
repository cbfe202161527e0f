//! Kinematics layer: robot kinematics on top of Pinocchio, inverse kinematics, and articulation
//! estimation.
//!
//! [`articulation`] (pure Rust, always available) estimates a part's joint from observations.
//! With the `pinocchio` feature: [`robot`] (the mobile manipulator), [`ik`] (Pinocchio + Clarabel)
//! and `pinocchio`, the safe binding (models built from Rust or parsed from URDF with
//! `Model::from_urdf_str`, forward kinematics, frame Jacobians, configuration-space
//! `integrate`/`difference`). Higher layers
//! (`crate::motion`) import from here, never the other way round.

#[cfg(feature = "pinocchio")]
pub use kinscene_pinocchio as pinocchio;

pub mod articulation;
#[cfg(feature = "pinocchio")]
pub mod ik;
#[cfg(feature = "pinocchio")]
pub mod robot;

/// Errors of the kinematics layer: one variant per module, each wrapping that module's enum.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The Pinocchio backend rejected its input, failed to load, or threw.
    #[cfg(feature = "pinocchio")]
    #[error("Pinocchio: {0}")]
    Pinocchio(#[from] kinscene_pinocchio::Error),
    /// The robot model: URDF, configurations, collision geometry.
    #[cfg(feature = "pinocchio")]
    #[error("robot: {0}")]
    Robot(#[from] robot::RobotError),
    /// Inverse kinematics: bad targets or settings, a failed QP.
    #[cfg(feature = "pinocchio")]
    #[error("IK: {0}")]
    Ik(#[from] ik::IkError),
    /// Articulation estimation: bad observations or settings.
    #[error("articulation: {0}")]
    Articulation(#[from] articulation::ArticulationError),
}
