//! Typed indices into a built [`SceneModel`](crate::scene::SceneModel).
//!
//! Ids are assigned by [`SceneModelBuilder::build`](crate::scene::SceneModelBuilder::build)
//! and are only meaningful for the model that issued them. Parts are numbered in depth-first
//! pre-order of the kinematic tree (a parent before its children, siblings in insertion order),
//! so the subtree of a part is a contiguous id range. Joint `i` moves part `i`.

use serde::{Deserialize, Serialize};

/// Index of an articulated part (a vertex of V).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PartId(pub(crate) usize);

/// Index of a joint (an edge of E); also the index of its value in a
/// [`State`](crate::scene::State).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct JointId(pub(crate) usize);

/// Index of a handle: the part that carries it and its position in that part's handle list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct HandleId {
    pub(crate) part: PartId,
    pub(crate) index: usize,
}

/// Index of a static collision shape of the base map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct BaseShapeId(pub(crate) usize);

impl PartId {
    /// The position of the part in [`SceneModel::parts`](crate::scene::SceneModel::parts).
    pub fn index(self) -> usize {
        self.0
    }
    /// The joint that moves this part (same index).
    pub fn joint(self) -> JointId {
        JointId(self.0)
    }
}

impl JointId {
    /// The position of the joint in [`SceneModel::joints`](crate::scene::SceneModel::joints)
    /// and of its value in a [`State`](crate::scene::State).
    pub fn index(self) -> usize {
        self.0
    }
    /// The part this joint moves (same index).
    pub fn part(self) -> PartId {
        PartId(self.0)
    }
}

impl HandleId {
    /// The part carrying the handle.
    pub fn part(self) -> PartId {
        self.part
    }
    /// The handle's position in [`Part::handles`](crate::scene::Part::handles).
    pub fn index(self) -> usize {
        self.index
    }
}

impl BaseShapeId {
    /// The position of the shape in [`BaseMap::shapes`](crate::scene::BaseMap::shapes).
    pub fn index(self) -> usize {
        self.0
    }
}

/// What a part is attached to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Parent {
    /// The static base map B (the world frame).
    Base,
    /// Another articulated part.
    Part(PartId),
}
