//! Continuous certification of a timed arm phase ([`ContactWalk`]: conservative advancement
//! in time), so that no obstacle, however thin, is passed between two checked configurations.
//!
//! The dense re-checks and the timing's blend checks look at configurations a fixed spacing
//! apart; between two of them the robot moves by up to that spacing times its levers (a few
//! centimetres at the gripper), so a thin shelf or rod could lie between them unseen. The
//! walk follows the timed trajectory (blends included, as the robot will execute it) with
//! steps the exact distances allow, under the joints' velocity limits, which the timing keeps.

use std::cell::RefCell;

use nalgebra::Vector3;

use super::refine::{Placed, StepRefinement};
use super::{Check, Failed, StepPath, StepReason};
use crate::kinematics::robot::{ContactWalk, Exempt, WalkOutcome};
use crate::motion::timing::TimedPath;
use crate::planner::PlannerError;
use crate::planner::timed::value_at;
use crate::scene::{JointKind, SceneData, forward_kinematics};

/// The walk's joint speeds: the velocity limits with this factor, which covers the timing's
/// round-off (its trajectories keep to the limits).
const SPEED_SLACK: f64 = 1.01;

/// Most configurations one stretch's walk looks at; one that needs more (it would have to
/// stay within a hair of something for long) is reported at the time it reached.
const MAX_STEPS: usize = 200_000;

/// One part of a phase to certify: the times `[from, to]` of the path, the scene and the
/// exemption that hold there, and which path it is (for the failure).
pub(super) struct Stretch<'d> {
    pub which: StepPath,
    pub from: f64,
    pub to: f64,
    pub data: &'d SceneData,
    pub exempt: Exempt<'d>,
}

impl StepRefinement<'_, '_> {
    /// Certifies `path` (failing as `check`) at base pose `base` over `stretches`; the
    /// failure names the configuration where the walk stopped.
    pub(super) fn certify(
        &self,
        path: &TimedPath,
        base: [f64; 3],
        stretches: &[Stretch<'_>],
        check: Check,
    ) -> Option<Failed> {
        let ctx = self.ctx;
        let bound = ctx.collision.motion_bound(ctx.robot);
        let vmax = walk_speeds(self);
        let trajectory = |t: f64| path.sample(t);
        for s in stretches {
            let walk = ContactWalk {
                robot: ctx.robot,
                collision: ctx.collision,
                bound: &bound,
                model: ctx.model,
                data: s.data,
                exempt: s.exempt,
                base,
                joint_speed: &vmax,
                max_steps: MAX_STEPS,
                scene_at: None,
                scene_speed: 0.0,
            };
            let t = match walk.first_contact(&trajectory, s.from, s.to) {
                WalkOutcome::Free { .. } => continue,
                WalkOutcome::Contact { t } | WalkOutcome::TooClose { t } => t,
            };
            let at = path.sample(t);
            let segment = segment_at(path, t);
            let contact = self.arm_exact(base, s.data, s.exempt).describe(&at);
            return Some(self.fail(
                check,
                StepReason::Collision {
                    path: s.which,
                    segment,
                    at,
                    scene_joint: None,
                    contact,
                },
            ));
        }
        None
    }
}

impl StepRefinement<'_, '_> {
    /// The fixed-base manipulation `path` certified as the approach and retreat are, with the
    /// grasped part moving where the arm's progress along the waypoints puts it
    /// ([`value_at`], as the dense re-check and the timing place it) and the grasp rule; every
    /// link's speed against the scene gains the most any point of the grasped part moves
    /// ([`Self::part_speed`]). A whole-body manipulation (the base moving too) is re-checked
    /// densely only.
    pub(super) fn certify_manipulation(
        &self,
        placed: &Placed,
        path: &TimedPath,
    ) -> Result<Option<Failed>, PlannerError> {
        if placed.bases.is_some() {
            return Ok(None);
        }
        let ctx = self.ctx;
        let model = ctx.model;
        let waypoints = placed.waypoints();
        let bound = ctx.collision.motion_bound(ctx.robot);
        let vmax = walk_speeds(self);
        let scene_speed = self.part_speed(waypoints, &vmax);
        if !scene_speed.is_finite() {
            // The part moves where the arm does not: no speed bound, the dense re-check only.
            return Ok(None);
        }
        let (from, to) = (self.step.from, self.step.to);
        let state = RefCell::new(self.state.clone());
        let scene_at = |t: f64, data: &mut SceneData| {
            let v = value_at(waypoints, &path.sample(t), from, to);
            let mut s = state.borrow_mut();
            s.set(model, self.joint, v).is_ok() && forward_kinematics(model, data, &s).is_ok()
        };
        let grasp = Exempt::Grasp(&self.grasped);
        let walk = ContactWalk {
            robot: ctx.robot,
            collision: ctx.collision,
            bound: &bound,
            model,
            data: &self.data,
            exempt: grasp,
            base: placed.base,
            joint_speed: &vmax,
            max_steps: MAX_STEPS,
            scene_at: Some(&scene_at),
            scene_speed,
        };
        let t = match walk.first_contact(&|t| path.sample(t), 0.0, path.duration) {
            WalkOutcome::Free { .. } => return Ok(None),
            WalkOutcome::Contact { t } | WalkOutcome::TooClose { t } => t,
        };
        let at = path.sample(t);
        let v = value_at(waypoints, &at, from, to);
        let mut s = self.state.clone();
        s.set(model, self.joint, v)?;
        let mut data = SceneData::new(model);
        forward_kinematics(model, &mut data, &s)?;
        let contact = self.arm_exact(placed.base, &data, grasp).describe(&at);
        Ok(Some(self.fail(
            Check::Manipulation,
            StepReason::Collision {
                path: StepPath::Manipulation,
                segment: segment_at(path, t),
                at,
                scene_joint: Some(v),
                contact,
            },
        )))
    }

    /// The most any point of the grasped part (and its descendants) moves per second while
    /// the arm follows `waypoints` with joint speeds at most `vmax`: the joint's rate times
    /// its lever (for a revolute joint the largest distance of a corner of the parts' world
    /// boxes from the axis, for a prismatic one 1). Along waypoint segment `k` the part's
    /// value is `v_k + s·Δv_k` with `s` the arm's projection onto the segment, whose rate is
    /// at most `|q̇| / |Δq_k|` (Euclidean norms): the joint's rate is at most
    /// `max_k |Δv_k|·|vmax| / |Δq_k|`. `+∞` when the part moves along a segment where the arm
    /// does not.
    fn part_speed(&self, waypoints: &[Vec<f64>], vmax: &[f64]) -> f64 {
        let ctx = self.ctx;
        let k = waypoints.len().saturating_sub(1).max(1);
        let dv = (self.step.to - self.step.from).abs() / k as f64;
        let speed = vmax.iter().map(|v| v * v).sum::<f64>().sqrt();
        let rate = waypoints
            .windows(2)
            .map(|w| {
                let dq = w[0]
                    .iter()
                    .zip(&w[1])
                    .map(|(a, b)| (b - a) * (b - a))
                    .sum::<f64>()
                    .sqrt();
                if dq > 0.0 {
                    dv * speed / dq
                } else if dv > 0.0 {
                    f64::INFINITY
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max);
        let Some(joint) = ctx.model.joint(self.joint) else {
            return f64::INFINITY;
        };
        let lever = match joint.kind {
            JointKind::Prismatic => 1.0,
            JointKind::Revolute => {
                let Some(frame) = self.data.world_from_joint(self.joint) else {
                    return f64::INFINITY;
                };
                let axis = frame.rotation * joint.axis.normalize();
                let origin = frame.translation.vector;
                let poses = self.data.world_from_parts();
                self.grasped
                    .iter()
                    .filter_map(|p| {
                        Some((
                            ctx.model.geometry.parts.get(p.index())?,
                            poses.get(p.index())?,
                        ))
                    })
                    .flat_map(|(shapes, pose)| shapes.iter().map(move |s| s.world_box(pose)))
                    .flat_map(|b| {
                        (0..8).map(move |c| {
                            Vector3::new(
                                if c & 1 == 0 { b.min.x } else { b.max.x },
                                if c & 2 == 0 { b.min.y } else { b.max.y },
                                if c & 4 == 0 { b.min.z } else { b.max.z },
                            )
                        })
                    })
                    .map(|corner| {
                        let r = corner - origin;
                        (r - axis * r.dot(&axis)).norm()
                    })
                    .fold(0.0, f64::max)
            }
        };
        rate * lever
    }
}

/// The index of the segment of `path` that time `t` is on.
fn segment_at(path: &TimedPath, t: f64) -> usize {
    path.times
        .iter()
        .rposition(|&tk| tk <= t)
        .unwrap_or(0)
        .min(path.positions.len().saturating_sub(2))
}

/// The walk's joint speeds: the velocity limits with [`SPEED_SLACK`].
fn walk_speeds(r: &StepRefinement<'_, '_>) -> Vec<f64> {
    r.ctx
        .robot
        .arm_joints()
        .iter()
        .map(|j| SPEED_SLACK * j.max_velocity)
        .collect()
}
