//! Continuous certification of a timed arm phase ([`ContactWalk`]: conservative advancement
//! in time), so that no obstacle, however thin, is passed between two checked configurations.
//!
//! The dense re-checks and the timing's blend checks look at configurations a fixed spacing
//! apart; between two of them the robot moves by up to that spacing times its levers (a few
//! centimetres at the gripper), so a thin shelf or rod could lie between them unseen. The
//! walk follows the timed trajectory (blends included, as the robot will execute it) with
//! steps the exact distances allow, under the joints' velocity limits, which the timing keeps.

use super::refine::StepRefinement;
use super::{Check, Failed, StepPath, StepReason};
use crate::kinematics::robot::{ContactWalk, Exempt, WalkOutcome};
use crate::motion::timing::TimedPath;
use crate::scene::SceneData;

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
        let vmax: Vec<f64> = ctx
            .robot
            .arm_joints()
            .iter()
            .map(|j| SPEED_SLACK * j.max_velocity)
            .collect();
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
            };
            let t = match walk.first_contact(&trajectory, s.from, s.to) {
                WalkOutcome::Free { .. } => continue,
                WalkOutcome::Contact { t } | WalkOutcome::TooClose { t } => t,
            };
            let at = path.sample(t);
            let segment = path
                .times
                .iter()
                .rposition(|&tk| tk <= t)
                .unwrap_or(0)
                .min(path.positions.len().saturating_sub(2));
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
