//! Forward kinematics of the scene tree: `world_from_part` for every part at a state Θ.

use nalgebra::{Isometry3, Point3, Unit, Vector3};

use super::Error;
use super::ids::{HandleId, JointId, Parent, PartId};
use super::joint::JointKind;
use super::model::SceneModel;
use super::state::State;

/// Scratch data for scene algorithms, owned by the caller (Model/Data split).
///
/// Holds the poses computed by the last [`forward_kinematics`] call. Create one per model
/// (and per thread) with [`SceneData::new`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneData {
    world_from_joint: Vec<Isometry3<f64>>,
    world_from_part: Vec<Isometry3<f64>>,
}

impl SceneData {
    /// Data sized for `model`, with every pose at the identity until the first
    /// [`forward_kinematics`].
    pub fn new(model: &SceneModel) -> Self {
        SceneData {
            world_from_joint: vec![Isometry3::identity(); model.nq()],
            world_from_part: vec![Isometry3::identity(); model.nq()],
        }
    }

    /// Pose of a part frame in the world, `None` for an id out of range.
    pub fn world_from_part(&self, id: PartId) -> Option<&Isometry3<f64>> {
        self.world_from_part.get(id.0)
    }

    /// Pose of a joint frame in the world (the frame the joint moves in, independent of the
    /// joint's own value), `None` for an id out of range.
    pub fn world_from_joint(&self, id: JointId) -> Option<&Isometry3<f64>> {
        self.world_from_joint.get(id.0)
    }

    /// All part poses, indexed by [`PartId::index`].
    pub fn world_from_parts(&self) -> &[Isometry3<f64>] {
        &self.world_from_part
    }

    /// Fails with [`Error::DimensionMismatch`] if the data is not sized for `model`.
    pub(crate) fn check(&self, model: &SceneModel) -> Result<(), Error> {
        if self.world_from_part.len() == model.nq() {
            Ok(())
        } else {
            Err(Error::DimensionMismatch {
                what: "scene data".into(),
                expected: model.nq(),
                got: self.world_from_part.len(),
            })
        }
    }
}

/// Computes every part pose at `state` into `data`:
/// `world_from_part(child) = world_from_part(parent) · parent_from_joint · joint_from_child(θ)`
/// with `world_from_part(base) = identity`. One pass in id order (parents come first).
///
/// `data` is resized if it was made for another model. Values are not checked against limits
/// (a state built through [`State`]'s checked API already is), only for finiteness.
///
/// # Errors
/// [`Error::DimensionMismatch`] if the state does not have `model.nq()` values;
/// [`Error::NonFinite`] if a value is NaN or infinite.
pub fn forward_kinematics(
    model: &SceneModel,
    data: &mut SceneData,
    state: &State,
) -> Result<(), Error> {
    state.check_len(model)?;
    if let Some(k) = state.q.iter().position(|v| !v.is_finite()) {
        return Err(Error::NonFinite {
            what: format!("value of joint {:?}", model.joints[k].name),
        });
    }
    if data.check(model).is_err() {
        *data = SceneData::new(model);
    }
    for (k, part) in model.parts.iter().enumerate() {
        let joint = &model.joints[k];
        let world_from_parent = match part.parent {
            Parent::Base => Isometry3::identity(),
            Parent::Part(p) => data.world_from_part[p.0],
        };
        let world_from_joint = world_from_parent * joint.parent_from_joint;
        data.world_from_joint[k] = world_from_joint;
        data.world_from_part[k] = world_from_joint * joint.joint_from_child(state.q[k]);
    }
    Ok(())
}

impl SceneModel {
    /// Convenience: every part pose at `state`, indexed by [`PartId::index`].
    ///
    /// # Errors
    /// As [`forward_kinematics`].
    pub fn world_from_parts(&self, state: &State) -> Result<Vec<Isometry3<f64>>, Error> {
        let mut data = SceneData::new(self);
        forward_kinematics(self, &mut data, state)?;
        Ok(data.world_from_part)
    }
}

/// A handle in the world: grasp point and unit outward normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandlePose {
    /// Grasp point `p` (m), world frame.
    pub position: Point3<f64>,
    /// Outward surface normal, world frame.
    pub normal: Unit<Vector3<f64>>,
}

/// The world pose of a handle at the state of the last [`forward_kinematics`].
///
/// # Errors
/// [`Error::UnknownId`] for a foreign id; [`Error::DimensionMismatch`] if `data` is not sized
/// for `model`.
pub fn world_from_handle(
    model: &SceneModel,
    data: &SceneData,
    handle: HandleId,
) -> Result<HandlePose, Error> {
    data.check(model)?;
    let h = model.checked_handle(handle)?;
    let world_from_part = &data.world_from_part[handle.part.0];
    Ok(HandlePose {
        position: world_from_part * h.position,
        normal: Unit::new_normalize(world_from_part * h.normal),
    })
}

/// A joint's axis in the world at some state: the paper's unit direction `u` and pivot `q`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointAxis {
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// A point on the axis (m): the joint-frame origin. For a revolute joint this is `q`.
    pub pivot: Point3<f64>,
    /// Unit direction `u` of the axis, world frame.
    pub direction: Unit<Vector3<f64>>,
}

/// The world axis of `joint` at the state of the last [`forward_kinematics`]. It depends on
/// the values of the joint's ancestors only, not on its own value.
///
/// # Errors
/// [`Error::UnknownId`] for a foreign id; [`Error::DimensionMismatch`] if `data` is not sized
/// for `model`.
pub fn joint_axis(
    model: &SceneModel,
    data: &SceneData,
    joint: JointId,
) -> Result<JointAxis, Error> {
    data.check(model)?;
    let j = model.checked_joint(joint)?;
    let world_from_joint = &data.world_from_joint[joint.0];
    Ok(JointAxis {
        kind: j.kind,
        pivot: Point3::from(world_from_joint.translation.vector),
        direction: Unit::new_normalize(world_from_joint * j.axis),
    })
}
