//! The joint motion a placement plans for: the grasp frames along the handle trajectory, along
//! the handle's normal or turned about its bar, stopped short of the front, with the straight
//! approach and retreat.

use nalgebra::{Unit, UnitQuaternion, Vector3};

use super::{JointMotion, PlacementError, PlacementProblem, PlacementSettings};
use crate::scene::collision::{handle_bar_axis, handle_standoff_along};
use crate::scene::{HandleId, JointId};

/// The joint motion [`place_and_plan`](super::place_and_plan) plans for: `joint` from its value in `problem.state`
/// to `to` in `settings.steps` steps by `handle`
/// ([`JointMotion::new`]), the grasp points moved out by [`grasp_standoff`] (with
/// `settings.manipulation.finger_clearance`, [`JointMotion::with_standoff`]), with the straight
/// approach and retreat of `settings` ([`JointMotion::with_approach`]). With
/// [`plan_manipulation`](super::plan_manipulation) it evaluates one given base pose exactly as the sampler evaluates
/// each of its candidates.
///
/// # Errors
/// As [`JointMotion::new`] and [`grasp_standoff`].
pub fn placement_motion(
    problem: PlacementProblem<'_>,
    joint: JointId,
    handle: HandleId,
    to: f64,
    settings: &PlacementSettings,
) -> Result<JointMotion, PlacementError> {
    placement_motion_turned(problem, joint, handle, to, settings, 0.0)
}

/// [`placement_motion`] with the grasp turned by `angle` (rad) about the handle's bar axis
/// ([`handle_bar_axis`], [`JointMotion::turned_about_bar`]): the stand-off measured along the
/// turned direction ([`grasp_standoff_along`]) and the straight approach and retreat along
/// it. `angle = 0` is [`placement_motion`].
///
/// # Errors
/// As [`placement_motion`]; [`PlacementError::InvalidSetting`] (`bar_turn`) for a non-zero
/// angle when the handle is not a bar.
pub fn placement_motion_turned(
    problem: PlacementProblem<'_>,
    joint: JointId,
    handle: HandleId,
    to: f64,
    settings: &PlacementSettings,
    angle: f64,
) -> Result<JointMotion, PlacementError> {
    let motion = JointMotion::new(
        problem.model,
        problem.state,
        joint,
        handle,
        to,
        settings.steps,
    )?;
    let normal = problem.model.checked_handle(handle)?.normal.normalize();
    let (motion, inward) = if angle == 0.0 {
        (motion, Unit::new_normalize(-normal))
    } else {
        let Some(bar) = handle_bar_axis(problem.model, handle)? else {
            return Err(crate::InvalidSetting::new(
                "bar_turn",
                angle,
                "0 for a handle that is not a bar",
            )
            .into());
        };
        let turn = UnitQuaternion::from_axis_angle(&bar, angle);
        let motion = motion.turned_about_bar(problem.model, problem.state, &bar, angle)?;
        (motion, turn * Unit::new_normalize(-normal))
    };
    let clearance = settings.manipulation.finger_clearance;
    Ok(motion
        .with_standoff(grasp_standoff_along(&problem, handle, &inward, clearance)?)
        .with_approach(settings.approach_distance, settings.approach_steps))
}

/// How far the tool stops short of `handle`'s grasp point (m, out along the normal): what the
/// gripper's fingertips ([`RobotCollision::fingertip_reach`](crate::kinematics::robot::RobotCollision::fingertip_reach)) plus `clearance` reach past the
/// handle's standoff from its part's front; 0 for a robot without contact geometry or a
/// handle with no front behind it.
///
/// # Errors
/// [`PlacementError::Scene`] for a foreign handle id.
pub fn grasp_standoff(
    problem: &PlacementProblem<'_>,
    handle: HandleId,
    clearance: f64,
) -> Result<f64, PlacementError> {
    let normal = problem.model.checked_handle(handle)?.normal;
    grasp_standoff_along(problem, handle, &Unit::new_normalize(-normal), clearance)
}

/// [`grasp_standoff`] for a grasp along `inward` (unit, the handle's part frame) turned by an
/// angle `φ` from the inward normal, the fingers beside each other along the bar (tool x, see
/// [`JointMotion::turned_about_bar`]): how far the tool stops short of the grasp point along
/// that direction. The fingertips reach `t` past the tool along it and `w` to either side of
/// the tool's x-z plane
/// ([`RobotCollision::fingertip_side_reach`](crate::kinematics::robot::RobotCollision::fingertip_side_reach)),
/// one side tilted towards the front by `φ`: against a flat front, a tool `d` short of the
/// grasp point keeps the fingertips clear when `d >= t + w·tan φ + clearance − f`, with `f`
/// the front's distance along `inward` ([`handle_standoff_along`]). For `φ = 0` this is
/// [`grasp_standoff`].
///
/// # Errors
/// [`PlacementError::Scene`] for a foreign handle id.
pub fn grasp_standoff_along(
    problem: &PlacementProblem<'_>,
    handle: HandleId,
    inward: &Unit<Vector3<f64>>,
    clearance: f64,
) -> Result<f64, PlacementError> {
    let Some(tip) = problem.collision.fingertip_reach(problem.robot) else {
        return Ok(0.0);
    };
    let normal = problem.model.checked_handle(handle)?.normal.normalize();
    let cos = (-inward.dot(&normal)).clamp(0.0, 1.0);
    let side = if cos < 1.0 {
        let w = problem.collision.fingertip_side_reach(problem.robot);
        w.unwrap_or(0.0).max(0.0) * (1.0 - cos * cos).sqrt() / cos.max(1e-9)
    } else {
        0.0
    };
    let need = tip.max(0.0) + side + clearance;
    Ok(handle_standoff_along(problem.model, handle, inward, need)?
        .map_or(0.0, |front| (need - front).max(0.0)))
}
