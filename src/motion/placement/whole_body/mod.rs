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
//!    continuity bounds `|b_{k+1} − b_k|`), then the arm's joints. `solve_near` from "base
//!    unmoved, arm at the previous configuration" pulls every coordinate towards that seed in
//!    the null space of the task, so the base moves no more than the step needs.
//!
//! 3. **Backtracking.** If both fail at waypoint `k`, waypoints `k − 1 … k` are solved again
//!    with step 2 only (the base moving from the earlier waypoint on), then `k − 2 … k` and
//!    `k − 3 … k`; the arm alone may have left the arm in a posture (folded, at a limit) from
//!    which the base cannot help any more.
//!
//! So the base moves only where the arm alone cannot follow (a lexicographic preference for
//! the arm, rather than a weighted sum whose weight would have to be tuned per robot).
//!
//! # Verification
//! Every waypoint of the returned plan is re-checked without the whole-body model: the
//! robot's forward kinematics puts the tool on the grasp frame within
//! [`ManipulationSettings`]' tolerances, the arm is within its limits and moved no more than
//! `max_joint_jump`, the base moved within its step bounds (in the previous base frame) and,
//! for a differential-drive base, no more than [`WholeBodySettings::sideways_tolerance`]
//! across its heading (at the mean yaw of the two poses: the chord of the arc a differential
//! drive follows), the robot is free of self-collision, every link keeps `margin` from the
//! scene under the grasp contact rule and the base links from the whole scene (the grasped part
//! included); the same holds along the segment from the previous waypoint with the base pose,
//! the arm and the part's joint interpolated together (steps of at most `segment_resolution`
//! in every arm joint and in the base's sweep).

mod check;
mod model;

use std::fmt;

use nalgebra::DVector;

pub use check::sideways;

use super::GraspFrame;
use super::manipulation::{Attempt, Prepared, unwrap_continuous};
use super::plan::WaypointFailure;
use super::{
    GraspRotation, JointMotion, ManipulationSettings, PlacementError, PlacementProblem, check_arm,
};
use crate::InvalidSetting;
use crate::kinematics::ik::{IkData, IkOutcome, IkSolution, IkTarget};
use crate::kinematics::robot::RobotModel;
use crate::scene::SceneData;
use model::WholeBodyIk;

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
}

impl Default for WholeBodySettings {
    fn default() -> Self {
        WholeBodySettings {
            max_base_step: 0.15,
            max_yaw_step: 0.35,
            sideways_tolerance: 0.01,
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
/// [`WholeBodySettings`]) and the arm, solved near the previous configuration through four
/// intermediate grasp frames; if both fail, the last one to three waypoints are solved again
/// with the base moving. Every whole-body waypoint is verified without the IK model: the
/// robot's forward kinematics on the grasp frame, limits, joint jump, base step, sideways
/// motion of a differential-drive base (at the mean yaw), self-collision, the contact rule,
/// the base links against the whole scene, and the segment from the previous waypoint with
/// base, arm and part interpolated together. At the first waypoint the base may move from
/// `start` within the step bounds when the arm alone cannot reach it; no segment is checked
/// before it.
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
    let prepared = Prepared::new(problem, motion, rotation)?;
    let wb = WholeBodyIk::new(problem.robot, settings, problem.ik.settings())?;
    let mut run = Run {
        prepared: &prepared,
        wb: &wb,
        manipulation,
        settings,
        arm_data: IkData::new(problem.ik)?,
        wb_data: IkData::new(&wb.solver)?,
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
    let mut k = 0;
    while k < motion.len() {
        let prev = plan.bases.last().copied().zip(plan.arm.last());
        match run.waypoint(k, prev, start, seed, !forced.contains(&k))? {
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

/// A waypoint's base pose and arm configuration, or why there is none.
type Reached = Result<([f64; 3], DVector<f64>), WholeBodyFailure>;

/// The solvers and scratch of one [`plan_whole_body`].
struct Run<'a> {
    prepared: &'a Prepared<'a>,
    wb: &'a WholeBodyIk,
    manipulation: &'a ManipulationSettings,
    settings: &'a WholeBodySettings,
    arm_data: IkData,
    wb_data: IkData,
    scratch: SceneData,
}

impl Run<'_> {
    /// Waypoint `k` after `prev` (none at the first, which starts from `start` and `seed`):
    /// the arm alone, else base and arm.
    fn waypoint(
        &mut self,
        k: usize,
        prev: Option<([f64; 3], &DVector<f64>)>,
        start: [f64; 3],
        seed: &DVector<f64>,
        arm_first: bool,
    ) -> Result<Reached, PlacementError> {
        let p = self.prepared;
        let (from, from_q) = prev.unwrap_or((start, seed));
        let world_from_base = RobotModel::world_from_base(from);
        let target = p.motion.grasps[k].ik_target_in_cone(
            &world_from_base,
            p.rotation,
            self.manipulation.approach_cone,
        );
        let attempt = Attempt {
            base: from,
            k,
            target: &target,
            continuing: prev.map(|(_, q)| q),
            start: from_q,
        };
        if arm_first {
            let (q, failure) = p.solve_waypoint(
                &attempt,
                self.manipulation,
                &mut self.arm_data,
                &mut self.scratch,
            )?;
            if failure.is_none() {
                return Ok(Ok((from, q)));
            }
        }
        let solution = match prev {
            Some(_) => self.track(k, from, from_q)?,
            None => {
                let seed = self.wb.seed(from_q);
                match self
                    .wb
                    .solver
                    .solve_with(&mut self.wb_data, &target, &seed)?
                {
                    IkOutcome::Solved(IkSolution { q, .. }) => Ok(q),
                    IkOutcome::Infeasible(f) => Err(not_converged(&f.best)),
                    IkOutcome::Timeout(best) | IkOutcome::Cancelled(best) => {
                        Err(not_converged(&best))
                    }
                }
            }
        };
        let solution = match solution {
            Ok(q) => q,
            Err(failure) => return Ok(Err(failure)),
        };
        let (base, mut q) = self.wb.split(from, &solution);
        if prev.is_some() {
            unwrap_continuous(p.problem.robot, &mut q, from_q);
        }
        let failure = p.check_whole_body(
            prev,
            base,
            &q,
            k,
            (self.manipulation, self.settings),
            &mut self.scratch,
        )?;
        Ok(failure.map_or(Ok((base, q)), Err))
    }
}

impl Run<'_> {
    /// Whole-body IK for waypoint `k` from the base at `from` and the arm at `from_q` (the
    /// previous waypoint's): the grasp frame moved from waypoint `k − 1`'s to `k`'s in
    /// [`SUBSTEPS`] equal steps (positions and orientations interpolated), each solved near
    /// the previous result, so the base displacement grows with the handle's motion.
    fn track(
        &mut self,
        k: usize,
        from: [f64; 3],
        from_q: &DVector<f64>,
    ) -> Result<Result<DVector<f64>, WholeBodyFailure>, PlacementError> {
        let p = self.prepared;
        let world_from_base = RobotModel::world_from_base(from);
        let (a, b) = (&p.motion.grasps[k - 1], &p.motion.grasps[k]);
        let mut q = self.wb.seed(from_q);
        for i in 1..=SUBSTEPS {
            let t = i as f64 / SUBSTEPS as f64;
            let frame = GraspFrame {
                position: a.position + (b.position - a.position) * t,
                approach: a.approach.slerp(&b.approach, t),
                world_from_tool: a.world_from_tool.lerp_slerp(&b.world_from_tool, t),
            };
            let target = frame.ik_target_in_cone(
                &world_from_base,
                p.rotation,
                self.manipulation.approach_cone,
            );
            q = match self.near(&target, &q)? {
                Ok(q) => q,
                Err(failure) => return Ok(Err(failure)),
            };
        }
        Ok(Ok(q))
    }

    /// `solve_near` from `seed`, continued from its best configuration up to [`ROUNDS`] times
    /// while it does not converge (each round is one attempt of `max_iterations` steps).
    fn near(
        &mut self,
        target: &IkTarget,
        seed: &DVector<f64>,
    ) -> Result<Result<DVector<f64>, WholeBodyFailure>, PlacementError> {
        let mut seed = seed.clone();
        let mut last = None;
        for _ in 0..ROUNDS {
            let best = match self
                .wb
                .solver
                .solve_near_with(&mut self.wb_data, target, &seed)?
            {
                IkOutcome::Solved(IkSolution { q, .. }) => return Ok(Ok(q)),
                IkOutcome::Infeasible(f) => f.best,
                IkOutcome::Timeout(best) | IkOutcome::Cancelled(best) => best,
            };
            seed = best.q.clone();
            last = Some(not_converged(&best));
        }
        Ok(Err(last.expect("at least one round")))
    }
}

/// How many waypoints before a failed one are solved again with the base moving (the arm
/// alone may have left the arm where the base can no longer help).
const MAX_BACKTRACK: usize = 3;

/// Intermediate grasp frames per waypoint of the whole-body IK.
const SUBSTEPS: usize = 4;

/// `solve_near` rounds per intermediate frame.
const ROUNDS: usize = 3;

fn not_converged(best: &crate::kinematics::ik::IkBest) -> WholeBodyFailure {
    WholeBodyFailure::Waypoint(WaypointFailure::NotConverged {
        position_error: best.position_error,
        rotation_error: best.rotation_error,
    })
}
