//! The motion bound: how far any point of a moving subtree can travel for a value change.
//!
//! **Claim.** Let joint `j` move from value `θ` to `θ'` with every other joint fixed, and let
//! `x` be any point of the geometry (colliders) or any handle point of `j`'s part or of one of
//! its descendants. Then `‖x(θ') − x(θ)‖ ≤ L·|θ' − θ|` where `L = r` for a revolute joint,
//! `r` = [`sweep_radius`], and `L = 1` for a prismatic joint.
//!
//! **Proof sketch.** The subtree moves rigidly by the world motion
//! [`JointAxis::displacement`](crate::scene::JointAxis::displacement). Prismatic: every point
//! moves by `(θ' − θ)·u` with `‖u‖ = 1`. Revolute: a point at distance `ρ` from the axis moves
//! on a circle of radius `ρ` about it; the chord is `2ρ·sin(|Δφ|/2) ≤ ρ·|Δφ|` (chord ≤ arc).
//! Every point of a collider lies in the collider's bounding sphere (centre `c`, radius `s`),
//! so `ρ ≤ dist(c, axis) + s ≤ r`. Rotation about the axis preserves distances to it, so `r`
//! computed at one value of `j` holds for all its values (with the other joints fixed).
//! Consequently the distance between the moving subtree and any fixed set is `L`-Lipschitz in
//! the joint value — the fact the sampled collision check relies on.

use crate::scene::kinematics::{forward_kinematics, joint_axis};
use crate::scene::motion::trajectory::check_joint_value;
use crate::scene::{Error, JointId, JointKind, SceneData, SceneModel, State};

/// The motion bound of one joint at fixed values of the others.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionBound {
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// [`sweep_radius`] (m): an upper bound on the distance from the joint axis of every
    /// point of the moving subtree.
    pub radius: f64,
}

impl MotionBound {
    /// The Lipschitz constant `L`: metres of point travel per radian (revolute, `= radius`)
    /// or per metre (prismatic, `= 1`) of joint motion.
    pub fn lipschitz(&self) -> f64 {
        match self.kind {
            JointKind::Revolute => self.radius,
            JointKind::Prismatic => 1.0,
        }
    }

    /// Upper bound (m) on the travel of any point of the moving subtree for a joint value
    /// change of `delta` (rad or m): `L·|delta|`.
    pub fn max_displacement(&self, delta: f64) -> f64 {
        self.lipschitz() * delta.abs()
    }
}

/// An upper bound (m) on the distance from `joint`'s axis of every point of the geometry and
/// every handle of the joint's part and its descendants, at the state of the last
/// [`forward_kinematics`] (other joints at those values; the joint's own value does not
/// matter). Computed from the colliders' bounding spheres: `max(dist(centre, axis) + radius)`,
/// so it is an upper bound, not the exact maximum.
///
/// # Errors
/// [`Error::UnknownId`] for a foreign id; [`Error::DimensionMismatch`] if `data` is not sized
/// for `model`.
pub fn sweep_radius(model: &SceneModel, data: &SceneData, joint: JointId) -> Result<f64, Error> {
    let axis = joint_axis(model, data, joint)?;
    let mut r: f64 = 0.0;
    for part in model.parts[joint.0].subtree() {
        let world_from_part = data.world_from_parts()[part.0];
        for c in &model.geometry.parts[part.0] {
            let centre = c.world_center(&world_from_part);
            r = r.max(axis.distance_to_axis(&centre) + c.sphere.radius);
        }
        for h in &model.parts[part.0].handles {
            r = r.max(axis.distance_to_axis(&(world_from_part * h.position)));
        }
    }
    Ok(r)
}

/// The [`MotionBound`] of `joint` at the state of the last [`forward_kinematics`].
///
/// # Errors
/// As [`sweep_radius`].
pub fn motion_bound(
    model: &SceneModel,
    data: &SceneData,
    joint: JointId,
) -> Result<MotionBound, Error> {
    Ok(MotionBound {
        kind: model.checked_joint(joint)?.kind,
        radius: sweep_radius(model, data, joint)?,
    })
}

/// Upper bound (m) on how far any point of the moving subtree travels when `joint` goes from
/// `a` to `b` with the other joints at their values in `state` (and between any two values in
/// `[a, b]`, scaled by their distance). Leaves `data` at the forward kinematics of `state`.
///
/// # Errors
/// [`Error::UnknownId`], [`Error::DimensionMismatch`], and [`Error::NonFinite`] /
/// [`Error::JointLimit`] if `a` or `b` is not a valid value of the joint.
pub fn max_displacement(
    model: &SceneModel,
    data: &mut SceneData,
    state: &State,
    joint: JointId,
    a: f64,
    b: f64,
) -> Result<f64, Error> {
    check_joint_value(model, joint, a)?;
    check_joint_value(model, joint, b)?;
    forward_kinematics(model, data, state)?;
    Ok(motion_bound(model, data, joint)?.max_displacement(b - a))
}
