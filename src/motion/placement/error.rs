//! The placement layer's error enum: bad input and broken backends only.

use crate::kinematics::ik::IkError;
use crate::kinematics::robot::RobotError;

/// Why a placement or manipulation plan could not be computed.
///
/// Bad input (unknown ids, a target value outside the joint's limits, invalid settings, a
/// solver built for another robot) and backend failures (CasADi cannot be loaded or throws).
/// Unreachable waypoints, colliding base poses and a rejected optimisation are outcomes
/// ([`PlacementOutcome`](super::PlacementOutcome)), not errors.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum PlacementError {
    /// The scene rejected the input: unknown joint or handle id, a handle that does not move
    /// with the joint, a target value outside the joint's limits, a state of the wrong size.
    #[error("scene: {0}")]
    Scene(#[from] crate::scene::Error),
    /// The robot rejected the input (wrong arm dimension, non-finite value).
    #[error("robot: {0}")]
    Robot(#[from] RobotError),
    /// The IK solver rejected its input.
    #[error("IK: {0}")]
    Ik(#[from] IkError),
    /// The CasADi/IPOPT backend failed to load, rejected the problem or threw.
    #[error("CasADi: {0}")]
    Casadi(#[from] kinscene_casadi::Error),
    /// Pinocchio failed (the verification of an optimised plan uses its forward kinematics).
    #[error("Pinocchio: {0}")]
    Pinocchio(#[from] kinscene_pinocchio::Error),
    /// A setting is out of its documented range.
    #[error("{0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
    /// An input value is NaN or infinite.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which input, e.g. `"robot_from"`.
        what: &'static str,
    },
    /// Two inputs do not fit together (e.g. an IK solver whose model has another number of
    /// joints than the robot, or a seed of the wrong size).
    #[error("{what}: expected {expected}, got {got}")]
    DimensionMismatch {
        /// Which input.
        what: &'static str,
        /// The size required.
        expected: usize,
        /// The size given.
        got: usize,
    },
}
