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
    let parent = add_arm(
        &mut builder,
        JointIndex::UNIVERSE,
        joints,
        base_from_arm_root,
    )?;
    let tool = builder.add_frame(TOOL_FRAME, parent, *last_from_tool)?;
    Ok((builder.build()?, tool))
}

/// Adds the arm's joints to `builder` as a chain below `root` (the first one placed by
/// `base_from_arm_root` in `root`'s frame); returns the last joint.
fn add_arm(
    builder: &mut ModelBuilder,
    root: JointIndex,
    joints: &[ArmJoint],
    base_from_arm_root: &Isometry3<f64>,
) -> Result<JointIndex, RobotError> {
    let mut parent = root;
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
    Ok(parent)
}

impl super::RobotModel {
    /// Adds this robot's arm to a Pinocchio model under construction, as a chain below `root`
    /// placed as the base places the arm (for models that put more joints, such as a moving
    /// base, above the arm); returns the arm's last joint.
    ///
    /// # Errors
    /// [`RobotError`] if Pinocchio refuses a joint.
    pub(crate) fn add_arm_to(
        &self,
        builder: &mut ModelBuilder,
        root: JointIndex,
    ) -> Result<JointIndex, RobotError> {
        add_arm(builder, root, self.arm_joints(), self.base_from_arm_root())
    }
}
