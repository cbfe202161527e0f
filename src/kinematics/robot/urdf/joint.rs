//! URDF joints and origins as the robot's arm joints and poses.

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use urdf_rs::JointType;

use crate::kinematics::robot::model::check_positive_limit;
use crate::kinematics::robot::{
    ArmJoint, ArmJointKind, DEFAULT_PRISMATIC_ACCELERATION, DEFAULT_REVOLUTE_ACCELERATION,
    RobotError,
};

pub(super) fn is_movable(kind: &JointType) -> bool {
    matches!(
        kind,
        JointType::Revolute | JointType::Continuous | JointType::Prismatic
    )
}

/// An actuated joint from its URDF element (`parent_from_joint` = the given origin). The
/// velocity and acceleration limits are checked only if `actuated` (not for frozen gripper
/// joints, which only need an axis and limits).
pub(super) fn arm_joint(
    joint: &urdf_rs::Joint,
    origin: Isometry3<f64>,
    actuated: bool,
) -> Result<ArmJoint, RobotError> {
    let name = &joint.name;
    let axis = Vector3::from(*joint.axis.xyz);
    let invalid_axis = || RobotError::InvalidAxis {
        joint: name.clone(),
        axis: *joint.axis.xyz,
    };
    if !axis.iter().all(|c| c.is_finite()) {
        return Err(invalid_axis());
    }
    let axis = Unit::try_new(axis, 1e-12).ok_or_else(invalid_axis)?;
    let limit = &joint.limit;
    let (kind, lower, upper, default_acceleration) = match joint.joint_type {
        JointType::Continuous => (
            ArmJointKind::Continuous,
            f64::NEG_INFINITY,
            f64::INFINITY,
            DEFAULT_REVOLUTE_ACCELERATION,
        ),
        JointType::Prismatic => (
            ArmJointKind::Prismatic,
            limit.lower,
            limit.upper,
            DEFAULT_PRISMATIC_ACCELERATION,
        ),
        _ => (
            ArmJointKind::Revolute,
            limit.lower,
            limit.upper,
            DEFAULT_REVOLUTE_ACCELERATION,
        ),
    };
    if lower.is_nan() || upper.is_nan() || lower > upper {
        return Err(RobotError::InvalidLimits {
            joint: name.clone(),
            lower,
            upper,
        });
    }
    if actuated {
        check_positive_limit(name, "velocity", limit.velocity)?;
    }
    // URDF 1.2 acceleration limits; absent ones read as +∞ and take the default.
    let max_acceleration = if limit.acceleration == f64::INFINITY || !actuated {
        default_acceleration
    } else {
        check_positive_limit(name, "acceleration", limit.acceleration)?;
        limit.acceleration
    };
    Ok(ArmJoint {
        name: name.clone(),
        kind,
        parent_from_joint: origin,
        axis,
        lower,
        upper,
        max_velocity: limit.velocity,
        max_acceleration,
    })
}

/// A URDF `<origin xyz rpy>` as `parent_from_child`, rpy fixed-axis `Rz(y)·Ry(p)·Rx(r)`.
pub(super) fn origin(
    pose: &urdf_rs::Pose,
    what: impl Fn() -> String,
) -> Result<Isometry3<f64>, RobotError> {
    if !pose
        .xyz
        .iter()
        .chain(pose.rpy.iter())
        .all(|c| c.is_finite())
    {
        return Err(RobotError::NonFinite { what: what() });
    }
    Ok(Isometry3::from_parts(
        Translation3::new(pose.xyz[0], pose.xyz[1], pose.xyz[2]),
        UnitQuaternion::from_euler_angles(pose.rpy[0], pose.rpy[1], pose.rpy[2]),
    ))
}
