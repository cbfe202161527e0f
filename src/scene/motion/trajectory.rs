//! The grasp-point trajectory of a one-joint motion (the paper's Eq. (3)–(5)).

use crate::InvalidSetting;
use crate::scene::kinematics::{HandlePose, forward_kinematics, joint_axis, world_from_handle};
use crate::scene::{Error, HandleId, JointId, SceneData, SceneModel, State};
use nalgebra::Unit;

/// Largest number of steps `K` [`grasp_trajectory`] accepts.
pub const MAX_TRAJECTORY_STEPS: usize = 1_000_000;

/// Checks `value` is finite and within the joint's limits.
pub(crate) fn check_joint_value(
    model: &SceneModel,
    joint: JointId,
    value: f64,
) -> Result<(), Error> {
    let j = model.checked_joint(joint)?;
    if !value.is_finite() {
        return Err(Error::NonFinite {
            what: format!("motion endpoint of joint {:?}", j.name),
        });
    }
    if !j.limits.contains(value) {
        return Err(Error::JointLimit {
            joint: j.name.clone(),
            value,
            min: j.limits.lower,
            max: j.limits.upper,
        });
    }
    Ok(())
}

/// The `K + 1` poses of a handle while `joint` goes from `a` to `b` in `k` equal steps, all
/// other joints at their values in `state`.
///
/// With `p`, `n` the handle's world point and normal at value `a`, `u` the joint's world
/// axis and `q` its pivot, step `i ∈ [0, K]` has `φᵢ = (i/K)(b − a)` and
/// - revolute (Eq. (3)–(4)): `pᵢ = R(φᵢ)(p − q) + q`, `nᵢ = R(φᵢ) n`;
/// - prismatic (Eq. (5)): `pᵢ = p + φᵢ u`, `nᵢ = n`.
///
/// The handle may sit on the joint's part or on any descendant: the whole subtree moves
/// rigidly with the joint, so the same formulas apply. The first and last poses equal the
/// forward kinematics of the handle at `a` and `b`. On return `data` holds the forward
/// kinematics of `state` with the joint at `a`.
///
/// # Errors
/// [`Error::UnknownId`] for foreign ids; [`Error::DimensionMismatch`] for a state not sized
/// for the model; [`Error::NonFinite`] / [`Error::JointLimit`] if `a` or `b` is not a valid
/// value of the joint; [`Error::NotInSubtree`] if the handle does not move with the joint;
/// [`Error::InvalidSetting`] if `k == 0` or `k >` [`MAX_TRAJECTORY_STEPS`].
#[allow(clippy::too_many_arguments)]
pub fn grasp_trajectory(
    model: &SceneModel,
    data: &mut SceneData,
    state: &State,
    handle: HandleId,
    joint: JointId,
    a: f64,
    b: f64,
    k: usize,
) -> Result<Vec<HandlePose>, Error> {
    state.check_len(model)?;
    let h = model.checked_handle(handle)?;
    let j = model.checked_joint(joint)?;
    if !model.parts[joint.0].subtree_contains(handle.part) {
        return Err(Error::NotInSubtree {
            handle: h.name.clone(),
            joint: j.name.clone(),
        });
    }
    check_joint_value(model, joint, a)?;
    check_joint_value(model, joint, b)?;
    if k == 0 || k > MAX_TRAJECTORY_STEPS {
        return Err(InvalidSetting::new(
            "trajectory steps K",
            k as f64,
            format!("between 1 and {MAX_TRAJECTORY_STEPS}"),
        )
        .into());
    }
    let mut start = state.clone();
    start.q[joint.0] = a;
    forward_kinematics(model, data, &start)?;
    let p = world_from_handle(model, data, handle)?;
    let axis = joint_axis(model, data, joint)?;
    Ok((0..=k)
        .map(|i| {
            let phi = (i as f64 / k as f64) * (b - a);
            HandlePose {
                position: axis.move_point(&p.position, phi),
                normal: Unit::new_normalize(axis.move_vector(&p.normal, phi)),
            }
        })
        .collect())
}
