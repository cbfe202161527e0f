//! The crate's error type.

/// Everything that can go wrong in this crate: bad input (detected in Rust before any C++
/// call), a shim that cannot be loaded, or an exception thrown by Pinocchio.
#[non_exhaustive]
#[derive(Debug, Clone, thiserror::Error)]
pub enum Error {
    /// The Pinocchio shim could not be loaded (missing file, unresolved symbol).
    #[error(transparent)]
    Load(#[from] kinscene_shim::LoadError),
    /// Pinocchio threw a C++ exception (its message is kept), or the shim rejected its input.
    #[error(transparent)]
    Backend(#[from] kinscene_shim::CallError),
    /// A vector or matrix has the wrong length.
    #[error("{what}: expected {expected} entries, got {got}")]
    DimensionMismatch {
        /// Which argument (`"q"`, `"v"`, ...).
        what: &'static str,
        /// The length the model requires.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// An input holds NaN or an infinity (for a placement: or its quaternion is near zero, so it
    /// is no rotation).
    #[error("{what} is not finite")]
    NonFinite {
        /// Which argument (`"q"`, `"parent_from_joint"`, `"mass"`, ...).
        what: &'static str,
    },
    /// A joint axis is zero (norm below 1e-12) or not finite.
    #[error("joint {joint:?}: invalid axis {axis:?} (must be finite and non-zero)")]
    InvalidAxis {
        /// The joint being added.
        joint: String,
        /// The axis given.
        axis: [f64; 3],
    },
    /// A joint index does not exist in the model (e.g. an unknown parent joint).
    #[error("joint index {index} out of range (the model has {count} joints, universe included)")]
    JointOutOfRange {
        /// The index given.
        index: usize,
        /// The number of joints, universe included.
        count: usize,
    },
    /// A frame index does not exist in the model.
    #[error("frame index {index} out of range (the model has {count} frames)")]
    FrameOutOfRange {
        /// The index given.
        index: usize,
        /// The number of frames.
        count: usize,
    },
    /// A joint or frame name is already taken. Joints and frames share one namespace, because
    /// every joint also owns a frame of the same name.
    #[error("{what} name {name:?} is already used by a joint or frame")]
    DuplicateName {
        /// `"joint"` or `"frame"`.
        what: &'static str,
        /// The name.
        name: String,
    },
    /// A name is empty or contains a NUL byte.
    #[error("{what} name {name:?} is empty or contains a NUL byte")]
    InvalidName {
        /// `"joint"` or `"frame"`.
        what: &'static str,
        /// The name.
        name: String,
    },
    /// Joints must be added depth-first (Pinocchio's requirement): the parent of a new joint
    /// must be the universe or lie on the chain from the universe to the last added joint.
    #[error(
        "joint {joint:?}: parent {parent} breaks depth-first order; add each branch completely before the next"
    )]
    NotDepthFirst {
        /// The joint being added.
        joint: String,
        /// Its parent joint index.
        parent: usize,
    },
    /// A position range with `lower > upper` (or a NaN bound).
    #[error("joint {joint:?}: lower position limit {lower} is above the upper limit {upper}")]
    InvertedLimits {
        /// The joint being added.
        joint: String,
        /// Lower bound (radians or metres).
        lower: f64,
        /// Upper bound (radians or metres).
        upper: f64,
    },
    /// A velocity or effort limit that is negative or NaN.
    #[error("joint {joint:?}: {what} limit {value} must be non-negative")]
    NegativeLimit {
        /// The joint being added.
        joint: String,
        /// `"velocity"` or `"effort"`.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// Position limits were given for a joint whose configuration is not a plain coordinate
    /// (unbounded revolute, planar).
    #[error("joint {joint:?}: position limits are only supported on revolute and prismatic joints")]
    LimitsNotSupported {
        /// The joint being added.
        joint: String,
    },
    /// A body with negative mass.
    #[error("body on joint {joint}: negative mass {mass} kg")]
    NegativeMass {
        /// The supporting joint index.
        joint: usize,
        /// The mass given (kg).
        mass: f64,
    },
    /// A rotational inertia that is not symmetric positive semi-definite.
    #[error("body on joint {joint}: rotational inertia {reason}")]
    InvalidInertia {
        /// The supporting joint index.
        joint: usize,
        /// What is wrong.
        reason: &'static str,
    },
    /// A `(cos, sin)` pair of an unbounded revolute or planar joint is not unit length (see
    /// [`crate::UNIT_NORM_TOLERANCE`]); use [`crate::normalize`].
    #[error("q: the (cos, sin) pair of joint {joint:?} has norm {norm}, not 1")]
    NotNormalized {
        /// The joint whose pair is off.
        joint: String,
        /// The pair's Euclidean norm.
        norm: f64,
    },
    /// A joint of a model Pinocchio built (from URDF) has a type this crate has no
    /// [`crate::JointKind`] for (e.g. a URDF `floating` joint, Pinocchio's `JointModelFreeFlyer`).
    #[error(
        "joint {joint:?}: Pinocchio joint type {kind} is not supported (revolute, continuous, prismatic and planar are)"
    )]
    UnsupportedJoint {
        /// The joint's name.
        joint: String,
        /// Pinocchio's short name of the joint type.
        kind: String,
    },
    /// A single joint value was given for a joint whose configuration is not one number
    /// ([`crate::JointKind::Planar`]).
    #[error("joint {joint:?} has no single joint value (it is planar)")]
    NotScalarJoint {
        /// The joint's name.
        joint: String,
    },
    /// A [`crate::Data`] was used with a [`crate::Model`] other than the one it was made for.
    #[error("this Data was created for a different Model")]
    DataModelMismatch,
    /// Placements were read from a [`crate::Data`] before [`crate::forward_kinematics`] ran on
    /// it (or after [`crate::frame_jacobian`], which updates only part of it).
    #[error("placements are not computed: call forward_kinematics first")]
    KinematicsNotComputed,
}
