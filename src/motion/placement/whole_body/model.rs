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
/// [`WholeBodySettings::max_base_step`] and [`WholeBodySettings::max_yaw_step`], or one side
/// of them ([`WholeBodyIk::solver`]): the IK knows no collisions, so a base step that meets
/// the scene is solved again with the base kept from going that way.
#[derive(Debug)]
pub(super) struct WholeBodyIk {
    /// Number of base coordinates in front of the arm's (3 or 2).
    pub base_dofs: usize,
    /// The step bound of each base coordinate (m or rad).
    pub step_bounds: Vec<f64>,
}

/// Which side of 0 a base coordinate may take in a whole-body IK model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Side {
    /// Either, within the step bound.
    Both,
    /// `>= 0` only.
    Positive,
    /// `<= 0` only.
    Negative,
}

impl WholeBodyIk {
    pub(super) fn new(robot: &RobotModel, settings: &WholeBodySettings) -> WholeBodyIk {
        let (step, yaw) = (settings.max_base_step, settings.max_yaw_step);
        let step_bounds = match robot.base().kind {
            BaseKind::DifferentialDrive => vec![step, yaw],
            _ => vec![step, step, yaw],
        };
        WholeBodyIk {
            base_dofs: step_bounds.len(),
            step_bounds,
        }
    }

    /// Number of side patterns ([`WholeBodyIk::code`]'s range): 3 to the number of base
    /// coordinates.
    pub(super) fn patterns(&self) -> usize {
        3_usize.pow(self.base_dofs as u32)
    }

    /// The index of a side pattern (one [`Side`] per base coordinate), in
    /// `0..`[`WholeBodyIk::patterns`].
    pub(super) fn code(sides: &[Side]) -> usize {
        sides.iter().rev().fold(0, |code, side| {
            3 * code
                + match side {
                    Side::Both => 0,
                    Side::Positive => 1,
                    Side::Negative => 2,
                }
        })
    }

    /// The IK solver of the model whose base coordinates take the sides `sides`.
    ///
    /// # Errors
    /// [`PlacementError::Pinocchio`] / [`PlacementError::Ik`] if the model cannot be built.
    pub(super) fn solver(
        &self,
        robot: &RobotModel,
        ik: &IkSettings,
        sides: &[Side],
    ) -> Result<IkSolver, PlacementError> {
        let bounds: Vec<(f64, f64)> = self
            .step_bounds
            .iter()
            .zip(sides)
            .map(|(b, side)| match side {
                Side::Both => (-b, *b),
                Side::Positive => (0.0, *b),
                Side::Negative => (-b, 0.0),
            })
            .collect();
        let (model, tool) = build(robot, &bounds)?;
        Ok(IkSolver::new(&model, tool, ik.clone())?)
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

/// The whole-body Pinocchio model with the base coordinates' limits `bounds` (forward,
/// sideways for 3 of them, yaw), and its tool frame.
fn build(robot: &RobotModel, bounds: &[(f64, f64)]) -> Result<(Model, FrameIndex), PlacementError> {
    let mut b = ModelBuilder::new();
    let forward = bounds[0];
    let mut parent = b.add_joint(
        "whole_body_forward",
        JointIndex::UNIVERSE,
        Isometry3::identity(),
        JointKind::Prismatic { axis: Vector3::x() },
        JointLimits::position(forward.0, forward.1),
    )?;
    if let [_, sideways, _] = bounds {
        parent = b.add_joint(
            "whole_body_sideways",
            parent,
            Isometry3::identity(),
            JointKind::Prismatic { axis: Vector3::y() },
            JointLimits::position(sideways.0, sideways.1),
        )?;
    }
    let yaw = bounds[bounds.len() - 1];
    parent = b.add_joint(
        "whole_body_yaw",
        parent,
        Isometry3::identity(),
        JointKind::Revolute { axis: Vector3::z() },
        JointLimits::position(yaw.0, yaw.1),
    )?;
    parent = robot.add_arm_to(&mut b, parent)?;
    let tool = b.add_frame("tool", parent, *robot.last_from_tool())?;
    Ok((b.build()?, tool))
}
