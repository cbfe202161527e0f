//! The scene layer's error enum.
//!
//! `Err` is for bad input only: a malformed model description, a state that does not fit the
//! model, an id from another model. Whether a motion collides is an outcome
//! ([`crate::scene::collision::SweepOutcome`]), not an error.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::PathBuf;

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
    /// parent is the first. For a URDF document, the elements are link names (each link's
    /// parent link is the next one).
    #[error("parent cycle through parts {parts:?}")]
    Cycle {
        /// The parts (or URDF links) on the cycle, in parent order.
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
    #[error("{0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
    /// The navigation grid would have more cells than allowed.
    #[error("navigation grid of {cells} cells exceeds the maximum {max}")]
    GridTooLarge {
        /// Cells requested.
        cells: u64,
        /// Maximum allowed.
        max: u64,
    },

    // ----- URDF import (`scene::urdf::read_str` / `read_file`) -----
    /// The document is not well-formed XML or not a URDF `<robot>` (urdf-rs's message), or its
    /// elements are nested deeper than the importer accepts.
    #[error("URDF parse error: {message}")]
    UrdfParse {
        /// What the parser reported.
        message: String,
    },
    /// Two URDF links share a name.
    #[error("duplicate URDF link name {name:?}")]
    DuplicateLink {
        /// The repeated link name.
        name: String,
    },
    /// A URDF joint names a parent or child link that does not exist.
    #[error("URDF joint {joint:?} names unknown {role} link {link:?}")]
    MissingLink {
        /// The joint.
        joint: String,
        /// `"parent"` or `"child"`.
        role: String,
        /// The link name it gave.
        link: String,
    },
    /// A URDF link is the child of more than one joint.
    #[error("URDF link {link:?} is the child of several joints {joints:?}")]
    SeveralParents {
        /// The link.
        link: String,
        /// The joints naming it as their child, in document order.
        joints: Vec<String>,
    },
    /// Several URDF links are no joint's child; a scene has exactly one root (the base).
    #[error("URDF has several root links {links:?}; a scene has exactly one (the static base)")]
    SeveralRoots {
        /// The root links, in document order.
        links: Vec<String>,
    },
    /// The URDF robot has no links, so there is no root link for the base.
    #[error("URDF robot {robot:?} has no links (no root link for the base)")]
    NoRoot {
        /// The `<robot name>`.
        robot: String,
    },
    /// A URDF joint has a type a scene cannot express (`planar`, `floating`, `spherical`).
    #[error(
        "URDF joint {joint:?} has unsupported type {kind:?} (scenes use revolute, continuous, prismatic and fixed)"
    )]
    UnsupportedJointType {
        /// The joint.
        joint: String,
        /// The type given.
        kind: String,
    },
    /// A revolute or prismatic URDF joint has no `<limit>` with finite `lower` and `upper`.
    #[error("URDF {kind} joint {joint:?} has no <limit> with finite lower and upper bounds")]
    MissingLimits {
        /// The joint.
        joint: String,
        /// `"revolute"` or `"prismatic"`.
        kind: String,
    },
    /// A `*_handle` link is attached (through fixed joints) to the static base rather than to a
    /// part; handles belong to articulated parts.
    #[error("URDF handle link {handle:?} is attached to the static base, not to a part")]
    HandleOnBase {
        /// The handle link.
        handle: String,
    },
    /// A mesh file does not exist.
    #[error("URDF link {link:?}: mesh {uri:?} not found at {path:?}")]
    MeshNotFound {
        /// The link whose collision element references the mesh.
        link: String,
        /// The `filename` as written.
        uri: String,
        /// Where it was looked for.
        path: PathBuf,
    },
    /// A mesh file exists but could not be read or parsed.
    #[error("URDF link {link:?}: mesh {uri:?} at {path:?} is unreadable: {message}")]
    MeshUnreadable {
        /// The link whose collision element references the mesh.
        link: String,
        /// The `filename` as written.
        uri: String,
        /// The resolved path.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A mesh file is not STL, OBJ or COLLADA (`.dae`).
    #[error(
        "URDF link {link:?}: mesh {uri:?} at {path:?} has an unsupported format (use STL, OBJ or COLLADA .dae)"
    )]
    UnsupportedMeshFormat {
        /// The link whose collision element references the mesh.
        link: String,
        /// The `filename` as written.
        uri: String,
        /// The resolved path.
        path: PathBuf,
    },
    /// A mesh URI uses a scheme the importer does not resolve (for example `http://`).
    #[error(
        "URDF link {link:?}: mesh URI {uri:?} has an unsupported scheme (use a path, file:// or package://)"
    )]
    UnsupportedMeshUri {
        /// The link whose collision element references the mesh.
        link: String,
        /// The `filename` as written.
        uri: String,
    },
    /// A `package://NAME/...` mesh URI names a package missing from the import options'
    /// package paths.
    #[error("URDF link {link:?}: mesh {uri:?} names unknown package {package:?}")]
    UnknownPackage {
        /// The link whose collision element references the mesh.
        link: String,
        /// The `filename` as written.
        uri: String,
        /// The package name.
        package: String,
    },
    /// Reading or writing a file or directory failed.
    #[error("I/O error on {path:?}: {message}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's message.
        message: String,
    },

    // ----- URDF export (`scene::urdf::write_string` / `write_file`) -----
    /// A convex mesh without a source file cannot be referenced from URDF unless a mesh
    /// directory is given to write it into.
    #[error(
        "{what} is a convex mesh without a source file; set ExportOptions::mesh_dir to write it as OBJ"
    )]
    MeshWithoutSource {
        /// Which collider or base shape.
        what: String,
    },
    /// A name cannot be written as a URDF link or joint name: two elements would get the same
    /// link name, or it contains characters XML cannot hold.
    #[error("cannot export name {name:?} to URDF: {reason}")]
    UnwritableName {
        /// The name.
        name: String,
        /// Why.
        reason: String,
    },
}
