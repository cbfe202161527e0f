//! The robot model's error type.

use std::path::PathBuf;

/// Everything that can go wrong when loading a robot, changing its settings, or evaluating its
/// kinematics with a bad configuration. Variants name the URDF element or argument at fault.
#[non_exhaustive]
#[derive(Debug, Clone, thiserror::Error)]
pub enum RobotError {
    /// The file could not be read.
    #[error("cannot read robot file {path:?}: {message}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's message.
        message: String,
    },
    /// The text is not well-formed URDF (urdf-rs's message), or nests elements too deeply.
    #[error("robot URDF is not valid XML/URDF: {message}")]
    Xml {
        /// The parser's message.
        message: String,
    },
    /// Two links or two joints share a name.
    #[error("robot URDF: duplicate {what} name {name:?}")]
    DuplicateName {
        /// `"link"` or `"joint"`.
        what: &'static str,
        /// The name.
        name: String,
    },
    /// A joint names a link that does not exist.
    #[error("robot URDF joint {joint:?}: unknown {role} link {link:?}")]
    UnknownLink {
        /// The joint.
        joint: String,
        /// `"parent"` or `"child"`.
        role: &'static str,
        /// The link named.
        link: String,
    },
    /// The links do not form one tree (several roots, a link with two parents, a cycle).
    #[error("robot URDF links do not form a tree: {reason}")]
    NotATree {
        /// What is wrong, naming the links.
        reason: String,
    },
    /// A joint type the robot model does not support at that place (`planar`/`floating` other
    /// than from the root link, `spherical` anywhere).
    #[error("robot URDF joint {joint:?}: unsupported joint type {kind}")]
    UnsupportedJointType {
        /// The joint.
        joint: String,
        /// The URDF type.
        kind: String,
    },
    /// No revolute, continuous or prismatic joint on the path from the base to the tool link.
    #[error("robot URDF has no movable joint between the base link {base:?} and the tool link")]
    NoMovableJoint {
        /// The base link.
        base: String,
    },
    /// [`RobotImportOptions::arm_root`](super::RobotImportOptions::arm_root) is not a link on
    /// the path from the base link to the tool link.
    #[error("robot arm root {link:?}: {reason}")]
    InvalidArmRoot {
        /// The link named.
        link: String,
        /// Why it cannot be the arm root.
        reason: String,
    },
    /// A [`RobotImportOptions::frozen`](super::RobotImportOptions::frozen) entry names no
    /// movable joint off the arm, or a value outside the joint's limits.
    #[error("robot frozen joint {joint:?}: {reason}")]
    InvalidFrozen {
        /// The joint named.
        joint: String,
        /// What is wrong.
        reason: String,
    },
    /// [`RobotImportOptions::tool_approach`](super::RobotImportOptions::tool_approach) is zero
    /// or not finite.
    #[error("robot tool approach {axis:?} is invalid (must be finite and non-zero)")]
    InvalidToolApproach {
        /// The direction given.
        axis: [f64; 3],
    },
    /// A joint axis is zero or not finite.
    #[error("robot URDF joint {joint:?}: invalid axis {axis:?} (must be finite and non-zero)")]
    InvalidAxis {
        /// The joint.
        joint: String,
        /// The axis given.
        axis: [f64; 3],
    },
    /// Position limits with `lower > upper` or a NaN bound.
    #[error("robot joint {joint:?}: invalid position limits [{lower}, {upper}]")]
    InvalidLimits {
        /// The joint.
        joint: String,
        /// Lower bound (rad or m).
        lower: f64,
        /// Upper bound (rad or m).
        upper: f64,
    },
    /// A velocity or acceleration limit that is not finite and positive (a missing `<limit>`
    /// reads as velocity 0).
    #[error("robot {what} limit of {joint:?} must be finite and > 0, got {value}")]
    NonPositiveLimit {
        /// The joint (or base axis `"base x"`, `"base y"`, `"base yaw"`).
        joint: String,
        /// `"velocity"` or `"acceleration"`.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A number of the description is NaN or infinite where a finite one is required.
    #[error("robot URDF: {what} is not finite")]
    NonFinite {
        /// The element, e.g. `joint "j1" origin`.
        what: String,
    },
    /// The tool link named in the import options does not exist.
    #[error("robot URDF has no tool link {link:?}")]
    MissingToolLink {
        /// The link name looked for.
        link: String,
    },
    /// A link named as contact geometry ([`super::RobotImportOptions::contact_links`]) does
    /// not exist or does not move with the tool.
    #[error("robot URDF contact link {link:?}: {reason}")]
    InvalidContactLink {
        /// The link named.
        link: String,
        /// What is wrong.
        reason: String,
    },
    /// A collision mesh cannot be used: its URI does not resolve (an unknown `package://`
    /// name, a missing file), the file is unreadable or not STL/OBJ/COLLADA, or it has no
    /// vertices. The message names the URI and, where resolved, the path.
    #[error("robot URDF link {link:?}: collision mesh {filename:?}: {reason}")]
    MeshCollision {
        /// The link.
        link: String,
        /// The mesh URI as written.
        filename: String,
        /// What went wrong (the mesh loader's message).
        reason: String,
    },
    /// A collision primitive with a non-positive or non-finite dimension.
    #[error("robot URDF link {link:?} collision {index}: {reason}")]
    InvalidShape {
        /// The link.
        link: String,
        /// Index of the collision element in the link.
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// A vector argument has the wrong length.
    #[error("{what}: expected {expected} entries, got {got}")]
    DimensionMismatch {
        /// Which argument (`"arm"`, `"acceleration limits"`, ...).
        what: &'static str,
        /// The length required.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// A configuration or setting holds NaN or an infinity.
    #[error("{what}[{index}] is not finite")]
    NonFiniteValue {
        /// Which argument (`"base"`, `"arm"`, ...).
        what: &'static str,
        /// The offending index.
        index: usize,
    },
    /// A joint value outside the joint's position limits.
    #[error("robot joint {joint:?}: value {value} outside its limits [{lower}, {upper}]")]
    OutOfLimits {
        /// The joint.
        joint: String,
        /// The value given.
        value: f64,
        /// Lower bound.
        lower: f64,
        /// Upper bound.
        upper: f64,
    },
    /// A setting out of range: the footprint radius, an allowed pair's link index, the
    /// sampling of the pairs or of the stow search.
    #[error("robot {0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
    /// No sampled arm configuration is free of self-collision and clear of the floor
    /// ([`RobotModel::with_computed_stow`](super::RobotModel::with_computed_stow)).
    #[error(
        "no stowed configuration found: none of {samples} sampled arm configurations is free of self-collision and clear of the floor"
    )]
    NoStow {
        /// Configurations tried.
        samples: usize,
    },
    /// The SRDF is not well-formed, or an element lacks what it needs.
    #[error("robot SRDF {element}: {message}")]
    Srdf {
        /// The element at fault (`document` for the file as a whole).
        element: String,
        /// What is wrong.
        message: String,
    },
    /// A robot description file (TOML) is not valid: TOML syntax, an unknown or missing key, a
    /// value of the wrong type, or a value the loader rejects (an unknown base kind, an unset
    /// variable, a bad stow, ...).
    #[error("robot description {field}: {message}")]
    Description {
        /// The element at fault: a key path such as `base.kind` or `stow.joint_1`, or for
        /// TOML errors the text at fault, its `[table]` and line.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// Pinocchio rejected the model built from the parsed robot, or could not be loaded.
    #[error("Pinocchio: {0}")]
    Pinocchio(#[from] kinscene_pinocchio::Error),
    /// parry could not compile a collision shape.
    #[error("robot link {link:?}: collision geometry cannot be compiled: {message}")]
    Collision {
        /// The link.
        link: String,
        /// parry's or the scene layer's message.
        message: String,
    },
}
