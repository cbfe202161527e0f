//! Continuous certification of a timed arm phase ([`ContactWalk`]: conservative advancement
//! in time), so that no obstacle, however thin, is passed between two checked configurations.
//!
//! The dense re-checks and the timing's blend checks look at configurations a fixed spacing
//! apart; between two of them the robot moves by up to that spacing times its levers (a few
//! centimetres at the gripper), so a thin shelf or rod could lie between them unseen. The
//! walk follows the timed trajectory (blends included, as the robot will execute it) with
//! steps the exact distances allow, under the joints' velocity limits, which the timing keeps.
//! The base path (arm stowed) and a whole-body manipulation are walked the same way, the
//! base moving under its planar speed and yaw rate limits ([`WalkBase::Moving`]).

use std::cell::RefCell;

use super::refine::{Placed, StepRefinement};
use super::{Check, Failed, StepPath, StepReason};
use crate::kinematics::robot::{ContactWalk, Exempt, WalkBase, WalkOutcome};
use crate::motion::timing::TimedPath;
use crate::planner::PlannerError;
use crate::planner::timed::value_at;
use crate::scene::motion::motion_bound;
use crate::scene::{SceneData, forward_kinematics};

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
    /// The walk with the base `base` in the scene `data` under `exempt`, with joint speeds
    /// `vmax` ([`walk_speeds`]); the scene still.
    fn contact_walk<'w>(
        &'w self,
        base: WalkBase<'w>,
        data: &'w SceneData,
        exempt: Exempt<'w>,
        vmax: &'w [f64],
    ) -> ContactWalk<'w> {
        let ctx = self.ctx;
        ContactWalk {
            robot: ctx.robot,
            collision: ctx.collision,
            bound: ctx.speeds,
            model: ctx.model,
            data,
            exempt,
            base,
            joint_speed: vmax,
            max_steps: MAX_STEPS,
            scene_at: None,
            scene_speed: 0.0,
        }
    }

    /// The failure of a walk stopped at time `t` of `path` (failing as `check`, the path
    /// `which`), the contact named in `data` under `exempt`.
    #[allow(clippy::too_many_arguments)]
    fn walk_failure(
        &self,
        (check, which): (Check, StepPath),
        path: &TimedPath,
        t: f64,
        base: [f64; 3],
        data: &SceneData,
        exempt: Exempt<'_>,
        scene_joint: Option<f64>,
    ) -> Failed {
        let at = path.sample(t);
        let contact = self.arm_exact(base, data, exempt).describe(&at);
        self.fail(
            check,
            StepReason::Collision {
                path: which,
                segment: segment_at(path, t),
                at,
                scene_joint,
                contact,
            },
        )
    }

    /// Certifies `path` (failing as `check`) at base pose `base` over `stretches`; the
    /// failure names the configuration where the walk stopped.
    pub(super) fn certify(
        &self,
        path: &TimedPath,
        base: [f64; 3],
        stretches: &[Stretch<'_>],
        check: Check,
    ) -> Option<Failed> {
        let vmax = walk_speeds(self);
        let trajectory = |t: f64| path.sample(t);
        stretches.iter().find_map(|s| {
            let walk = self.contact_walk(WalkBase::Still(base), s.data, s.exempt, &vmax);
            match walk.first_contact(&trajectory, s.from, s.to) {
                WalkOutcome::Free { .. } => None,
                WalkOutcome::Contact { t } | WalkOutcome::TooClose { t } => {
                    Some(self.walk_failure((check, s.which), path, t, base, s.data, s.exempt, None))
                }
            }
        })
    }

    /// The base path `path` (arm stowed, the scene at the step's start state, nothing
    /// exempt) certified as the arm's phases are, the base moving under its limits
    /// ([`base_speeds`]); the failure names the base pose where the walk stopped.
    pub(super) fn certify_base(&self, path: &TimedPath) -> Option<Failed> {
        let pose = |t: f64| pose_at(path, t);
        let (linear, angular) = base_speeds(self);
        let still = vec![0.0; self.ctx.robot.dof()];
        let walk = self.contact_walk(
            WalkBase::Moving {
                pose: &pose,
                linear,
                angular,
            },
            &self.data,
            Exempt::Nothing,
            &still,
        );
        let stow: Vec<f64> = self.ctx.stow.iter().copied().collect();
        let t = match walk.first_contact(&|_| stow.clone(), 0.0, path.duration) {
            WalkOutcome::Free { .. } => return None,
            WalkOutcome::Contact { t } | WalkOutcome::TooClose { t } => t,
        };
        let at = pose(t);
        Some(self.fail(
            Check::BasePath,
            StepReason::Collision {
                path: StepPath::Base,
                segment: segment_at(path, t),
                at: at.to_vec(),
                scene_joint: None,
                contact: self.base_contact(&at),
            },
        ))
    }

    /// The manipulation `path` certified as the approach and retreat are, with the grasped
    /// part moving where the progress along the waypoints puts it ([`value_at`], as the dense
    /// re-check and the timing place it) and the grasp rule; every link's speed against the
    /// scene gains the most any point of the grasped part moves ([`Self::part_speed`]). A
    /// whole-body manipulation (`base_path`: the base's trajectory, in step with the arm's)
    /// has its base moving under its limits, and the progress is measured along the whole
    /// configurations `[x, y, yaw, q…]`, as its timing measures it.
    pub(super) fn certify_manipulation(
        &self,
        placed: &Placed,
        path: &TimedPath,
        base_path: Option<&TimedPath>,
    ) -> Result<Option<Failed>, PlannerError> {
        let model = self.ctx.model;
        let vmax = walk_speeds(self);
        let (linear, angular) = base_speeds(self);
        let (waypoints, speeds): (Vec<Vec<f64>>, Vec<f64>) = match base_path {
            None => (placed.waypoints().to_vec(), vmax.clone()),
            Some(_) => (
                placed
                    .waypoint_bases()
                    .iter()
                    .zip(placed.waypoints())
                    .map(|(b, q)| b.iter().chain(q).copied().collect())
                    .collect(),
                // The norm of the whole configuration's rate: planar speed, yaw rate, joints.
                [linear, angular]
                    .into_iter()
                    .chain(vmax.iter().copied())
                    .collect(),
            ),
        };
        let scene_speed = self.part_speed(&waypoints, &speeds)?;
        if !scene_speed.is_finite() {
            // The part moves where the robot does not: no speed bound, the dense re-check only.
            return Ok(None);
        }
        let (from, to) = (self.step.from, self.step.to);
        let pose = |t: f64| base_path.map_or(placed.base, |b| pose_at(b, t));
        let config = |t: f64| -> Vec<f64> {
            match base_path {
                None => path.sample(t),
                Some(b) => b.sample(t).into_iter().chain(path.sample(t)).collect(),
            }
        };
        let state = RefCell::new(self.state.clone());
        let value = |t: f64| value_at(&waypoints, &config(t), from, to);
        let scene_at = |t: f64, data: &mut SceneData| {
            let mut s = state.borrow_mut();
            s.set(model, self.joint, value(t)).is_ok()
                && forward_kinematics(model, data, &s).is_ok()
        };
        let base = match base_path {
            None => WalkBase::Still(placed.base),
            Some(_) => WalkBase::Moving {
                pose: &pose,
                linear,
                angular,
            },
        };
        let grasp = Exempt::Grasp(&self.grasped);
        let walk = ContactWalk {
            scene_at: Some(&scene_at),
            scene_speed,
            ..self.contact_walk(base, &self.data, grasp, &vmax)
        };
        let t = match walk.first_contact(&|t| path.sample(t), 0.0, path.duration) {
            WalkOutcome::Free { .. } => return Ok(None),
            WalkOutcome::Contact { t } | WalkOutcome::TooClose { t } => t,
        };
        let mut data = SceneData::new(model);
        if !scene_at(t, &mut data) {
            data.clone_from(&self.data);
        }
        Ok(Some(self.walk_failure(
            (Check::Manipulation, StepPath::Manipulation),
            path,
            t,
            pose(t),
            &data,
            grasp,
            Some(value(t)),
        )))
    }

    /// The most any point of the grasped part (and its descendants) moves per second while
    /// the robot follows `waypoints` with a rate whose Euclidean norm is at most that of
    /// `vmax`: the joint's rate times the scene's Lipschitz constant of the joint
    /// ([`motion_bound`]). Along waypoint segment `k` the part's value is `v_k + s·Δv_k` with
    /// `s` the configuration's projection onto the segment, whose rate is at most
    /// `|q̇| / |Δq_k|` (Euclidean norms): the joint's rate is at most
    /// `max_k |Δv_k|·|vmax| / |Δq_k|`. `+∞` when the part moves along a segment where the
    /// robot does not.
    fn part_speed(&self, waypoints: &[Vec<f64>], vmax: &[f64]) -> Result<f64, PlannerError> {
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
        let lipschitz = motion_bound(self.ctx.model, &self.data, self.joint)?.lipschitz();
        Ok(rate * lipschitz)
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

/// The base pose `[x, y, yaw]` of the base trajectory `path` at time `t`.
fn pose_at(path: &TimedPath, t: f64) -> [f64; 3] {
    let p = path.sample(t);
    [p[0], p[1], p[2]]
}

/// The walk's base speeds, planar (m/s) and yaw rate (rad/s): the length of the base's planar
/// velocity limits (a holonomic base's per-axis limits, a differential drive's forward
/// speed) and its yaw limit, with [`SPEED_SLACK`].
fn base_speeds(r: &StepRefinement<'_, '_>) -> (f64, f64) {
    let [vx, vy, w] = r.ctx.robot.base().max_velocity;
    (SPEED_SLACK * vx.hypot(vy), SPEED_SLACK * w.abs())
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
