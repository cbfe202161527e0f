//! The built, immutable scene model M = ⟨B, V, E⟩.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::base::{BaseMap, BaseShape};
use super::builder::SceneModelBuilder;
use super::collision::geometry::CollisionGeometry;
use super::ids::{BaseShapeId, HandleId, JointId, Parent, PartId};
use super::joint::Joint;
use super::nav::NavGrid;
use super::part::{Handle, Part, PartSpec};
use super::state::State;
use super::{ElementKind, Error};

/// A validated scene-level articulation model: the base map B, the parts V and the joints E,
/// forming a kinematic tree of any depth rooted at the base.
///
/// Built by [`SceneModelBuilder::build`]; immutable afterwards, `Send + Sync`, cheap to share
/// behind an `Arc`. Scratch space for algorithms lives in a
/// [`SceneData`](crate::scene::SceneData) the caller owns. Serialises as its
/// [`SceneModelBuilder`] description and is re-validated when deserialised.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(into = "SceneModelBuilder", try_from = "SceneModelBuilder")]
pub struct SceneModel {
    pub(crate) parts: Vec<Part>,
    pub(crate) joints: Vec<Joint>,
    pub(crate) base: BaseMap,
    pub(crate) part_names: BTreeMap<String, PartId>,
    pub(crate) joint_names: BTreeMap<String, JointId>,
    pub(crate) handle_names: BTreeMap<String, HandleId>,
    pub(crate) base_names: BTreeMap<String, BaseShapeId>,
    pub(crate) geometry: CollisionGeometry,
    pub(crate) base_grid: NavGrid,
}

impl PartialEq for SceneModel {
    /// Models are equal if they describe the same scene (derived data is ignored).
    fn eq(&self, other: &Self) -> bool {
        self.parts == other.parts && self.joints == other.joints && self.base == other.base
    }
}

impl SceneModel {
    /// Number of joints, which is the length of a [`State`] (Pinocchio's `nq`).
    pub fn nq(&self) -> usize {
        self.joints.len()
    }

    /// All parts, indexed by [`PartId::index`] (parents before children).
    pub fn parts(&self) -> &[Part] {
        &self.parts
    }

    /// All joints, indexed by [`JointId::index`]; joint `i` moves part `i`.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The base map.
    pub fn base(&self) -> &BaseMap {
        &self.base
    }

    /// A part by id, `None` for an id from another model.
    pub fn part(&self, id: PartId) -> Option<&Part> {
        self.parts.get(id.0)
    }

    /// The kinematic chain from `part` down to the base: the part itself, its parent part, and
    /// so on to the part on the base (nearest first). Empty for an id from another model.
    pub fn path_to_base(&self, part: PartId) -> impl Iterator<Item = PartId> + '_ {
        let mut next = self.part(part).map(|_| part);
        std::iter::from_fn(move || {
            let current = next?;
            next = self.part(current).and_then(|p| match p.parent() {
                Parent::Part(q) => Some(q),
                Parent::Base => None,
            });
            Some(current)
        })
    }

    /// A joint by id, `None` for an id from another model.
    pub fn joint(&self, id: JointId) -> Option<&Joint> {
        self.joints.get(id.0)
    }

    /// A handle by id, `None` for an id from another model.
    pub fn handle(&self, id: HandleId) -> Option<&Handle> {
        self.parts.get(id.part.0)?.handles.get(id.index)
    }

    /// A base shape by id, `None` for an id from another model.
    pub fn base_shape(&self, id: BaseShapeId) -> Option<&BaseShape> {
        self.base.shapes.get(id.0)
    }

    /// The id of the part called `name`.
    ///
    /// # Errors
    /// [`Error::UnknownPart`] if there is none.
    pub fn part_id(&self, name: &str) -> Result<PartId, Error> {
        self.part_names
            .get(name)
            .copied()
            .ok_or_else(|| Error::UnknownPart { name: name.into() })
    }

    /// The id of the joint called `name`.
    ///
    /// # Errors
    /// [`Error::UnknownJoint`] if there is none.
    pub fn joint_id(&self, name: &str) -> Result<JointId, Error> {
        self.joint_names
            .get(name)
            .copied()
            .ok_or_else(|| Error::UnknownJoint { name: name.into() })
    }

    /// The id of the handle called `name`.
    ///
    /// # Errors
    /// [`Error::UnknownHandle`] if there is none.
    pub fn handle_id(&self, name: &str) -> Result<HandleId, Error> {
        self.handle_names
            .get(name)
            .copied()
            .ok_or_else(|| Error::UnknownHandle { name: name.into() })
    }

    /// The id of the base shape called `name`.
    ///
    /// # Errors
    /// [`Error::UnknownBaseShape`] if there is none.
    pub fn base_shape_id(&self, name: &str) -> Result<BaseShapeId, Error> {
        self.base_names
            .get(name)
            .copied()
            .ok_or_else(|| Error::UnknownBaseShape { name: name.into() })
    }

    /// Every handle with its id, part by part.
    pub fn handles(&self) -> impl Iterator<Item = (HandleId, &Handle)> + '_ {
        self.parts.iter().flat_map(|p| {
            p.handles
                .iter()
                .enumerate()
                .map(move |(index, h)| (HandleId { part: p.id, index }, h))
        })
    }

    /// The state with every joint at 0 clamped into its limits.
    pub fn zero_state(&self) -> State {
        State {
            q: self.joints.iter().map(|j| j.limits.clamp(0.0)).collect(),
        }
    }

    /// The occupancy grid of the base map alone (computed once at build time).
    pub fn base_grid(&self) -> &NavGrid {
        &self.base_grid
    }

    /// This model, or a copy of it whose navigation grid also covers `points`.
    ///
    /// With automatic bounds ([`NavGridSettings::bounds`](super::nav::NavGridSettings) `None`),
    /// the grid spans the base shapes plus `padding`, so a robot that starts farther than the
    /// padding from every base shape would be off the map. For every point outside the grid,
    /// the copy's explicit bounds are the grid's extent grown to the point plus `padding` on
    /// every side (the same margin the automatic bounds give the shapes); its cells are
    /// aligned with this grid's, so every cell this grid has keeps its occupancy. A model
    /// whose grid already covers every point, or whose bounds the user set explicitly, is
    /// returned as is (a point off explicit bounds stays the caller's input error).
    /// Non-finite points are left to the caller's checks.
    ///
    /// # Errors
    /// [`Error::GridTooLarge`] when the grown grid would exceed
    /// [`MAX_GRID_CELLS`](super::nav::MAX_GRID_CELLS).
    pub fn covering(
        &self,
        points: &[nalgebra::Point2<f64>],
    ) -> Result<std::borrow::Cow<'_, SceneModel>, Error> {
        let g = &self.base_grid;
        let off: Vec<_> = points
            .iter()
            .filter(|p| p.x.is_finite() && p.y.is_finite() && g.cell_of(**p).is_none())
            .collect();
        if off.is_empty() || self.base.nav.bounds.is_some() {
            return Ok(std::borrow::Cow::Borrowed(self));
        }
        let (o, r) = (g.origin(), g.resolution());
        let (mut lo, mut hi) = (
            o,
            nalgebra::Point2::new(o.x + r * g.width() as f64, o.y + r * g.height() as f64),
        );
        let pad = self.base.nav.padding;
        for p in off {
            lo = nalgebra::Point2::new(lo.x.min(p.x - pad), lo.y.min(p.y - pad));
            hi = nalgebra::Point2::new(hi.x.max(p.x + pad), hi.y.max(p.y + pad));
        }
        // Keep the cells aligned: move the lower corner down by whole cells.
        let min = nalgebra::Point2::new(
            o.x - ((o.x - lo.x) / r).ceil() * r,
            o.y - ((o.y - lo.y) / r).ceil() * r,
        );
        let mut builder = self.to_builder();
        let mut nav = self.base.nav;
        nav.bounds = Some(super::nav::GridBounds { min, max: hi });
        builder.nav_settings(nav);
        Ok(std::borrow::Cow::Owned(builder.build()?))
    }
    /// The description this model was built from, in id order (parents before children).
    /// `to_builder().build()` gives an equal model.
    pub fn to_builder(&self) -> SceneModelBuilder {
        let parts = self
            .parts
            .iter()
            .map(|p| PartSpec {
                name: p.name.clone(),
                parent: match p.parent {
                    Parent::Base => None,
                    Parent::Part(id) => Some(self.parts[id.0].name.clone()),
                },
                joint: self.joints[p.id.0].clone(),
                colliders: p.colliders.clone(),
                handles: p.handles.clone(),
            })
            .collect();
        SceneModelBuilder {
            base: self.base.clone(),
            parts,
        }
    }

    /// The joint with this id, or [`Error::UnknownId`].
    pub(crate) fn checked_joint(&self, id: JointId) -> Result<&Joint, Error> {
        self.joints.get(id.0).ok_or(Error::UnknownId {
            kind: ElementKind::Joint,
            index: id.0,
        })
    }

    /// The part with this id, or [`Error::UnknownId`].
    pub(crate) fn checked_part(&self, id: PartId) -> Result<&Part, Error> {
        self.parts.get(id.0).ok_or(Error::UnknownId {
            kind: ElementKind::Part,
            index: id.0,
        })
    }

    /// The handle with this id, or [`Error::UnknownId`].
    pub(crate) fn checked_handle(&self, id: HandleId) -> Result<&Handle, Error> {
        self.handle(id).ok_or(Error::UnknownId {
            kind: ElementKind::Handle,
            index: id.index,
        })
    }
}

impl From<SceneModel> for SceneModelBuilder {
    fn from(model: SceneModel) -> Self {
        model.to_builder()
    }
}

impl TryFrom<SceneModelBuilder> for SceneModel {
    type Error = Error;
    fn try_from(builder: SceneModelBuilder) -> Result<Self, Error> {
        builder.build()
    }
}
