//! Kinematics layer: the mobile manipulator's kinematics on top of Pinocchio, and inverse
//! kinematics.
//!
//! [`robot`] (the mobile manipulator), [`ik`] (Pinocchio + Clarabel) and `pinocchio`, the safe
//! binding (models built from Rust or parsed from URDF with `Model::from_urdf_str`, forward
//! kinematics, frame Jacobians, configuration-space `integrate`/`difference`). The whole layer
//! needs the `pinocchio` feature. It is about the robot only: estimating a scene part's joint
//! from observations is [`crate::articulation`], beside it. Higher layers (`crate::motion`)
//! import from here, never the other way round.

pub use kinscene_pinocchio as pinocchio;

pub mod ik;
pub mod robot;

/// Errors of the kinematics layer: one variant per module, each wrapping that module's enum.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The Pinocchio backend rejected its input, failed to load, or threw.
    #[error("Pinocchio: {0}")]
    Pinocchio(#[from] kinscene_pinocchio::Error),
    /// The robot model: URDF, configurations, collision geometry.
    #[error("robot: {0}")]
    Robot(#[from] robot::RobotError),
    /// Inverse kinematics: bad targets or settings, a failed QP.
    #[error("IK: {0}")]
    Ik(#[from] ik::IkError),
}
