//! Execution of a planner's [`StepMotion`] in the simulator: the base path, the arm approach,
//! the grasp, the manipulation with the part dragged under physics, release and retreat.

use kinscene::motion::timing::TimedPath;
use kinscene::planner::StepMotion;
use kinscene::scene::PartId;
use nalgebra::{DVector, Point3};

use super::hardware::{GRASP_TOLERANCE, RELEASE_SETTLE, SLIP_DISTANCE};
use super::physics::DT;
use super::robot::pose_of;
use super::sensors::Owner;
use super::{Clock, ExecFailure, FailureCategory, SimWorld, StepExecution};

/// Collision checks along the base path every this long (s): 2 cm at 0.5 m/s.
const BASE_TICK: f64 = 0.04;
/// Collision checks along arm paths every this long (s): under 0.02 rad per joint at the
/// Gen3's 0.87 rad/s.
const ARM_TICK: f64 = 0.02;
/// During manipulation the arm is checked against the scene every this many physics steps.
const ARM_CHECK_EVERY: usize = 3;
/// The base trace gets a pose every this far (m).
const TRACE_SPACING: f64 = 0.05;

fn other(reason: impl Into<String>) -> ExecFailure {
    ExecFailure::new(FailureCategory::Other, reason)
}

/// Checks that a timed path is usable: waypoints of `dim` finite values, finite duration.
fn check_path(path: &TimedPath, dim: usize, what: &str) -> Result<(), ExecFailure> {
    let ok = !path.positions.is_empty()
        && path.duration.is_finite()
        && path.duration >= 0.0
        && path
            .positions
            .iter()
            .all(|p| p.len() == dim && p.iter().all(|v| v.is_finite()));
    if ok {
        Ok(())
    } else {
        Err(other(format!(
            "malformed {what}: waypoints must have {dim} finite values and the duration be finite"
        )))
    }
}

/// Sample times `0, d/n, …, d` with `n = ceil(d / tick)` (at least 1).
fn ticks(duration: f64, tick: f64) -> impl Iterator<Item = f64> {
    let n = ((duration / tick).ceil() as usize).max(1);
    (0..=n).map(move |k| duration * k as f64 / n as f64)
}

/// Checks that a whole-body manipulation's base path goes with its arm path: one base pose
/// per arm waypoint, at the same times (the planner times both together).
fn check_companion(bases: &TimedPath, arm: &TimedPath) -> Result<(), ExecFailure> {
    let same_times = bases.times.len() == arm.times.len()
        && bases
            .times
            .iter()
            .zip(&arm.times)
            .all(|(a, b)| (a - b).abs() <= 1e-9)
        && (bases.duration - arm.duration).abs() <= 1e-9;
    if bases.positions.len() == arm.positions.len() && same_times {
        Ok(())
    } else {
        Err(other(format!(
            "malformed manipulation base path: {} base poses over {:.3} s for {} arm waypoints \
             over {:.3} s (one per waypoint, at the same times)",
            bases.positions.len(),
            bases.duration,
            arm.positions.len(),
            arm.duration
        )))
    }
}

impl SimWorld {
    /// [`SimWorld::execute_step`].
    pub(super) fn run_step(&mut self, step: &StepMotion) -> StepExecution {
        let mut exec = StepExecution {
            joint: step.joint.clone(),
            base_time: 0.0,
            arm_time: 0.0,
            failure: None,
        };
        if let Err(f) = self.run_phases(step, &mut exec) {
            // The robot stops where it is and opens the gripper.
            self.physics.detach();
            self.settle(RELEASE_SETTLE);
            exec.failure = Some(f);
        }
        let _ = self.sync_robot();
        self.clock.base += exec.base_time;
        self.clock.arm += exec.arm_time;
        exec
    }

    fn run_phases(
        &mut self,
        step: &StepMotion,
        exec: &mut StepExecution,
    ) -> Result<(), ExecFailure> {
        let dof = self.robot.model.dof();
        check_path(&step.base_path, 3, "base path")?;
        check_path(&step.approach, dof, "approach")?;
        check_path(&step.manipulation, dof, "manipulation")?;
        check_path(&step.retreat, dof, "retreat")?;
        if let Some(bases) = &step.manipulation_base {
            check_path(bases, 3, "manipulation base path")?;
            check_companion(bases, &step.manipulation)?;
        }
        // Between steps: gripper open, arm stowed.
        self.physics.detach();
        if self.robot.arm != self.robot.stow {
            exec.arm_time += self.robot.arm_time(&self.robot.arm, &self.robot.stow);
            self.robot.arm = self.robot.stow.clone();
        }
        self.follow_base(&step.base_path, exec)?;

        // The part under the tool at the end of the approach may touch the gripper.
        let end = self.arm_at(&step.approach, step.approach.duration);
        let tip = self
            .robot
            .tool_at(self.robot.base, &end)
            .map(|t| Point3::from(t.translation.vector))
            .map_err(|e| other(e.to_string()))?;
        let reached = self
            .nearest_handle(&tip)
            .filter(|(_, _, d)| *d <= 2.0 * GRASP_TOLERANCE)
            .map(|(k, _, _)| self.subtree_ids(k))
            .unwrap_or_default();
        self.follow_arm(&step.approach, &reached, "approach", exec)?;

        let part = self.close_gripper()?;
        self.follow_manipulation(
            &step.manipulation,
            step.manipulation_base.as_ref(),
            part,
            exec,
        )?;
        self.physics.detach();
        self.settle(RELEASE_SETTLE);
        let held = self.subtree_ids(part);
        self.follow_arm(&step.retreat, &held, "retreat", exec)
    }

    fn arm_at(&self, path: &TimedPath, t: f64) -> DVector<f64> {
        DVector::from_vec(path.sample(t))
    }

    /// Drives the base path with the arm stowed, checking the robot against the true scene.
    fn follow_base(
        &mut self,
        path: &TimedPath,
        exec: &mut StepExecution,
    ) -> Result<(), ExecFailure> {
        let (_, data) = self.true_data();
        let stow = self.robot.stow.clone();
        let mut traced = self.robot.base;
        for t in ticks(path.duration, BASE_TICK) {
            let p = path.sample(t);
            let base = [p[0], p[1], p[2]];
            let poses = self
                .robot
                .link_poses_at(base, &stow)
                .map_err(|e| other(e.to_string()))?;
            if let Some((link, body)) = self.robot.scene_hit(&poses, &self.truth, &data, &[], false)
            {
                exec.base_time = t;
                return Err(ExecFailure::new(
                    FailureCategory::PathBlocked,
                    format!(
                        "the base path is blocked by {} at ({:.2}, {:.2}) (robot {})",
                        self.body_name(body),
                        base[0],
                        base[1],
                        self.link_name(link)
                    ),
                ));
            }
            self.robot.base = base;
            let moved = (base[0] - traced[0]).hypot(base[1] - traced[1]);
            if moved >= TRACE_SPACING || t >= path.duration {
                self.trace.push(pose_of(&base));
                traced = base;
            }
        }
        exec.base_time = path.duration;
        Ok(())
    }

    /// Follows an arm path (no part held), checking self-collision and the arm against the
    /// true scene with the parts `ignore` exempt.
    fn follow_arm(
        &mut self,
        path: &TimedPath,
        ignore: &[PartId],
        phase: &str,
        exec: &mut StepExecution,
    ) -> Result<(), ExecFailure> {
        let (_, data) = self.true_data();
        for t in ticks(path.duration, ARM_TICK) {
            let q = self.arm_at(path, t);
            let poses = self
                .robot
                .link_poses_at(self.robot.base, &q)
                .map_err(|e| other(e.to_string()))?;
            if let Some((a, b)) = self.robot.self_hit(&poses) {
                exec.arm_time += t;
                return Err(other(format!(
                    "self-collision of {} and {} during the {phase}",
                    self.link_name(a),
                    self.link_name(b)
                )));
            }
            if let Some((link, body)) =
                self.robot
                    .scene_hit(&poses, &self.truth, &data, ignore, false)
            {
                exec.arm_time += t;
                return Err(other(format!(
                    "during the {phase} the arm's {} touched {}",
                    self.link_name(link),
                    self.body_name(body)
                )));
            }
            self.robot.arm = q;
        }
        exec.arm_time += path.duration;
        self.sync_robot().map_err(|e| other(e.to_string()))
    }

    /// Closes the gripper on the true handle under the tool: the grasped part's index.
    fn close_gripper(&mut self) -> Result<usize, ExecFailure> {
        self.sync_robot().map_err(|e| other(e.to_string()))?;
        let tool = self
            .robot
            .world_from_tool()
            .map_err(|e| other(e.to_string()))?;
        let tip = Point3::from(tool.translation.vector);
        let lost = |reason: String| ExecFailure::new(FailureCategory::GraspLost, reason);
        let Some((part, _, d)) = self.nearest_handle(&tip) else {
            return Err(lost("the scene has no handle".into()));
        };
        if d > GRASP_TOLERANCE {
            return Err(lost(format!(
                "no handle within {:.1} cm of the gripper (nearest: on part {}, {:.1} cm away)",
                100.0 * GRASP_TOLERANCE,
                self.truth.parts()[part].name(),
                100.0 * d
            )));
        }
        if self.roll(self.settings.faults.grasp_slip) {
            return Err(lost("the grasp slipped (injected fault)".into()));
        }
        self.physics
            .attach(self.robot.gripper_link(), part, &tip, &tool)
            .map_err(|e| other(e.to_string()))?;
        Ok(part)
    }

    /// Follows the manipulation trajectory with the physics running: the grasped part moves
    /// along its true joint as far as the grasp spring drags it. With `bases` (a whole-body
    /// manipulation) the base moves too, to its pose sampled at the same time as the arm's
    /// configuration; the robot's links, base included, are moved kinematically at every
    /// physics step and checked against the scene as the arm is. The robot ends at the last
    /// base pose, where the retreat runs.
    ///
    /// Time: the manipulation's duration counts as arm time, whether or not the base moves
    /// (the planner's `StepTiming::arm` counts it so too); the base's share is not added to
    /// the base time, since base and arm move at once and the base time is the time spent
    /// driving with the arm stowed.
    fn follow_manipulation(
        &mut self,
        path: &TimedPath,
        bases: Option<&TimedPath>,
        part: usize,
        exec: &mut StepExecution,
    ) -> Result<(), ExecFailure> {
        let moving = self.subtree(part);
        let ignore = self.subtree_ids(part);
        let gripper = self.robot.gripper_link();
        let n = ((path.duration / DT).ceil() as usize).max(1);
        let slip_per_step = self.settings.faults.grasp_slip * path.duration / n as f64;
        let name = |w: &SimWorld, k: usize| w.truth.parts()[k].name().to_string();
        let mut traced = self.robot.base;
        for s in 1..=n {
            let t = path.duration * s as f64 / n as f64;
            let q = self.arm_at(path, t);
            let base = bases.map_or(self.robot.base, |b| {
                let p = b.sample(t);
                [p[0], p[1], p[2]]
            });
            let poses = self
                .robot
                .link_poses_at(base, &q)
                .map_err(|e| other(e.to_string()))?;
            self.physics.move_links(&poses);
            self.physics.step();
            self.robot.arm = q;
            self.robot.base = base;
            let moved = (base[0] - traced[0]).hypot(base[1] - traced[1]);
            if moved >= TRACE_SPACING || (s == n && base != traced) {
                self.trace.push(pose_of(&base));
                traced = base;
            }
            self.check_watch(Clock {
                base: exec.base_time,
                arm: exec.arm_time + t,
            });
            if let Some(hit) = self.physics.moving_contact(&moving) {
                exec.arm_time += t;
                let what = match (hit.other, hit.base_shape) {
                    (Owner::Part(o), _) => format!("part {}", name(self, o)),
                    (_, Some(k)) => format!("the kitchen ({})", self.truth.base().shapes[k].name),
                    _ => "the kitchen".to_string(),
                };
                return Err(ExecFailure::new(
                    FailureCategory::PartCollision,
                    format!(
                        "part {} collided with {what} ({:.1} mm deep, {:.0} N)",
                        name(self, hit.part),
                        1000.0 * hit.depth.max(0.0),
                        hit.force
                    ),
                ));
            }
            let stretch = self.physics.stretch(gripper).unwrap_or(f64::INFINITY);
            if stretch > SLIP_DISTANCE {
                exec.arm_time += t;
                return Err(ExecFailure::new(
                    FailureCategory::GraspLost,
                    format!(
                        "the handle slipped out of the gripper: part {} does not follow the \
                         planned handle trajectory (grasp spring stretched {:.1} cm)",
                        name(self, part),
                        100.0 * stretch
                    ),
                ));
            }
            if self.roll(slip_per_step) {
                exec.arm_time += t;
                return Err(ExecFailure::new(
                    FailureCategory::GraspLost,
                    "the grasp slipped during the manipulation (injected fault)",
                ));
            }
            if s % ARM_CHECK_EVERY == 0 || s == n {
                if let Some((a, b)) = self.robot.self_hit(&poses) {
                    exec.arm_time += t;
                    return Err(other(format!(
                        "self-collision of {} and {} during the manipulation",
                        self.link_name(a),
                        self.link_name(b)
                    )));
                }
                let (_, data) = self.true_data();
                if let Some((link, body)) =
                    self.robot
                        .scene_hit(&poses, &self.truth, &data, &ignore, false)
                {
                    exec.arm_time += t;
                    return Err(other(format!(
                        "during the manipulation the arm's {} touched {}",
                        self.link_name(link),
                        self.body_name(body)
                    )));
                }
            }
        }
        exec.arm_time += path.duration;
        Ok(())
    }
}
