//! The tool frame's rotation in the tool link: +z onto the configured approach axis.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use crate::kinematics::robot::{RobotError, RobotImportOptions};

/// The tool frame in the tool link's frame: a rotation taking +z onto
/// [`RobotImportOptions::tool_approach`] (the identity without one).
pub(super) fn approach_rotation(
    options: &RobotImportOptions,
) -> Result<Isometry3<f64>, RobotError> {
    let Some(axis) = options.tool_approach else {
        return Ok(Isometry3::identity());
    };
    let invalid = || RobotError::InvalidToolApproach { axis };
    let axis = Vector3::from(axis);
    if !axis.iter().all(|c| c.is_finite()) {
        return Err(invalid());
    }
    let axis = axis.try_normalize(1e-12).ok_or_else(invalid)?;
    // rotation_between has no unique answer for the opposite direction: a half turn about x.
    let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &axis).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    Ok(Isometry3::from_parts(Translation3::identity(), rotation))
}
