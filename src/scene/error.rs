//! The scene layer's error enum.
//!
//! `Err` is for bad input only: a malformed model description, a state that does not fit the
//! model, an id from another model. Whether a motion collides is an outcome
//! ([`crate::scene::collision::SweepOutcome`]), not an error.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Which kind of named element of a scene an error refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum ElementKind {
    /// An articulated part (a vertex of V).
    Part,
    /// A joint (an edge of E).
    Joint,
    /// A handle (interaction point) on a part.
    Handle,
    /// A static collision shape of the base map B.
    BaseShape,
}

impl fmt::Display for ElementKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ElementKind::Part => "part",
            ElementKind::Joint => "joint",
            ElementKind::Handle => "handle",
            ElementKind::BaseShape => "base shape",
        })
    }
}

/// Errors of the scene layer. Every variant names the offending element.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// Two elements of the same kind share a name.
    #[error("duplicate {kind} name {name:?}")]
    DuplicateName {
        /// The kind of element.
        kind: ElementKind,
        /// The repeated name.
        name: String,
    },
    /// An element has an empty name.
    #[error("a {kind} has an empty name")]
    EmptyName {
        /// The kind of element.
        kind: ElementKind,
    },
    /// No part has this name.
    #[error("unknown part {name:?}")]
    UnknownPart {
        /// The name looked up.
        name: String,
    },
    /// No joint has this name.
    #[error("unknown joint {name:?}")]
    UnknownJoint {
        /// The name looked up.
        name: String,
    },
    /// No handle has this name.
    #[error("unknown handle {name:?}")]
    UnknownHandle {
        /// The name looked up.
        name: String,
    },
    /// No base shape has this name.
    #[error("unknown base shape {name:?}")]
    UnknownBaseShape {
        /// The name looked up.
        name: String,
    },
    /// An id is out of range for this model (it was taken from another model).
    #[error("{kind} id {index} does not belong to this model")]
    UnknownId {
        /// The kind of id.
        kind: ElementKind,
        /// The id's index.
        index: usize,
    },
    /// A part names a parent that is neither the base nor another part.
    #[error("part {part:?} has unknown parent {parent:?}")]
    UnknownParent {
        /// The part.
        part: String,
        /// The parent name it gave.
        parent: String,
    },
    /// The parent relation has a cycle: each part's parent is the next one, the last one's
    /// parent is the first.
    #[error("parent cycle through parts {parts:?}")]
    Cycle {
        /// The parts on the cycle, in parent order.
        parts: Vec<String>,
    },
    /// A length, coordinate or limit exceeds [`MAX_MAGNITUDE`](crate::scene::MAX_MAGNITUDE) in
    /// magnitude (no scene is that large; such values only come from corrupted input).
    #[error("{what} has magnitude {value} above {max}")]
    OutOfRange {
        /// What holds the value.
        what: String,
        /// The value given.
        value: f64,
        /// The largest magnitude accepted.
        max: f64,
    },
    /// A value that must be finite is NaN or infinite.
    #[error("non-finite value in {what}")]
    NonFinite {
        /// What holds the value, e.g. `joint "hinge" axis`.
        what: String,
    },
    /// A joint axis has norm below [`crate::scene::MIN_AXIS_NORM`].
    #[error("joint {joint:?} has a zero axis")]
    ZeroAxis {
        /// The joint.
        joint: String,
    },
    /// A handle normal has norm below [`crate::scene::MIN_AXIS_NORM`].
    #[error("handle {handle:?} has a zero normal")]
    ZeroNormal {
        /// The handle.
        handle: String,
    },
    /// A prismatic joint is marked continuous (only revolute joints can be).
    #[error("prismatic joint {joint:?} is marked continuous")]
    ContinuousPrismatic {
        /// The joint.
        joint: String,
    },
    /// A rotation quaternion is not of unit norm (within 1e-6).
    #[error("rotation of {what} is not a unit quaternion (norm {norm})")]
    InvalidRotation {
        /// What holds the rotation.
        what: String,
        /// The quaternion's norm.
        norm: f64,
    },
    /// A joint's lower limit is above its upper limit.
    #[error("joint {joint:?} has lower limit {lower} above upper limit {upper}")]
    InvalidLimits {
        /// The joint.
        joint: String,
        /// Lower limit (rad or m).
        lower: f64,
        /// Upper limit (rad or m).
        upper: f64,
    },
    /// A shape dimension or a setting that must be positive is not.
    #[error("{what} must be positive, got {value}")]
    NonPositive {
        /// What holds the value.
        what: String,
        /// The value given.
        value: f64,
    },
    /// A convex mesh has fewer than 4 vertices or they span no volume.
    #[error("degenerate convex mesh in {what}: {reason}")]
    DegenerateMesh {
        /// Which collider.
        what: String,
        /// Why it was rejected.
        reason: String,
    },
    /// A joint value lies outside the joint's limits.
    #[error("joint {joint:?} value {value} outside limits [{min}, {max}]")]
    JointLimit {
        /// The joint.
        joint: String,
        /// The value given (rad or m).
        value: f64,
        /// Lower limit.
        min: f64,
        /// Upper limit.
        max: f64,
    },
    /// A state or buffer does not have the size the model needs.
    #[error("{what}: expected {expected} values, got {got}")]
    DimensionMismatch {
        /// What was sized wrongly.
        what: String,
        /// Size the model needs.
        expected: usize,
        /// Size given.
        got: usize,
    },
    /// A handle is not on the part moved by a joint nor on one of its descendants.
    #[error("handle {handle:?} does not move with joint {joint:?}")]
    NotInSubtree {
        /// The handle.
        handle: String,
        /// The joint.
        joint: String,
    },
    /// A setting has an invalid value (see the setting's documentation).
    #[error("invalid setting {what}: {value}")]
    InvalidSetting {
        /// The setting.
        what: String,
        /// The value given.
        value: f64,
    },
    /// The navigation grid would have more cells than allowed.
    #[error("navigation grid of {cells} cells exceeds the maximum {max}")]
    GridTooLarge {
        /// Cells requested.
        cells: u64,
        /// Maximum allowed.
        max: u64,
    },
}
