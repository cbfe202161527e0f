//! The arm as a Pinocchio model, built with `ModelBuilder` from the parsed robot.

use kinscene_pinocchio::{FrameIndex, JointIndex, JointKind, JointLimits, Model, ModelBuilder};
use nalgebra::Isometry3;

use super::{ArmJoint, ArmJointKind, RobotError};

/// Name of the tool frame in the Pinocchio model.
pub const TOOL_FRAME: &str = "tool";

/// Builds the arm model (see [`super::RobotModel::pinocchio`]) and returns it with the tool
/// frame's index.
pub(super) fn build(
    joints: &[ArmJoint],
    base_from_arm_root: &Isometry3<f64>,
    last_from_tool: &Isometry3<f64>,
) -> Result<(Model, FrameIndex), RobotError> {
    let mut builder = ModelBuilder::new();
    let mut parent = JointIndex::UNIVERSE;
    for (i, joint) in joints.iter().enumerate() {
        let axis = joint.axis.into_inner();
        let (kind, limits) = match joint.kind {
            ArmJointKind::Revolute => (
                JointKind::Revolute { axis },
                JointLimits::position(joint.lower, joint.upper),
            ),
            // A plain revolute joint without position limits: q stays the angle (nq = 1).
            ArmJointKind::Continuous => (JointKind::Revolute { axis }, JointLimits::NONE),
            ArmJointKind::Prismatic => (
                JointKind::Prismatic { axis },
                JointLimits::position(joint.lower, joint.upper),
            ),
        };
        let placement = if i == 0 {
            base_from_arm_root * joint.parent_from_joint
        } else {
            joint.parent_from_joint
        };
        parent = builder.add_joint(
            &joint.name,
            parent,
            placement,
            kind,
            limits.with_velocity(joint.max_velocity),
        )?;
    }
    let tool = builder.add_frame(TOOL_FRAME, parent, *last_from_tool)?;
    Ok((builder.build()?, tool))
}
