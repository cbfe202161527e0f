//! The whole-body IK model: the base's planar displacement from the previous waypoint's base
//! pose as joints in front of the arm, and the conversion between its configuration and a
//! (base pose, arm configuration) pair.

use kinscene_pinocchio::{FrameIndex, JointIndex, JointKind, JointLimits, Model, ModelBuilder};
use nalgebra::{DVector, Isometry3, Vector3};

use super::WholeBodySettings;
use crate::kinematics::ik::{IkSettings, IkSolver};
use crate::kinematics::robot::{BaseKind, RobotModel};
use crate::motion::placement::PlacementError;

/// The robot with its base displacement as joints: for a holonomic base a prismatic joint
/// along the previous base frame's x, one along its y and a revolute joint about z (3 base
/// coordinates); for a differential-drive base the prismatic joint along x and the revolute
/// one only (2: no sideways motion). The root frame is the previous waypoint's base frame, so
/// one model serves every waypoint; the base joints' limits are
/// [`WholeBodySettings::max_base_step`] and [`WholeBodySettings::max_yaw_step`].
#[derive(Debug)]
pub(super) struct WholeBodyIk {
    pub solver: IkSolver,
    /// Number of base coordinates in front of the arm's (3 or 2).
    pub base_dofs: usize,
}

impl WholeBodyIk {
    pub(super) fn new(
        robot: &RobotModel,
        settings: &WholeBodySettings,
        ik: &IkSettings,
    ) -> Result<WholeBodyIk, PlacementError> {
        let (model, tool, base_dofs) = build(robot, settings)?;
        Ok(WholeBodyIk {
            solver: IkSolver::new(&model, tool, ik.clone())?,
            base_dofs,
        })
    }

    /// The model's configuration for the base staying where it is and the arm at `arm`.
    pub(super) fn seed(&self, arm: &DVector<f64>) -> DVector<f64> {
        let mut q = DVector::zeros(self.base_dofs + arm.len());
        q.rows_mut(self.base_dofs, arm.len()).copy_from(arm);
        q
    }

    /// The base pose and arm configuration of the model's configuration `q` with the root at
    /// the base pose `from`.
    pub(super) fn split(&self, from: [f64; 3], q: &DVector<f64>) -> ([f64; 3], DVector<f64>) {
        let (dx, dy, dyaw) = match self.base_dofs {
            3 => (q[0], q[1], q[2]),
            _ => (q[0], 0.0, q[1]),
        };
        let (s, c) = from[2].sin_cos();
        let base = [
            from[0] + c * dx - s * dy,
            from[1] + s * dx + c * dy,
            from[2] + dyaw,
        ];
        let arm = q
            .rows(self.base_dofs, q.len() - self.base_dofs)
            .into_owned();
        (base, arm)
    }
}

/// The whole-body Pinocchio model, its tool frame and the number of base coordinates.
fn build(
    robot: &RobotModel,
    settings: &WholeBodySettings,
) -> Result<(Model, FrameIndex, usize), PlacementError> {
    let mut b = ModelBuilder::new();
    let step = settings.max_base_step;
    let translation = JointLimits::position(-step, step);
    let mut parent = b.add_joint(
        "whole_body_forward",
        JointIndex::UNIVERSE,
        Isometry3::identity(),
        JointKind::Prismatic { axis: Vector3::x() },
        translation,
    )?;
    let base_dofs = match robot.base().kind {
        BaseKind::DifferentialDrive => 2,
        _ => {
            parent = b.add_joint(
                "whole_body_sideways",
                parent,
                Isometry3::identity(),
                JointKind::Prismatic { axis: Vector3::y() },
                translation,
            )?;
            3
        }
    };
    parent = b.add_joint(
        "whole_body_yaw",
        parent,
        Isometry3::identity(),
        JointKind::Revolute { axis: Vector3::z() },
        JointLimits::position(-settings.max_yaw_step, settings.max_yaw_step),
    )?;
    parent = robot.add_arm_to(&mut b, parent)?;
    let tool = b.add_frame("tool", parent, *robot.last_from_tool())?;
    Ok((b.build()?, tool, base_dofs))
}
