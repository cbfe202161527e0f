//! The `Hardware` actions of the simulated robot: navigation, grasp, compliant pull steps and
//! retract, in simulated time.

use kinscene::discovery::{Hardware, HardwareFailure, LocalGoal};
use kinscene::scene::nav::occupancy;
use nalgebra::{
    Isometry2, Isometry3, Point2, Point3, Translation3, Unit, UnitQuaternion, Vector2, Vector3,
};

use super::navigation::route;
use super::physics::DT;
use super::robot::base_of;
use super::{Clock, SimWorld};

/// The gripper closes on a true handle within this distance (m) of the tool point.
pub(super) const GRASP_TOLERANCE: f64 = 0.035;
/// The grasp slips when the spring stretches beyond this (m).
pub(super) const SLIP_DISTANCE: f64 = 0.045;
/// A pull step: the gripper moves for this long (s) ...
const PULL_MOVE: f64 = 0.2;
/// ... then holds for this long (s) while the part settles.
const PULL_HOLD: f64 = 0.1;
/// After the gripper opens, the physics runs this long (s) so a released part comes to rest.
pub(super) const RELEASE_SETTLE: f64 = 0.3;
/// A base that starts inside the inflated obstacles may cross them within this radius (m) of
/// its start (a robot parked close to a counter leaves it).
const ESCAPE: f64 = 0.3;
/// Searching for a lost target costs this long (s) of base time.
const TRACKER_SEARCH: f64 = 1.0;

fn failure(reason: impl Into<String>) -> HardwareFailure {
    HardwareFailure::Other {
        reason: reason.into(),
    }
}

fn finite(values: impl IntoIterator<Item = f64>) -> bool {
    values.into_iter().all(f64::is_finite)
}

/// `a - b` wrapped into (-π, π].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(2.0 * std::f64::consts::PI);
    if d > std::f64::consts::PI {
        d - 2.0 * std::f64::consts::PI
    } else {
        d
    }
}

impl SimWorld {
    /// Global navigation (see [`Hardware::navigate_to`](kinscene::discovery::Hardware)).
    pub(super) fn navigate(&mut self, goal: &Isometry2<f64>) -> Result<(), HardwareFailure> {
        let target = base_of(goal);
        if !finite(target) {
            return Err(failure(format!("navigation goal {target:?} is not finite")));
        }
        if self.physics.grasp.is_some() {
            return Err(failure("navigating while holding a handle"));
        }
        self.stow_arm()?;
        let (_, data) = self.true_data();
        let nav_failed = |reason: String| HardwareFailure::NavigationFailed { reason };
        let grid = occupancy(&self.truth, &data)
            .and_then(|g| g.inflate(self.robot.model.base().footprint_radius))
            .map_err(|e| nav_failed(format!("occupancy grid: {e}")))?;
        let from = self.robot.base;
        let r = route(
            &grid,
            Point2::new(from[0], from[1]),
            Point2::new(target[0], target[1]),
            ESCAPE,
        )
        .map_err(nav_failed)?;
        let poses = self
            .robot
            .link_poses_at(target, &self.robot.stow)
            .map_err(|e| failure(e.to_string()))?;
        if let Some((link, body)) = self.robot.scene_hit(&poses, &self.truth, &data, &[], false) {
            return Err(nav_failed(format!(
                "at the goal the robot's {} would touch {}",
                self.link_name(link),
                self.body_name(body)
            )));
        }
        let limits = self.robot.model.base().max_velocity;
        let turn = angle_diff(target[2], from[2]);
        let time = r.length / limits[0].min(limits[1]) + turn.abs() / limits[2];
        // The trace: the route's corners, the heading turning in proportion to the distance.
        let mut along = 0.0;
        for w in r.points.windows(2) {
            along += (w[1] - w[0]).norm();
            let f = if r.length > 0.0 {
                along / r.length
            } else {
                1.0
            };
            self.trace
                .push(Isometry2::new(w[1].coords, from[2] + turn * f));
        }
        self.robot.base = [target[0], target[1], from[2] + turn];
        self.clock.base += time;
        self.sync_robot().map_err(|e| failure(e.to_string()))
    }

    /// Local navigation with the tracker-loss and drift faults.
    pub(super) fn navigate_tracked(&mut self, goal: &LocalGoal) -> Result<(), HardwareFailure> {
        if self.roll(self.settings.faults.tracker_loss) {
            self.clock.base += TRACKER_SEARCH;
            return Err(HardwareFailure::TrackingLost);
        }
        let sigma = self.settings.faults.nav_drift;
        if sigma > 0.0 {
            let drift = Vector2::new(self.gaussian(), self.gaussian()) * sigma;
            let mut drifted = goal.world_from_base;
            drifted.translation.vector += drift;
            // A drifted goal the base cannot reach: it stops at the nominal one instead.
            if self.navigate(&drifted).is_ok() {
                return Ok(());
            }
        }
        self.navigate(&goal.world_from_base)
    }

    /// Moves the arm to its stowed configuration (no gripper change), counting the time.
    fn stow_arm(&mut self) -> Result<(), HardwareFailure> {
        if self.robot.arm != self.robot.stow {
            self.clock.arm += self.robot.arm_time(&self.robot.arm, &self.robot.stow);
            self.robot.arm = self.robot.stow.clone();
            self.sync_robot().map_err(|e| failure(e.to_string()))?;
        }
        Ok(())
    }

    /// Grasp (see [`Hardware::grasp`](kinscene::discovery::Hardware)).
    pub(super) fn close_on(
        &mut self,
        point: &Point3<f64>,
        approach: &Unit<Vector3<f64>>,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        if !finite(point.coords.iter().chain(approach.iter()).copied()) {
            return Err(failure("grasp target is not finite"));
        }
        self.physics.detach();
        // The part the gripper reaches for may touch the arm; nothing else may. The first IK
        // solution that keeps to that is taken; without one, the first solution's failure.
        let ignore = self
            .nearest_handle(point)
            .filter(|(_, _, d)| *d <= 2.0 * GRASP_TOLERANCE)
            .map(|(k, _, _)| self.subtree_ids(k))
            .unwrap_or_default();
        let (_, data) = self.true_data();
        let mut first_failure = None;
        let mut accepted = None;
        for q in self.robot.solutions(point, approach, &self.robot.arm) {
            let poses = self
                .robot
                .link_poses_at(self.robot.base, &q)
                .map_err(|e| failure(e.to_string()))?;
            let failed = if self.robot.self_hit(&poses).is_some() {
                Some(HardwareFailure::SelfCollision)
            } else {
                self.robot
                    .scene_hit(&poses, &self.truth, &data, &ignore, true)
                    .map(|(link, body)| {
                        failure(format!(
                            "the arm's {} would touch {}",
                            self.link_name(link),
                            self.body_name(body)
                        ))
                    })
            };
            match failed {
                None => {
                    accepted = Some(q);
                    break;
                }
                Some(f) => {
                    first_failure.get_or_insert(f);
                }
            }
        }
        let Some(q) = accepted else {
            return Err(first_failure.unwrap_or(HardwareFailure::Unreachable));
        };
        self.clock.arm += self.robot.arm_time(&self.robot.arm, &q);
        self.robot.arm = q;
        self.sync_robot().map_err(|e| failure(e.to_string()))?;
        if self.roll(self.settings.faults.grasp_slip) {
            return Err(HardwareFailure::GraspLost);
        }
        let tool = Hardware::ee_pose(self);
        let tip = Point3::from(tool.translation.vector);
        let Some((part, _, d)) = self.nearest_handle(&tip) else {
            return Err(HardwareFailure::GraspLost);
        };
        if d > GRASP_TOLERANCE {
            return Err(HardwareFailure::GraspLost);
        }
        self.physics
            .attach(self.robot.gripper_link(), part, &tip, &tool)
            .map_err(|e| failure(e.to_string()))?;
        Ok(tool)
    }

    /// One compliant pull step (see [`Hardware::pull_step`](kinscene::discovery::Hardware)).
    pub(super) fn pull(
        &mut self,
        direction: &Unit<Vector3<f64>>,
        step: f64,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        if !(finite(direction.iter().copied()) && step.is_finite() && step >= 0.0) {
            return Err(failure("pull step is not finite and non-negative"));
        }
        let Some(part_from_tool) = self.physics.grasp.as_ref().map(|g| g.part_from_tool) else {
            return Err(HardwareFailure::GraspLost);
        };
        self.clock.arm += PULL_MOVE + PULL_HOLD;
        if self.roll(self.settings.faults.joint_limit) {
            return Err(HardwareFailure::JointLimit);
        }
        if self.roll(self.settings.faults.grasp_slip) {
            self.physics.detach();
            return Err(HardwareFailure::GraspLost);
        }
        let gripper = self.robot.gripper_link();
        let tool_from_link = self.robot.model.last_from_tool().inverse();
        let start = Hardware::ee_pose(self);
        let moves = (PULL_MOVE / DT).round() as usize;
        let holds = (PULL_HOLD / DT).round() as usize;
        let mut links = self
            .robot
            .link_poses()
            .map_err(|e| failure(e.to_string()))?;
        for i in 1..=moves + holds {
            let f = (i as f64 / moves as f64).min(1.0);
            let tool = Translation3::from(direction.into_inner() * (step * f)) * start;
            if let Some(link) = links.get_mut(gripper) {
                *link = tool * tool_from_link;
            }
            self.physics.move_links(&links);
            self.physics.step();
            // The clock already holds the whole pull.
            self.check_watch(Clock {
                base: 0.0,
                arm: i as f64 * DT - (PULL_MOVE + PULL_HOLD),
            });
        }
        if self
            .physics
            .stretch(gripper)
            .is_none_or(|s| s > SLIP_DISTANCE)
        {
            self.physics.detach();
            self.sync_robot().map_err(|e| failure(e.to_string()))?;
            return Err(HardwareFailure::GraspLost);
        }
        // The compliant arm follows the grasp point on the part.
        let (Some(point), Some(world_from_part)) = (
            self.physics.grasp_point(),
            self.physics
                .grasp
                .as_ref()
                .and_then(|g| self.physics.world_from_part(g.part)),
        ) else {
            return Err(HardwareFailure::GraspLost);
        };
        let axis = Unit::new_normalize((world_from_part * part_from_tool).rotation * Vector3::z());
        // The fingers' give never takes the arm past a limit: where the deflected tool pose is
        // out of reach, the arm stays on the grasp point and the fingers take up the slack.
        let (bent, tilted) = self.comply(point, axis);
        let solved = self
            .robot
            .solve(&bent, &tilted, &self.robot.arm, true)
            .or_else(|| self.robot.solve(&point, &axis, &self.robot.arm, true));
        let Some(q) = solved else {
            self.sync_robot().map_err(|e| failure(e.to_string()))?;
            return Err(HardwareFailure::JointLimit);
        };
        let poses = self
            .robot
            .link_poses_at(self.robot.base, &q)
            .map_err(|e| failure(e.to_string()))?;
        if self.robot.self_hit(&poses).is_some() {
            self.sync_robot().map_err(|e| failure(e.to_string()))?;
            return Err(HardwareFailure::SelfCollision);
        }
        self.robot.arm = q;
        self.sync_robot().map_err(|e| failure(e.to_string()))?;
        Ok(Hardware::ee_pose(self))
    }

    /// The tool's target under the fingers' compliance ([`super::GraspCompliance`]): the grasp
    /// point deflected and the approach axis tilted by the compliance's own draws (none when
    /// both deviations are 0).
    fn comply(
        &mut self,
        point: Point3<f64>,
        axis: Unit<Vector3<f64>>,
    ) -> (Point3<f64>, Unit<Vector3<f64>>) {
        let g = self.settings.grasp;
        if g.deflection == 0.0 && g.tilt == 0.0 {
            return (point, axis);
        }
        let rng = &mut self.compliance_rng;
        let offset = Vector3::from_fn(|_, _| super::standard_normal(rng)) * g.deflection;
        let (a, b) = (super::standard_normal(rng), super::standard_normal(rng));
        let helper = if axis.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let e1 = axis.cross(&helper).normalize();
        let e2 = axis.cross(&e1);
        let tilt = UnitQuaternion::from_scaled_axis((e1 * a + e2 * b) * g.tilt);
        (point + offset, tilt * axis)
    }

    /// Retract: open the gripper, let the part come to rest, stow the arm.
    pub(super) fn open_and_stow(&mut self) -> Result<(), HardwareFailure> {
        self.physics.detach();
        self.settle(RELEASE_SETTLE);
        self.stow_arm()
    }
}
