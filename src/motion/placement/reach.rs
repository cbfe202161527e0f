//! A bound on how far the arm reaches: the shoulder and the arm's length.

use nalgebra::Point3;

use crate::kinematics::robot::{ArmJointKind, RobotModel};

/// A bound on where the arm can put the tool: the origin of the first arm joint (in the base
/// frame) and the arm's length from it — the sum of the link offsets after it and of the tool
/// offset, plus the stroke of prismatic joints. Rotations about axes through a joint origin
/// keep distances from it, so by the triangle inequality no configuration puts the tool
/// farther than `length` from `base_from_shoulder`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmReach {
    /// The first arm joint's origin in the base frame (m).
    pub base_from_shoulder: Point3<f64>,
    /// The length bound (m).
    pub length: f64,
}

/// The reach bound of `robot`'s arm (see [`ArmReach`]).
pub fn arm_reach(robot: &RobotModel) -> ArmReach {
    let joints = robot.arm_joints();
    let shoulder = joints.first().map_or(*robot.base_from_arm_root(), |j| {
        robot.base_from_arm_root() * j.parent_from_joint
    });
    let links: f64 = joints
        .iter()
        .skip(1)
        .map(|j| j.parent_from_joint.translation.vector.norm())
        .sum();
    let strokes: f64 = joints
        .iter()
        .filter(|j| j.kind == ArmJointKind::Prismatic)
        .map(|j| j.lower.abs().max(j.upper.abs()))
        .sum();
    ArmReach {
        base_from_shoulder: Point3::from(shoulder.translation.vector),
        length: links + strokes + robot.last_from_tool().translation.vector.norm(),
    }
}
