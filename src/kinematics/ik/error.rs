//! The inverse-kinematics error type.

/// Bad input to the IK solver, or a backend that failed. Not converging is no error: it is an
/// [`IkOutcome`](crate::kinematics::ik::IkOutcome) other than `Solved`.
#[non_exhaustive]
#[derive(Debug, Clone, thiserror::Error)]
pub enum IkError {
    /// A vector has the wrong length.
    #[error("{what}: expected {expected} entries, got {got}")]
    DimensionMismatch {
        /// Which argument (`"seed"`, ...).
        what: &'static str,
        /// The length the model requires.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// An input holds NaN or an infinity.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which argument (`"seed"`, `"target position"`, `"target rotation"`, ...).
        what: &'static str,
    },
    /// The approach axis of a [`crate::kinematics::ik::IkTarget::PositionAxis`] is not unit
    /// length (it was built with `Unit::new_unchecked` from a non-unit vector).
    #[error("target axis has norm {norm}, not 1")]
    NonUnitAxis {
        /// The axis' Euclidean norm.
        norm: f64,
    },
    /// The half-angle of a [`crate::kinematics::ik::IkTarget::PositionCone`] is not in
    /// `[0, π/2]` (or not finite).
    #[error("target cone half-angle {half_angle} rad is not in [0, pi/2]")]
    InvalidCone {
        /// The half-angle given (rad).
        half_angle: f64,
    },
    /// The rotation of a [`crate::kinematics::ik::IkTarget::Pose`] is not a unit quaternion.
    #[error("target rotation quaternion has norm {norm}, not 1")]
    NonUnitRotation {
        /// The quaternion's Euclidean norm.
        norm: f64,
    },
    /// A field of [`crate::kinematics::ik::IkSettings`] is out of range.
    #[error("{0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
    /// The target frame is not a frame of the model.
    #[error("frame index {index} out of range (the model has {count} frames)")]
    UnknownFrame {
        /// The index given.
        index: usize,
        /// The number of frames of the model.
        count: usize,
    },
    /// The model has no degree of freedom that moves the target frame.
    #[error("frame {frame:?} is not moved by any joint of the model")]
    NoDegreesOfFreedom {
        /// The frame's name.
        frame: String,
    },
    /// The Pinocchio backend rejected its input, failed to load, or threw.
    #[error("Pinocchio: {0}")]
    Pinocchio(#[from] kinscene_pinocchio::Error),
    /// Clarabel could not set up an IK step's QP (its `SolverError`, formatted).
    #[error("Clarabel rejected the IK step QP: {message}")]
    QpSetup {
        /// Clarabel's message.
        message: String,
    },
    /// Clarabel ended an IK step's QP with a status other than `Solved`/`AlmostSolved`. The
    /// step QP is always feasible (dq = 0 satisfies every constraint) and strictly convex, so
    /// this is a numerical failure of the backend, not a property of the target.
    #[error("Clarabel failed on the IK step QP with status {status}")]
    QpFailed {
        /// Clarabel's `SolverStatus` name (`"NumericalError"`, `"MaxIterations"`, ...).
        status: String,
    },
}
