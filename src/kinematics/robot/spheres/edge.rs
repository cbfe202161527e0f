//! The scene the arm check takes ([`EdgeScene`]) and the check of its inputs.

use super::RobotSpheres;
use crate::kinematics::robot::{Exempt, RobotError, RobotModel};
use crate::scene::{SceneData, SceneModel};

/// The scene an [`ArmCheck`](super::ArmCheck) checks against, as
/// [`RobotCollision::scene_collision`](crate::kinematics::robot::RobotCollision::scene_collision)
/// takes it.
#[derive(Debug, Clone, Copy)]
pub struct EdgeScene<'a> {
    /// The scene model.
    pub model: &'a SceneModel,
    /// Its part poses ([`crate::scene::forward_kinematics`] of `model`).
    pub data: &'a SceneData,
    /// Which bodies some robot shapes may touch.
    pub exempt: Exempt<'a>,
    /// Clearance (m) required from the scene; negative or NaN counts as 0.
    pub margin: f64,
}

/// The number of `robot`'s links, after checking that `spheres` covers as many and that `base`
/// is finite (the inputs of the arm check).
pub(super) fn check_inputs(
    robot: &RobotModel,
    spheres: &RobotSpheres,
    base: [f64; 3],
) -> Result<usize, RobotError> {
    let links = robot.links().len();
    if spheres.links().len() != links {
        return Err(RobotError::DimensionMismatch {
            what: "sphere model links",
            expected: links,
            got: spheres.links().len(),
        });
    }
    if let Some(index) = base.iter().position(|v| !v.is_finite()) {
        return Err(RobotError::NonFiniteValue {
            what: "base",
            index,
        });
    }
    Ok(links)
}
