//! Articulated parts (the vertices V) and their handles.

use nalgebra::{Isometry3, Point3, Vector3};
use serde::{Deserialize, Serialize};

use super::ids::{JointId, Parent, PartId};
use super::joint::Joint;
use super::shape::{Collider, Shape};

/// An interaction point on a part: where the gripper grasps and the outward surface normal
/// there, both in the part frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Handle {
    /// Name, unique among all handles of the scene.
    pub name: String,
    /// Grasp point `p` (m), in the part frame.
    pub position: Point3<f64>,
    /// Outward surface normal at the grasp point, in the part frame. Normalised by the builder.
    pub normal: Vector3<f64>,
}

impl Handle {
    /// A handle at `position` with outward `normal` (part frame).
    pub fn new(name: impl Into<String>, position: Point3<f64>, normal: Vector3<f64>) -> Self {
        Handle {
            name: name.into(),
            position,
            normal,
        }
    }
}

/// Builder input for one part: plain data, validated by
/// [`SceneModelBuilder::build`](crate::scene::SceneModelBuilder::build).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartSpec {
    /// Unique part name (URDF link name).
    pub name: String,
    /// Name of the parent part, or `None` for a part attached to the base map.
    pub parent: Option<String>,
    /// The joint connecting the part to its parent.
    pub joint: Joint,
    /// Collision geometry, in the part frame.
    pub colliders: Vec<Collider>,
    /// Interaction points.
    pub handles: Vec<Handle>,
}

impl PartSpec {
    /// A part attached to the base map by `joint`.
    pub fn on_base(name: impl Into<String>, joint: Joint) -> Self {
        PartSpec {
            name: name.into(),
            parent: None,
            joint,
            colliders: Vec::new(),
            handles: Vec::new(),
        }
    }

    /// A part attached to the part named `parent` by `joint`.
    pub fn on_part(name: impl Into<String>, parent: impl Into<String>, joint: Joint) -> Self {
        PartSpec {
            parent: Some(parent.into()),
            ..PartSpec::on_base(name, joint)
        }
    }

    /// Adds a collider at `part_from_shape`.
    pub fn with_collider(mut self, shape: Shape, part_from_shape: Isometry3<f64>) -> Self {
        self.colliders.push(Collider::new(shape, part_from_shape));
        self
    }

    /// Adds a handle.
    pub fn with_handle(mut self, handle: Handle) -> Self {
        self.handles.push(handle);
        self
    }
}

/// A validated part of a built [`SceneModel`](crate::scene::SceneModel).
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    pub(crate) name: String,
    pub(crate) id: PartId,
    pub(crate) parent: Parent,
    pub(crate) colliders: Vec<Collider>,
    pub(crate) handles: Vec<Handle>,
    pub(crate) children: Vec<PartId>,
    /// One past the last id of this part's subtree (pre-order numbering).
    pub(crate) subtree_end: usize,
    pub(crate) depth: usize,
}

impl Part {
    /// The part's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// The part's id.
    pub fn id(&self) -> PartId {
        self.id
    }
    /// What the part is attached to.
    pub fn parent(&self) -> Parent {
        self.parent
    }
    /// The joint connecting the part to its parent.
    pub fn joint(&self) -> JointId {
        self.id.joint()
    }
    /// Collision geometry in the part frame.
    pub fn colliders(&self) -> &[Collider] {
        &self.colliders
    }
    /// Handles, with unit normals.
    pub fn handles(&self) -> &[Handle] {
        &self.handles
    }
    /// Parts attached directly to this one.
    pub fn children(&self) -> &[PartId] {
        &self.children
    }
    /// This part and all its descendants: the parts its joint moves.
    pub fn subtree(&self) -> impl ExactSizeIterator<Item = PartId> + use<> {
        (self.id.0..self.subtree_end).map(PartId)
    }
    /// Whether `other` is this part or one of its descendants.
    pub fn subtree_contains(&self, other: PartId) -> bool {
        (self.id.0..self.subtree_end).contains(&other.0)
    }
    /// Number of joints between the base and this part (1 for a part on the base).
    pub fn depth(&self) -> usize {
        self.depth
    }
}
