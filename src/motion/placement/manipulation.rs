//! IK along the grasp trajectory at one base pose, with continuity, joint-jump and collision
//! checks: the [`ManipulationPlan`].

use std::cell::RefCell;
use std::collections::BTreeSet;
use std::f64::consts::PI;

use nalgebra::{DVector, Isometry3, Vector3};

use super::grasp::{GraspRotation, JointMotion};
use super::plan::{ManipulationPlan, Obstacle, WaypointFailure};
use super::reach::{ArmReach, arm_reach};
use super::{ManipulationSettings, PlacementError, PlacementProblem};
use crate::control::Termination;
use crate::kinematics::ik::{IkBest, IkData, IkFailure, IkOutcome, IkSolution, IkTarget};
use crate::kinematics::robot::{ArmJointKind, Exempt, RobotConfig, RobotModel};
use crate::scene::collision::{Body, handle_front_shapes};
use crate::scene::{PartId, SceneData, forward_kinematics};

/// Moves each continuous joint of `q` by a multiple of 2π to within π of `prev` (the IK
/// wraps unlimited angles into [−π, π); a trajectory must not jump by 2π).
pub(crate) fn unwrap_continuous(robot: &RobotModel, q: &mut DVector<f64>, prev: &DVector<f64>) {
    for (j, joint) in robot.arm_joints().iter().enumerate() {
        if joint.kind == ArmJointKind::Continuous {
            let d = q[j] - prev[j];
            q[j] = prev[j] + (d + PI).rem_euclid(2.0 * PI) - PI;
        }
    }
}

/// When IK along a trajectory gives up on a base pose that cannot win any more.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Cutoff {
    /// Never: every waypoint is tried.
    None,
    /// Once fewer than this many waypoints can still be reached.
    Reached(usize),
    /// At the first waypoint not reached (the reached prefix is then fixed).
    FirstMiss,
}

/// One waypoint's IK problem.
pub(crate) struct Attempt<'a> {
    pub base: [f64; 3],
    pub k: usize,
    pub target: &'a IkTarget,
    /// The previous configuration when it was reached (continue from it).
    pub continuing: Option<&'a DVector<f64>>,
    /// The previous configuration, or the plan's seed at the first waypoint.
    pub start: &'a DVector<f64>,
}

/// A joint motion prepared for repeated planning at different base poses: the scene's forward
/// kinematics at every waypoint and the parts that move with the joint.
#[derive(Debug)]
pub(crate) struct Prepared<'a> {
    pub problem: PlacementProblem<'a>,
    pub motion: &'a JointMotion,
    /// The joint's part and its descendants: the grasped part, which only the gripper's
    /// contact shapes may touch.
    pub moving: Vec<PartId>,
    /// Scene FK at each waypoint.
    pub scene: Vec<SceneData>,
    pub reach: ArmReach,
    /// Free or fixed rotation about the approach axis.
    pub rotation: GraspRotation,
    /// When the sampler stops drawing base poses (the caller's condition capped by the
    /// sampling budget).
    pub termination: Termination<'a>,
    pub lower: DVector<f64>,
    pub upper: DVector<f64>,
    /// The front shapes of the handle's part (all but the handle's own), which the contact
    /// shapes must not touch either: the stand-off keeps the fingertips off the front at the
    /// waypoints of a grasp along the normal, but not between them (the tool tilts a little
    /// along a joint-space segment) nor beside the axis of a grasp turned about a bar.
    pub front: Vec<usize>,
    /// The clearance the robot's links keep from each other
    /// ([`ManipulationSettings::self_margin`] capped by the resting configuration's, see
    /// [`rest_self_margin`]).
    pub self_margin: f64,
    /// Every scene part any check of this preparation found the robot within its margin of
    /// (a rejected IK restart's included): what its results depend on.
    met: RefCell<BTreeSet<PartId>>,
}

/// The self-clearance (m) the configurations of a manipulation keep: `wanted`, but at most
/// half the least clearance between the checked link pairs at `rest` (the arm's resting
/// configuration), so that a robot whose links sit close together at rest still has
/// configurations that keep it.
///
/// # Errors
/// [`PlacementError::Robot`] for a configuration of the wrong size.
pub(crate) fn rest_self_margin(
    problem: &PlacementProblem<'_>,
    wanted: f64,
    rest: &DVector<f64>,
) -> Result<f64, PlacementError> {
    if wanted <= 0.0 {
        return Ok(0.0);
    }
    let poses = problem.robot.link_poses(&RobotConfig {
        base: [0.0; 3],
        arm: rest.clone(),
    })?;
    let at_rest = problem.collision.self_clearance(&poses, 2.0 * wanted);
    Ok(wanted.min(0.5 * at_rest).max(0.0))
}

impl<'a> Prepared<'a> {
    /// `motion` prepared; the links keep `self_margin` from each other (the value of
    /// [`rest_self_margin`]).
    pub(crate) fn new(
        problem: PlacementProblem<'a>,
        motion: &'a JointMotion,
        rotation: GraspRotation,
        self_margin: f64,
    ) -> Result<Prepared<'a>, PlacementError> {
        let model = problem.model;
        let part = model
            .part(motion.joint.part())
            .ok_or(crate::scene::Error::UnknownId {
                kind: crate::scene::ElementKind::Joint,
                index: motion.joint.index(),
            })?;
        let moving = part.subtree().collect();
        let scene = (0..motion.len())
            .map(|k| {
                let mut data = SceneData::new(model);
                forward_kinematics(model, &mut data, &motion.state_at(problem.state, k))?;
                Ok(data)
            })
            .collect::<Result<Vec<_>, crate::scene::Error>>()?;
        let (lower, upper) = problem.robot.arm_bounds();
        if problem.ik.model().nq() != problem.robot.dof() {
            return Err(PlacementError::DimensionMismatch {
                what: "IK solver joints (robot dof)",
                expected: problem.robot.dof(),
                got: problem.ik.model().nq(),
            });
        }
        let front = handle_front_shapes(model, motion.handle)?;
        // A turned grasp keeps its fingers along the bar (see `JointMotion::turned_about_bar`).
        let rotation = if motion.grasp_angle == 0.0 {
            rotation
        } else {
            GraspRotation::Fixed
        };
        Ok(Prepared {
            front,
            reach: arm_reach(problem.robot),
            rotation,
            termination: Termination::none(),
            problem,
            motion,
            moving,
            scene,
            lower,
            upper,
            self_margin,
            met: RefCell::default(),
        })
    }

    /// Records that a check found the robot in the way of `body`, when it is a part.
    pub(crate) fn note(&self, body: Body) {
        if let Body::Part(part) = body {
            self.met.borrow_mut().insert(part);
        }
    }

    /// The scene parts any check of this preparation so far found the robot within its
    /// margin of, whatever became of the configuration (a later IK restart or candidate may
    /// have got round it): with these parts (and the moving part's ancestors) at the same
    /// values, every check gives the same answers, and so the deterministic planners on top
    /// give the same result whatever the other joints do.
    pub(crate) fn met_parts(&self) -> BTreeSet<PartId> {
        self.met.borrow().clone()
    }

    /// The first obstacle of the robot at `(base, q)` with the scene in `data`: two links
    /// within [`Prepared::self_margin`] of each other; any link within `margin` of the scene under the grasp contact rule (only the
    /// gripper's contact shapes may touch the moving parts, see [`Exempt::Grasp`]); the base
    /// links within `margin` of the moving parts (which the base must not be in the way of);
    /// a contact shape touching the handle's part's front.
    pub(crate) fn obstacle(
        &self,
        base: [f64; 3],
        q: &DVector<f64>,
        data: &SceneData,
        margin: f64,
    ) -> Result<Option<Obstacle>, PlacementError> {
        let p = &self.problem;
        let poses = p.robot.link_poses(&RobotConfig {
            base,
            arm: q.clone(),
        })?;
        let exempt = Exempt::Grasp(&self.moving);
        if let Some(o) = Obstacle::at(
            p.robot,
            p.collision,
            p.model,
            &poses,
            data,
            exempt,
            margin,
            self.self_margin,
        ) {
            if let Obstacle::Scene { body, .. } = &o {
                self.note(*body);
            }
            return Ok(Some(o));
        }
        let part = self.motion.handle.part();
        if let Some(link) = p
            .collision
            .contact_touches(&poses, p.model, data, part, &self.front)
        {
            return Ok(Some(Obstacle::scene(
                p.robot,
                p.model,
                (link, Body::Part(part)),
            )));
        }
        Ok(self.base_obstacle(&poses, data, margin).map(|hit| {
            self.note(hit.1);
            Obstacle::scene(p.robot, p.model, hit)
        }))
    }

    /// The base links (a prefix of `poses` up to the last of
    /// [`RobotCollision::base_links`](crate::kinematics::robot::RobotCollision::base_links))
    /// against the whole scene in `data`, moving parts included.
    pub(crate) fn base_obstacle(
        &self,
        poses: &[Isometry3<f64>],
        data: &SceneData,
        margin: f64,
    ) -> Option<(usize, Body)> {
        let p = &self.problem;
        let n = p.collision.base_links().iter().max().map_or(1, |m| m + 1);
        p.collision.scene_collision(
            &poses[..n.min(poses.len())],
            p.model,
            data,
            Exempt::Nothing,
            margin,
        )
    }

    /// Position and rotation error of the tool at `(base, q)` w.r.t. waypoint `k`, from the
    /// robot's forward kinematics: the distance to the grasp point, and the angle between tool
    /// +z and the approach direction beyond the approach cone (for [`GraspRotation::Fixed`],
    /// the angle of the full rotation error).
    pub(crate) fn tool_errors(
        &self,
        world_from_tool: &Isometry3<f64>,
        k: usize,
        settings: &ManipulationSettings,
    ) -> (f64, f64) {
        let g = &self.motion.grasps[k];
        let position = (world_from_tool.translation.vector - g.position.coords).norm();
        let angle = match self.rotation {
            GraspRotation::Free => {
                let z = world_from_tool.rotation * Vector3::z();
                (z.angle(&g.approach) - settings.approach_cone).max(0.0)
            }
            GraspRotation::Fixed => {
                (g.world_from_tool.rotation * world_from_tool.rotation.inverse()).angle()
            }
        };
        (position, angle)
    }

    /// Whether the tool follows the handle path from waypoint `k − 1` (at `prev`, the base at
    /// `from`) to `k` (at `q`, the base at `base`) with base pose and arm interpolated
    /// linearly: at `t = i/8`, `i = 1..=7`, within
    /// [`ManipulationSettings::tracking_tolerance`] of the straight line between the grasp
    /// points and with its approach axis within
    /// [`ManipulationSettings::tracking_angle`] of the normalised interpolated approach.
    pub(crate) fn tracks(
        &self,
        (from, base): ([f64; 3], [f64; 3]),
        prev: &DVector<f64>,
        q: &DVector<f64>,
        k: usize,
        settings: &ManipulationSettings,
    ) -> Result<bool, PlacementError> {
        let (a, b) = (&self.motion.grasps[k - 1], &self.motion.grasps[k]);
        for i in 1..8 {
            let t = i as f64 / 8.0;
            let tool = self.problem.robot.world_from_tool(&RobotConfig {
                base: [0, 1, 2].map(|j| from[j] + t * (base[j] - from[j])),
                arm: prev + (q - prev) * t,
            })?;
            let want = a.position.coords.lerp(&b.position.coords, t);
            let approach = a.approach.lerp(&b.approach, t);
            let z = tool.rotation * Vector3::z();
            if (tool.translation.vector - want).norm() > settings.tracking_tolerance
                || z.angle(&approach) > settings.tracking_angle + settings.approach_cone
            {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The tool at `(base, q)` off waypoint `k`'s grasp frame beyond the tolerances, or `q`
    /// outside the joint limits: [`WaypointFailure::OutOfTolerance`] (`None` otherwise).
    pub(crate) fn pose_failure(
        &self,
        base: [f64; 3],
        q: &DVector<f64>,
        k: usize,
        settings: &ManipulationSettings,
    ) -> Result<Option<WaypointFailure>, PlacementError> {
        let world_from_tool = self.problem.robot.world_from_tool(&RobotConfig {
            base,
            arm: q.clone(),
        })?;
        let (position_error, rotation_error) = self.tool_errors(&world_from_tool, k, settings);
        let in_limits = q
            .iter()
            .zip(self.lower.iter().zip(self.upper.iter()))
            .all(|(v, (lo, hi))| (*lo..=*hi).contains(v));
        let off = position_error > settings.position_tolerance
            || rotation_error > settings.rotation_tolerance
            || !in_limits;
        Ok(off.then_some(WaypointFailure::OutOfTolerance {
            position_error,
            rotation_error,
        }))
    }

    /// Checks waypoint `k` at `(base, q)` against everything but IK convergence: tolerance,
    /// limits, jump from `prev` (the previous reached configuration, if any), collisions at the
    /// waypoint and along the segment from `prev`.
    pub(crate) fn check_waypoint(
        &self,
        base: [f64; 3],
        q: &DVector<f64>,
        k: usize,
        prev: Option<&DVector<f64>>,
        settings: &ManipulationSettings,
        scratch: &mut SceneData,
    ) -> Result<Option<WaypointFailure>, PlacementError> {
        if let Some(f) = self.pose_failure(base, q, k, settings)? {
            return Ok(Some(f));
        }
        if let Some(prev) = prev {
            let (joint, jump) =
                (q - prev)
                    .iter()
                    .map(|d| d.abs())
                    .enumerate()
                    .fold(
                        (0, 0.0),
                        |best, (j, d)| if d > best.1 { (j, d) } else { best },
                    );
            if jump > settings.max_joint_jump && !self.tracks((base, base), prev, q, k, settings)? {
                return Ok(Some(WaypointFailure::Jump { joint, jump }));
            }
        }
        if let Some(o) = self.obstacle(base, q, &self.scene[k], settings.margin)? {
            return Ok(Some(WaypointFailure::Collision(o)));
        }
        if let Some(prev) = prev
            && let Some(o) =
                self.segment_collision((base, prev), (base, q), k, settings, scratch)?
        {
            return Ok(Some(WaypointFailure::SegmentCollision(o)));
        }
        Ok(None)
    }

    /// The first collision on the way from `(from, prev)` at waypoint `k − 1` to `(base, q)` at
    /// waypoint `k`: base pose, arm and the joint's value interpolated linearly, checked at
    /// steps of at most `segment_resolution` in every arm joint and in the base's motion (its
    /// translation plus its turn times its footprint radius, the farthest any base point
    /// moves; 0 for a fixed base).
    pub(crate) fn segment_collision(
        &self,
        (from, prev): ([f64; 3], &DVector<f64>),
        (base, q): ([f64; 3], &DVector<f64>),
        k: usize,
        settings: &ManipulationSettings,
        scratch: &mut SceneData,
    ) -> Result<Option<Obstacle>, PlacementError> {
        let p = &self.problem;
        let radius = p.robot.base().footprint_radius;
        let base_motion =
            (base[0] - from[0]).hypot(base[1] - from[1]) + (base[2] - from[2]).abs() * radius;
        let step = (q - prev).amax().max(base_motion);
        let n = (step / settings.segment_resolution).ceil() as usize;
        let (v0, v1) = (self.motion.values[k - 1], self.motion.values[k]);
        for i in 1..n {
            let t = i as f64 / n as f64;
            let qi = prev + (q - prev) * t;
            let mut s = p.state.clone();
            s.set_unchecked(self.motion.joint, v0 + t * (v1 - v0));
            forward_kinematics(p.model, scratch, &s)?;
            let bi = [0, 1, 2].map(|i| from[i] + t * (base[i] - from[i]));
            if let Some(o) = self.obstacle(bi, &qi, scratch, settings.margin)? {
                return Ok(Some(o));
            }
        }
        Ok(None)
    }

    /// The configuration for one waypoint and why it fails, if it does. Continuing from a
    /// reached waypoint: `solve_near` from it. Otherwise a full solve (restarts) from `start`;
    /// if it converges but fails a check (a collision, typically of the gripper with a
    /// neighbouring part), again from `start` with the last arm joint turned by `2π·i/n`,
    /// `i = 1 .. n − 1` (`n` = [`ManipulationSettings::roll_attempts`]; another roll about the
    /// approach axis for the usual wrist), keeping the first success or else the first result.
    pub(crate) fn solve_waypoint(
        &self,
        a: &Attempt<'_>,
        settings: &ManipulationSettings,
        ik_data: &mut IkData,
        scratch: &mut SceneData,
    ) -> Result<(DVector<f64>, Option<WaypointFailure>), PlacementError> {
        let ik = self.problem.ik;
        let attempts = if a.continuing.is_some() {
            1
        } else {
            settings.roll_attempts
        };
        let mut first = None;
        for i in 0..attempts {
            let outcome = match a.continuing {
                Some(prev) => ik.solve_near_with(ik_data, a.target, prev)?,
                None => ik.solve_with(ik_data, a.target, &self.rolled(a.start, i, attempts))?,
            };
            let result = match outcome {
                IkOutcome::Solved(IkSolution { mut q, .. }) => {
                    if a.k > 0 {
                        unwrap_continuous(self.problem.robot, &mut q, a.start);
                    }
                    let failure =
                        self.check_waypoint(a.base, &q, a.k, a.continuing, settings, scratch)?;
                    (q, failure)
                }
                IkOutcome::Infeasible(IkFailure { best, .. })
                | IkOutcome::Timeout(best)
                | IkOutcome::Cancelled(best) => {
                    let IkBest {
                        q: mut best,
                        position_error,
                        rotation_error,
                        ..
                    } = best;
                    if a.k > 0 {
                        unwrap_continuous(self.problem.robot, &mut best, a.start);
                    }
                    let failure = WaypointFailure::NotConverged {
                        position_error,
                        rotation_error,
                    };
                    // Restarts did not find the target: another seed will not either.
                    return Ok(first.unwrap_or((best, Some(failure))));
                }
            };
            if result.1.is_none() {
                let q = match a.continuing {
                    Some(_) => result.0,
                    None => self.roll_towards_start(a, result.0, settings, scratch)?,
                };
                return Ok((q, None));
            }
            first.get_or_insert(result);
        }
        Ok(first.expect("at least one attempt"))
    }

    /// At the first waypoint, `q` (reached) with its last joint turned to its value in
    /// `a.start` (clamped into its limits) when that configuration is reached too: on the
    /// usual wrist the last joint turns the tool about its approach axis, which a
    /// [`GraspRotation::Free`](super::GraspRotation::Free) grasp leaves free, so the arm need
    /// not turn it on its way from the stow. Every check of the waypoint decides (pose,
    /// limits, collisions); where the last joint moves the tool otherwise, the check fails and
    /// `q` is kept.
    fn roll_towards_start(
        &self,
        a: &Attempt<'_>,
        q: DVector<f64>,
        settings: &ManipulationSettings,
        scratch: &mut SceneData,
    ) -> Result<DVector<f64>, PlacementError> {
        let Some(last) = q.len().checked_sub(1) else {
            return Ok(q);
        };
        let want = a.start[last].clamp(self.lower[last], self.upper[last]);
        if a.k != 0 || (q[last] - want).abs() < 1e-9 {
            return Ok(q);
        }
        let mut turned = q.clone();
        turned[last] = want;
        Ok(
            match self.check_waypoint(a.base, &turned, a.k, None, settings, scratch)? {
                None => turned,
                Some(_) => q,
            },
        )
    }

    /// `seed` with its last joint turned by `2π·i/n`, clamped into its limits.
    fn rolled(&self, seed: &DVector<f64>, i: usize, n: usize) -> DVector<f64> {
        let mut q = seed.clone();
        if let Some(last) = q.len().checked_sub(1).filter(|_| i > 0) {
            q[last] = (q[last] + 2.0 * PI * i as f64 / n as f64)
                .clamp(self.lower[last], self.upper[last]);
        }
        q
    }

    /// IK along the trajectory at `base` (see [`plan_manipulation`](super::plan_manipulation)).
    /// Gives up (marking the rest [`WaypointFailure::Skipped`]) as `cutoff` says.
    pub(crate) fn plan(
        &self,
        base: [f64; 3],
        seed: &DVector<f64>,
        settings: &ManipulationSettings,
        cutoff: Cutoff,
    ) -> Result<ManipulationPlan, PlacementError> {
        let p = &self.problem;
        let n = self.motion.len();
        let world_from_base = RobotModel::world_from_base(base);
        let shoulder = world_from_base * self.reach.base_from_shoulder;
        let mut plan = ManipulationPlan {
            base,
            arm: Vec::with_capacity(n),
            reached: Vec::with_capacity(n),
            failures: Vec::with_capacity(n),
        };
        let mut scratch = SceneData::new(p.model);
        let mut ik_data = IkData::new(p.ik)?;
        for k in 0..n {
            let give_up = match cutoff {
                Cutoff::None => false,
                Cutoff::Reached(at_least) => plan.reached_count() + (n - k) < at_least,
                Cutoff::FirstMiss => plan.reached.iter().any(|r| !r),
            };
            if give_up {
                let last = plan.arm.last().cloned().unwrap_or_else(|| seed.clone());
                plan.arm.push(last);
                plan.reached.push(false);
                plan.failures.push(Some(WaypointFailure::Skipped));
                continue;
            }
            let prev_reached = plan.reached.last().copied().unwrap_or(false);
            let prev = plan.arm.last().cloned();
            let grasp = &self.motion.grasps[k];
            let distance = (grasp.position - shoulder).norm();
            let (q, failure) = if distance > self.reach.length {
                (
                    prev.clone().unwrap_or_else(|| seed.clone()),
                    Some(WaypointFailure::OutOfReach {
                        distance,
                        reach: self.reach.length,
                    }),
                )
            } else {
                let target = grasp.ik_target_in_cone(
                    &world_from_base,
                    self.rotation,
                    settings.approach_cone,
                );
                let continuing = prev.as_ref().filter(|_| prev_reached);
                let start = prev.as_ref().unwrap_or(seed);
                let attempt = Attempt {
                    base,
                    k,
                    target: &target,
                    continuing,
                    start,
                };
                self.solve_waypoint(&attempt, settings, &mut ik_data, &mut scratch)?
            };
            plan.arm.push(q);
            plan.reached.push(failure.is_none());
            plan.failures.push(failure);
        }
        Ok(plan)
    }
}
