//! The verification of one whole-body waypoint, independent of the IK model that produced
//! it: the robot's own forward kinematics, the joint limits and jumps, the base's step and
//! (differential drive) sideways motion, and collisions at the waypoint and along the segment
//! from the previous one with base, arm and part interpolated together.

use nalgebra::DVector;

use super::{WholeBodyFailure, WholeBodySettings};
use crate::kinematics::robot::BaseKind;
use crate::motion::placement::manipulation::Prepared;
use crate::motion::placement::plan::WaypointFailure;
use crate::motion::placement::{ManipulationSettings, PlacementError};
use crate::scene::SceneData;

/// Slack on the base step bounds for the IK's round-off (m or rad).
const STEP_SLACK: f64 = 1e-9;

/// The previous waypoint's base pose and arm configuration.
pub(super) type Previous<'a> = Option<([f64; 3], &'a DVector<f64>)>;

/// The displacement from `from` to `to` in `from`'s base frame: forward (m), sideways (m),
/// turn (rad).
pub(crate) fn local_step(from: [f64; 3], to: [f64; 3]) -> [f64; 3] {
    let (dx, dy) = (to[0] - from[0], to[1] - from[1]);
    let (s, c) = from[2].sin_cos();
    [c * dx + s * dy, -s * dx + c * dy, to[2] - from[2]]
}

/// The sideways displacement from `from` to `to` (m): across the heading at their mean yaw,
/// the direction a differential-drive base moves along on the arc between them.
pub fn sideways(from: [f64; 3], to: [f64; 3]) -> f64 {
    let psi = 0.5 * (from[2] + to[2]);
    -psi.sin() * (to[0] - from[0]) + psi.cos() * (to[1] - from[1])
}

impl Prepared<'_> {
    /// Why waypoint `k` at `(base, q)` is not reached after `prev`, `None` if it is (see the
    /// [module docs](self)).
    pub(super) fn check_whole_body(
        &self,
        prev: Previous<'_>,
        base: [f64; 3],
        q: &DVector<f64>,
        k: usize,
        (manipulation, settings): (&ManipulationSettings, &WholeBodySettings),
        scratch: &mut SceneData,
    ) -> Result<Option<WholeBodyFailure>, PlacementError> {
        if let Some(f) = self.pose_failure(base, q, k, manipulation)? {
            return Ok(Some(WholeBodyFailure::Waypoint(f)));
        }
        if let Some((from, prev_q)) = prev {
            if let Some(f) = self.base_step_failure(from, base, settings) {
                return Ok(Some(f));
            }
            let (joint, jump) = (q - prev_q)
                .iter()
                .map(|d| d.abs())
                .enumerate()
                .fold((0, 0.0), |b, (j, d)| if d > b.1 { (j, d) } else { b });
            if jump > manipulation.max_joint_jump
                && !self.tracks((from, base), prev_q, q, k, manipulation)?
            {
                let failure = WaypointFailure::Jump { joint, jump };
                return Ok(Some(WholeBodyFailure::Waypoint(failure)));
            }
        }
        if let Some(o) = self.obstacle(base, q, &self.scene[k], manipulation.margin)? {
            return Ok(Some(WholeBodyFailure::Waypoint(
                WaypointFailure::Collision(o),
            )));
        }
        let Some(prev) = prev else {
            return Ok(None);
        };
        let hit = self.segment_collision(prev, (base, q), k, manipulation, scratch)?;
        Ok(hit.map(|o| WholeBodyFailure::Waypoint(WaypointFailure::SegmentCollision(o))))
    }

    /// The base's step from `from` to `to` beyond its bounds, or sideways for a
    /// differential-drive base.
    fn base_step_failure(
        &self,
        from: [f64; 3],
        to: [f64; 3],
        settings: &WholeBodySettings,
    ) -> Option<WholeBodyFailure> {
        let [forward, side, turn] = local_step(from, to);
        let translation = forward.abs().max(side.abs());
        if translation > settings.max_base_step + STEP_SLACK
            || turn.abs() > settings.max_yaw_step + STEP_SLACK
        {
            return Some(WholeBodyFailure::BaseStep {
                translation,
                turn: turn.abs(),
            });
        }
        let sideways = sideways(from, to).abs();
        let differential = self.problem.robot.base().kind == BaseKind::DifferentialDrive;
        (differential && sideways > settings.sideways_tolerance).then_some(
            WholeBodyFailure::Sideways {
                sideways,
                tolerance: settings.sideways_tolerance,
            },
        )
    }
}
