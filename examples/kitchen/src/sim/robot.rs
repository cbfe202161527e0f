//! The simulated robot's kinematic state: base pose, arm configuration, forward kinematics,
//! IK, collision checks against the true scene, and arm motion timing.

use std::time::Duration;

use kinscene::kinematics::ik::{IkOutcome, IkSettings, IkSolver, IkTarget};
use kinscene::kinematics::robot::{Exempt, RobotCollision, RobotConfig, RobotModel};
use kinscene::scene::collision::Body;
use kinscene::scene::{PartId, SceneData, SceneModel};
use nalgebra::{DVector, Isometry2, Isometry3, Point3, Unit, Vector3};

use super::SimError;

/// Random restarts of a grasp's IK solve (deterministic: the solver seeds them itself).
const IK_RESTARTS: usize = 20;
/// The IK wall-clock budget, far above what the iteration limits take, so that it never
/// decides an outcome (the simulation must not depend on the machine's speed).
const IK_BUDGET: Duration = Duration::from_secs(60);

/// Further IK seeds a grasp tries when the solution from the current arm touches the robot
/// itself or the scene: drawn uniformly within the joint limits from a fixed stream, so the
/// simulation stays deterministic. A controller that checks its IK solutions for collision
/// does the same.
const GRASP_SEEDS: u64 = 8;

/// The robot: model, solvers and current configuration.
pub(super) struct Robot {
    /// The robot model.
    pub model: RobotModel,
    /// Its compiled collision geometry.
    pub collision: RobotCollision,
    ik: IkSolver,
    /// The stowed arm configuration (`RobotModel::neutral`, as the planner's default).
    pub stow: DVector<f64>,
    /// Base pose x (m), y (m), yaw (rad).
    pub base: [f64; 3],
    /// Arm configuration.
    pub arm: DVector<f64>,
}

/// `[x, y, yaw]` of a planar pose.
pub(super) fn base_of(pose: &Isometry2<f64>) -> [f64; 3] {
    [
        pose.translation.vector.x,
        pose.translation.vector.y,
        pose.rotation.angle(),
    ]
}

/// The planar pose of `[x, y, yaw]`.
pub(super) fn pose_of(base: &[f64; 3]) -> Isometry2<f64> {
    Isometry2::new(nalgebra::Vector2::new(base[0], base[1]), base[2])
}

impl Robot {
    /// The robot at `base`, arm stowed.
    pub(super) fn new(model: &RobotModel, base: [f64; 3]) -> Result<Robot, SimError> {
        let collision = RobotCollision::new(model)
            .map_err(|e| SimError::Setup(format!("robot collision model: {e}")))?;
        let settings = IkSettings {
            restarts: IK_RESTARTS,
            budget: IK_BUDGET,
            ..IkSettings::default()
        };
        let ik = IkSolver::for_robot(model, settings)
            .map_err(|e| SimError::Setup(format!("IK solver: {e}")))?;
        let stow = model.neutral();
        Ok(Robot {
            model: model.clone(),
            collision,
            ik,
            arm: stow.clone(),
            stow,
            base,
        })
    }

    /// Index of the gripper link (the last arm link, which carries the gripper geometry).
    pub(super) fn gripper_link(&self) -> usize {
        self.model.links().len().saturating_sub(1)
    }

    /// The base pose.
    pub(super) fn world_from_base(&self) -> Isometry2<f64> {
        pose_of(&self.base)
    }

    /// Link poses at `base` and `arm`.
    pub(super) fn link_poses_at(
        &self,
        base: [f64; 3],
        arm: &DVector<f64>,
    ) -> Result<Vec<Isometry3<f64>>, SimError> {
        self.model
            .link_poses(&RobotConfig {
                base,
                arm: arm.clone(),
            })
            .map_err(|e| SimError::Setup(format!("robot forward kinematics: {e}")))
    }

    /// Link poses now.
    pub(super) fn link_poses(&self) -> Result<Vec<Isometry3<f64>>, SimError> {
        self.link_poses_at(self.base, &self.arm)
    }

    /// The tool frame at `base` and `arm`.
    pub(super) fn tool_at(
        &self,
        base: [f64; 3],
        arm: &DVector<f64>,
    ) -> Result<Isometry3<f64>, SimError> {
        self.model
            .world_from_tool(&RobotConfig {
                base,
                arm: arm.clone(),
            })
            .map_err(|e| SimError::Setup(format!("robot forward kinematics: {e}")))
    }

    /// The tool frame now.
    pub(super) fn world_from_tool(&self) -> Result<Isometry3<f64>, SimError> {
        self.tool_at(self.base, &self.arm)
    }

    /// An arm configuration placing the tool at `point` with tool z along `axis` (world frame)
    /// from the current base: from `seed` with random restarts (`near == false`), or staying
    /// close to `seed` without restarts (`near == true`). `None` if IK does not converge.
    pub(super) fn solve(
        &self,
        point: &Point3<f64>,
        axis: &Unit<Vector3<f64>>,
        seed: &DVector<f64>,
        near: bool,
    ) -> Option<DVector<f64>> {
        let base_from_world = RobotModel::world_from_base(self.base).inverse();
        let target = IkTarget::PositionAxis {
            position: base_from_world * point,
            axis: Unit::new_normalize(base_from_world * axis.into_inner()),
        };
        let outcome = if near {
            self.ik.solve_near(&target, seed)
        } else {
            self.ik.solve(&target, seed)
        };
        match outcome {
            Ok(IkOutcome::Solved(solution)) => Some(solution.q),
            _ => None,
        }
    }

    /// IK solutions placing the tool at `point` with tool z along `axis`, lazily: from `seed`
    /// with restarts (as [`Robot::solve`]), then from each of [`GRASP_SEEDS`] configurations
    /// drawn within the limits; the caller takes the first it accepts.
    pub(super) fn solutions<'a>(
        &'a self,
        point: &'a Point3<f64>,
        axis: &'a Unit<Vector3<f64>>,
        seed: &'a DVector<f64>,
    ) -> impl Iterator<Item = DVector<f64>> + 'a {
        use rand::{Rng, SeedableRng};
        (0..=GRASP_SEEDS).filter_map(move |k| {
            if k == 0 {
                return self.solve(point, axis, seed, false);
            }
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(k);
            let start = DVector::from_iterator(
                seed.len(),
                self.model
                    .arm_joints()
                    .iter()
                    .zip(seed.iter())
                    .map(|(j, &q)| {
                        let (lo, hi) = if j.lower.is_finite() && j.upper.is_finite() {
                            (j.lower, j.upper)
                        } else {
                            (q - std::f64::consts::PI, q + std::f64::consts::PI)
                        };
                        rng.random_range(lo..=hi)
                    }),
            );
            self.solve(point, axis, &start, false)
        })
    }

    /// The first pair of robot links in contact at `poses`, if any.
    pub(super) fn self_hit(&self, poses: &[Isometry3<f64>]) -> Option<(usize, usize)> {
        self.collision.self_collision(poses)
    }

    /// The first robot link touching the true scene (`truth` at the state in `data`) at
    /// `poses`, the parts `ignore` exempt; the gripper link is skipped when `skip_gripper`
    /// (its fingers close around a handle, next to neighbouring fronts).
    pub(super) fn scene_hit(
        &self,
        poses: &[Isometry3<f64>],
        truth: &SceneModel,
        data: &SceneData,
        ignore: &[PartId],
        skip_gripper: bool,
    ) -> Option<(usize, Body)> {
        let n = if skip_gripper {
            self.gripper_link().min(poses.len())
        } else {
            poses.len()
        };
        self.collision
            .scene_collision(&poses[..n], truth, data, Exempt::Parts(ignore), 0.0)
    }

    /// Simulated time (s) of a rest-to-rest arm motion from `from` to `to`: every joint on a
    /// trapezoidal profile at its velocity and acceleration limits, the slowest joint deciding.
    pub(super) fn arm_time(&self, from: &DVector<f64>, to: &DVector<f64>) -> f64 {
        self.model
            .arm_joints()
            .iter()
            .zip(from.iter().zip(to.iter()))
            .map(|(j, (a, b))| {
                let d = (b - a).abs();
                let (v, acc) = (j.max_velocity, j.max_acceleration);
                if d >= v * v / acc {
                    d / v + v / acc
                } else {
                    2.0 * (d / acc).sqrt()
                }
            })
            .fold(0.0, f64::max)
    }
}
