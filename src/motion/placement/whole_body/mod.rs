//! Whole-body manipulation: the base moves along with the arm while the tool follows the grasp
//! frames, for handle trajectories that no single base pose covers (a wide door, a corner
//! door).
//!
//! # Method
//! Waypoint by waypoint ([`plan_whole_body`]):
//! 1. **Arm alone.** IK for the arm with the base where it stood at the previous waypoint
//!    (at the first, the given start), exactly as [`plan_manipulation`](super::plan_manipulation)
//!    does at a fixed base pose: `solve_near` from the previous configuration, every check of
//!    the fixed-base plan. If the waypoint is reached, the base does not move.
//! 2. **Base and arm.** Otherwise IK on a model whose root is the previous base frame and whose
//!    first joints are the base's displacement from it: forward, sideways (holonomic bases
//!    only: a differential-drive base gets no sideways joint) and yaw, bounded by
//!    [`WholeBodySettings::max_base_step`] and [`WholeBodySettings::max_yaw_step`] (the
//!    continuity bounds `|b_{k+1} − b_k|`), then the arm's joints. `solve_near` pulls every
//!    coordinate towards its seed in the null space of the task. Candidates, the first that
//!    passes every check kept:
//!    - *relaxed*: the tracked solution (next) with the arm moved towards the **posture** —
//!      the arm at the first waypoint — by at most [`WholeBodySettings::posture_step`] per
//!      joint, as the seed: the base takes up what the arm gives back, so the arm stays near
//!      a posture known to be collision-free instead of drifting, waypoint after waypoint,
//!      into a fold (forearm onto wrist) that the base cannot undo later;
//!    - *tracked*: from "base unmoved, arm at the previous configuration", the grasp frame
//!      moved there in four steps, so the base moves no more than the step needs;
//!    - *restricted* ([`WholeBodySettings::restricted_base_steps`]): both again with the
//!      base kept from moving the way the tracked solution moved it, one base coordinate at a
//!      time (its step bound cut at 0 on that side), then more coordinates as the new
//!      solutions move along them: the IK knows no collisions, so this steers a base step that
//!      meets the scene (or moves the arm into it) off that way.
//!
//!    The arm alone also gives way to these when it takes some joint farther than
//!    [`WholeBodySettings::posture_tolerance`] from the posture (and farther than the
//!    previous waypoint did); it is kept when none of them passes.
//!
//! 3. **Backtracking.** If both fail at waypoint `k`, waypoints `k − 1 … k` are solved again
//!    with step 2 only (the base moving from the earlier waypoint on), then `k − 2 … k` and
//!    `k − 3 … k`; the arm alone may have left the arm in a posture (folded, at a limit) from
//!    which the base cannot help any more.
//!
//! So the base moves where the arm alone cannot follow or would leave its posture (a
//! lexicographic preference for the arm, rather than a weighted sum whose weight would have
//! to be tuned per robot).
//!
//! # Verification
//! Every waypoint of the returned plan is re-checked without the whole-body model: the
//! robot's forward kinematics puts the tool on the grasp frame within
//! [`ManipulationSettings`]' tolerances, the arm is within its limits and moved no more than
//! `max_joint_jump` (more only where the tool, base and arm interpolated together, stays on
//! the handle path within `tracking_tolerance` and `tracking_angle`, as the fixed-base plan
//! allows: a wrist joint near its singularity turns fast while the tool follows), the base
//! moved within its step bounds (in the previous base frame) and,
//! for a differential-drive base, no more than [`WholeBodySettings::sideways_tolerance`]
//! across its heading (at the mean yaw of the two poses: the chord of the arc a differential
//! drive follows), the robot's links keep `self_margin` from each other (capped by half the
//! seed's clearance), every link keeps `margin` from the
//! scene under the grasp contact rule and the base links from the whole scene (the grasped part
//! included); the same holds along the segment from the previous waypoint with the base pose,
//! the arm and the part's joint interpolated together (steps of at most `segment_resolution`
//! in every arm joint and in the base's sweep).

mod check;
mod model;
mod run;
mod starts;

use std::fmt;

use nalgebra::DVector;

pub use check::sideways;
pub use starts::{WholeBodyAttempt, WholeBodyStart, plan_whole_body_from_starts};

use super::manipulation::{Prepared, rest_self_margin};
use super::plan::WaypointFailure;
use super::{
    GraspRotation, JointMotion, ManipulationSettings, PlacementError, PlacementProblem, check_arm,
};
use crate::InvalidSetting;
use crate::kinematics::ik::IkData;
use crate::scene::{PartId, SceneData};
use model::WholeBodyIk;
use run::{Origin, Run};

/// Settings of [`plan_whole_body`].
#[derive(Debug, Clone, PartialEq)]
pub struct WholeBodySettings {
    /// Largest base translation between consecutive waypoints along each axis of the previous
    /// base frame (m), > 0. Default 0.15.
    pub max_base_step: f64,
    /// Largest base turn between consecutive waypoints (rad), in `(0, π]`. Default 0.35.
    pub max_yaw_step: f64,
    /// Largest sideways displacement of a differential-drive base between consecutive
    /// waypoints (m, across the heading at the mean yaw), >= 0. Default 0.01.
    pub sideways_tolerance: f64,
    /// Largest move of each arm joint towards the posture (the arm at the first waypoint) per
    /// whole-body waypoint (rad or m): the relaxed candidate's seed. Finite and >= 0; 0 turns
    /// the relaxed candidate off. Default 0.1.
    pub posture_step: f64,
    /// An arm-alone solution that puts some joint farther than this from the posture (rad or
    /// m), and farther than the previous waypoint's configuration, gives way to a whole-body
    /// candidate when one passes (the base moves before the arm drifts into a fold). > 0
    /// (`INFINITY`: the arm alone whenever it reaches). Default 0.5.
    pub posture_tolerance: f64,
    /// Whether, when the relaxed and the tracked candidates fail (a base link or the arm
    /// against the scene: the IK knows no collisions), the waypoint is solved again with the
    /// base kept from moving the way it moved along one base coordinate (its step bound cut at
    /// 0 on that side), the coordinate it moved farthest along first, then also along the
    /// coordinates the new solutions move farthest along. Costs IK solves only where those
    /// candidates fail. Default true.
    pub restricted_base_steps: bool,
    /// How many starts (base poses) [`plan_whole_body_from_starts`] tries, in the order given
    /// (the planner: the best samples of the longest-prefix placement), in `1..=64`.
    /// Default 4.
    pub starts: usize,
    /// How many arm seeds [`plan_whole_body_from_starts`] tries per start: the start's own,
    /// then configurations drawn within the joint limits, in `1..=64`. Default 3.
    pub arm_seeds: usize,
    /// Seed of the generator drawing those arm seeds. Default 0x7762 ("wb").
    pub seed: u64,
}

impl Default for WholeBodySettings {
    fn default() -> Self {
        WholeBodySettings {
            max_base_step: 0.15,
            max_yaw_step: 0.35,
            sideways_tolerance: 0.01,
            posture_step: 0.1,
            posture_tolerance: 0.5,
            restricted_base_steps: true,
            starts: 4,
            arm_seeds: 3,
            seed: 0x7762,
        }
    }
}

impl WholeBodySettings {
    /// Checks every field's range.
    ///
    /// # Errors
    /// [`PlacementError::InvalidSetting`] naming the field.
    pub fn validate(&self) -> Result<(), PlacementError> {
        let s = self;
        if !(s.max_base_step.is_finite() && s.max_base_step > 0.0) {
            return Err(
                InvalidSetting::new("max_base_step", s.max_base_step, "finite and > 0").into(),
            );
        }
        if !(s.max_yaw_step > 0.0 && s.max_yaw_step <= std::f64::consts::PI) {
            return Err(InvalidSetting::new("max_yaw_step", s.max_yaw_step, "in (0, pi]").into());
        }
        if !(s.sideways_tolerance.is_finite() && s.sideways_tolerance >= 0.0) {
            let t = s.sideways_tolerance;
            return Err(InvalidSetting::new("sideways_tolerance", t, "finite and >= 0").into());
        }
        if !(s.posture_step.is_finite() && s.posture_step >= 0.0) {
            let t = s.posture_step;
            return Err(InvalidSetting::new("posture_step", t, "finite and >= 0").into());
        }
        if s.posture_tolerance.is_nan() || s.posture_tolerance <= 0.0 {
            let t = s.posture_tolerance;
            return Err(InvalidSetting::new("posture_tolerance", t, "> 0").into());
        }
        if !(1..=64).contains(&s.starts) {
            return Err(InvalidSetting::new("starts", s.starts as f64, "in 1..=64").into());
        }
        if !(1..=64).contains(&s.arm_seeds) {
            return Err(InvalidSetting::new("arm_seeds", s.arm_seeds as f64, "in 1..=64").into());
        }
        Ok(())
    }
}

/// Base poses and arm configurations along the grasp frames.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WholeBodyPlan {
    /// The base pose at each waypoint: x (m), y (m), yaw (rad).
    pub bases: Vec<[f64; 3]>,
    /// The arm configuration at each waypoint.
    pub arm: Vec<DVector<f64>>,
}

impl WholeBodyPlan {
    /// Distance (m) the base drives, summed over the waypoints.
    pub fn base_travel(&self) -> f64 {
        self.bases
            .windows(2)
            .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
            .sum()
    }

    /// Number of waypoints at which the base stands elsewhere than at the previous one.
    pub fn base_moves(&self) -> usize {
        self.bases.windows(2).filter(|w| w[0] != w[1]).count()
    }
}

/// Why a waypoint of a whole-body plan fails.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq)]
pub enum WholeBodyFailure {
    /// A check the fixed-base plan makes too (IK, tolerance, limits, jump, collision).
    Waypoint(WaypointFailure),
    /// The base moved more than the step bounds allow.
    BaseStep {
        /// Largest translation along an axis of the previous base frame (m).
        translation: f64,
        /// Turn (rad, absolute).
        turn: f64,
    },
    /// A differential-drive base moved sideways.
    Sideways {
        /// Displacement across the heading (m, absolute).
        sideways: f64,
        /// The tolerance (m).
        tolerance: f64,
    },
}

impl fmt::Display for WholeBodyFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WholeBodyFailure::Waypoint(w) => write!(f, "{w}"),
            WholeBodyFailure::BaseStep { translation, turn } => write!(
                f,
                "the base steps {translation:.3} m and {turn:.3} rad, beyond its step bounds"
            ),
            WholeBodyFailure::Sideways {
                sideways,
                tolerance,
            } => write!(
                f,
                "the differential-drive base moves {sideways:.4} m sideways (tolerance \
                 {tolerance:.4} m)"
            ),
        }
    }
}

/// The result of [`plan_whole_body`].
#[derive(Debug, Clone, PartialEq)]
pub enum WholeBodyOutcome {
    /// Every waypoint reached.
    Tracked(WholeBodyPlan),
    /// A waypoint could not be reached with the base and arm together.
    Failed {
        /// The first waypoint not reached.
        waypoint: usize,
        /// Why (the whole-body attempt's failure).
        failure: WholeBodyFailure,
        /// The waypoints before it, as reached before backtracking.
        reached: WholeBodyPlan,
        /// The scene parts any check of the attempt found the robot within the margin of
        /// (rejected candidates' included), sorted: with these parts (and the moving part's
        /// ancestors) at the same values the attempt fails the same way whatever the other
        /// joints do.
        obstacles: Vec<PartId>,
    },
}

impl WholeBodyOutcome {
    /// The plan, if every waypoint is reached.
    pub fn plan(&self) -> Option<&WholeBodyPlan> {
        match self {
            WholeBodyOutcome::Tracked(plan) => Some(plan),
            WholeBodyOutcome::Failed { .. } => None,
        }
    }

    /// The scene parts the failed attempt depends on (see [`WholeBodyOutcome::Failed`]);
    /// none when tracked.
    pub fn obstacles(&self) -> &[PartId] {
        match self {
            WholeBodyOutcome::Tracked(_) => &[],
            WholeBodyOutcome::Failed { obstacles, .. } => obstacles,
        }
    }

    /// Why it failed, with the waypoint; `None` when tracked.
    pub fn reason(&self) -> Option<String> {
        match self {
            WholeBodyOutcome::Tracked(_) => None,
            WholeBodyOutcome::Failed {
                waypoint, failure, ..
            } => Some(format!("whole-body: waypoint {waypoint}: {failure}")),
        }
    }
}

/// Base poses and arm configurations that put the tool on every grasp frame of `motion`,
/// starting from the base at `start` with the first IK seeded at `seed`. Per waypoint: the
/// arm alone at the previous base pose (the fixed-base plan's IK and checks); else one IK over
/// the base's displacement (forward, sideways for a holonomic base only, yaw; bounded by
/// [`WholeBodySettings`]) and the arm: relaxed towards the first waypoint's arm posture, or
/// near the previous configuration through four intermediate grasp frames, or either with the
/// base kept from the way it moved (the arm alone also gives way to these when it leaves the
/// posture);
/// if all fail, the last one to three waypoints are solved again with the base moving. Every whole-body waypoint is verified without the IK model: the
/// robot's forward kinematics on the grasp frame, limits, joint jump, base step, sideways
/// motion of a differential-drive base (at the mean yaw), self-collision, the contact rule,
/// the base links against the whole scene, and the segment from the previous waypoint with
/// base, arm and part interpolated together. At the first waypoint the base may move from
/// `start` within the step bounds when the arm alone cannot reach it; no segment is checked
/// before it. The straight approach after its first waypoint and the straight retreat keep the
/// base still: the arm alone moves the tool in and out along the handle's normal.
///
/// # Errors
/// [`PlacementError::InvalidSetting`] for bad settings, [`PlacementError::NonFinite`] for a
/// non-finite `start`, [`PlacementError::DimensionMismatch`] / [`PlacementError::NonFinite`]
/// for a bad seed, [`PlacementError::Scene`] if `motion` is not from `problem.model`,
/// [`PlacementError::Ik`] / [`PlacementError::Pinocchio`] when a backend fails. A waypoint
/// that cannot be reached is [`WholeBodyOutcome::Failed`].
pub fn plan_whole_body(
    problem: PlacementProblem<'_>,
    motion: &JointMotion,
    start: [f64; 3],
    seed: &DVector<f64>,
    rotation: GraspRotation,
    manipulation: &ManipulationSettings,
    settings: &WholeBodySettings,
) -> Result<WholeBodyOutcome, PlacementError> {
    manipulation.validate()?;
    settings.validate()?;
    if start.iter().any(|v| !v.is_finite()) {
        return Err(PlacementError::NonFinite { what: "start" });
    }
    check_arm(problem.robot, seed, "arm seed")?;
    let self_margin = rest_self_margin(&problem, manipulation.self_margin, seed)?;
    let prepared = Prepared::new(problem, motion, rotation, self_margin)?;
    let wb = WholeBodyIk::new(problem.robot, settings);
    let mut run = Run {
        prepared: &prepared,
        solvers: (0..wb.patterns()).map(|_| None).collect(),
        wb,
        manipulation,
        settings,
        arm_data: IkData::new(problem.ik)?,
        scratch: SceneData::new(problem.model),
    };
    let mut plan = WholeBodyPlan::default();
    // The first failure not yet overcome, how far back the base was made to move earlier,
    // and the waypoints where the arm-alone attempt is skipped.
    let mut failed: Option<(usize, WholeBodyFailure)> = None;
    let mut back = 0;
    let mut forced = 0..0;
    // The waypoints reached before the first failure not overcome.
    let mut kept = WholeBodyPlan::default();
    // The straight approach (after its first waypoint) and the straight retreat run at one
    // base pose each: the robot moves in and out along the handle's normal with the base still.
    let trajectory = motion.trajectory();
    let base_fixed = |k: usize| k > 0 && (k <= *trajectory.start() || k > *trajectory.end());
    let mut k = 0;
    while k < motion.len() {
        let origin = Origin {
            prev: plan.bases.last().copied().zip(plan.arm.last()),
            start: (start, seed),
            posture: plan.arm.first(),
            arm_first: !forced.contains(&k),
            base_fixed: base_fixed(k),
        };
        match run.waypoint(k, &origin)? {
            Ok((base, q)) => {
                plan.bases.push(base);
                plan.arm.push(q);
                k += 1;
                if failed.as_ref().is_some_and(|(at, _)| k > *at) {
                    (failed, back) = (None, 0);
                }
            }
            Err(failure) => {
                if failed.is_none() {
                    kept = plan.clone();
                }
                let at = failed.get_or_insert((k, failure)).0;
                back += 1;
                if back > MAX_BACKTRACK || back > at {
                    let (waypoint, failure) = failed.expect("set above");
                    return Ok(WholeBodyOutcome::Failed {
                        waypoint,
                        failure,
                        reached: kept,
                        obstacles: prepared.met_parts().into_iter().collect(),
                    });
                }
                k = at - back;
                plan.bases.truncate(k);
                plan.arm.truncate(k);
                forced = k..at + 1;
            }
        }
    }
    Ok(WholeBodyOutcome::Tracked(plan))
}

/// How many waypoints before a failed one are solved again with the base moving (the arm
/// alone may have left the arm where the base can no longer help).
const MAX_BACKTRACK: usize = 3;
