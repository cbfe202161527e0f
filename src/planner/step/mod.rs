//! Refining one single-joint change: base path, base pose, arm paths, manipulation, timing.
//!
//! The robot executes a step in five phases, one after the other:
//! 1. **base**: it drives from its pose to the placement's base pose with the arm stowed
//!    (OMPL in SE(2); the whole robot — base and stowed arm — against the base map and the parts
//!    at the current state, with the planner's margin). A differential-drive base follows the
//!    SE(2) path's positions by turning in place and driving straight
//!    ([`differential_drive`](crate::motion::paths::differential_drive)), every turn and drive
//!    checked densely with the same whole-robot check; if no such motion follows one SE(2) path,
//!    up to two more are planned (next seeds). Its path is timed exactly, without blends, under
//!    the forward speed and yaw rate
//!    ([`time_differential_drive`](crate::motion::timing::time_differential_drive));
//! 2. **approach**: the arm moves from the stowed configuration to the *pre-grasp*
//!    configuration (OMPL in joint space; nothing exempt: every robot shape keeps the margin
//!    from every body, the part about to be grasped included), then straight in along the
//!    handle's inward normal (or the grasp direction turned about a bar handle,
//!    `placement.bar_turn`) to the grasp, the first waypoint of the manipulation (the
//!    placement's approach, `placement.approach_distance`, chosen with the base pose);
//! 3. **manipulation**: the arm follows the joint-space trajectory that keeps the tool on the
//!    handle trajectory of Eq. (3)–(5) while the part moves with it;
//! 4. **retreat**: the arm backs straight out along the grasp direction in the new state to
//!    the *post-grasp* configuration, then returns to the stowed configuration (OMPL, nothing
//!    exempt);
//! 5. nothing else moves: the next step starts from the stowed arm at this base pose.
//!
//! **Segments.** A step that no single base pose covers is executed as consecutive segments,
//! each the phases above from a base pose of its own (the rule is in the
//! [planner's docs](crate::planner#segments); the code in `segment.rs`).
//!
//! **Whole-body manipulation.** With [`PlannerSettings::whole_body`], a step that no single
//! base pose covers may instead keep one grasp while the base moves along with the arm: phase
//! 1 drives to the base pose of the manipulation's first waypoint, phase 2 approaches there,
//! phase 3 moves base and arm together (a base pose per waypoint,
//! [`StepMotion::manipulation_base`]), and phase 4 retreats at the last waypoint's base pose,
//! where the next step starts ([`StepMotion::end_base`]); the rule is in the
//! [planner's docs](crate::planner#whole-body-manipulation), the code in `whole_body.rs`.
//!
//! **Contact rule.** From the pre-grasp through the manipulation to the post-grasp
//! configuration the robot is checked with [`Exempt::Grasp`](crate::kinematics::robot::Exempt::Grasp): only the gripper's contact
//! shapes (fingers, pads) may touch the grasped part and its descendants, and every other
//! shape keeps the margin from every body, the grasped part included. The grasp itself stops
//! the tool short of the handle where the fingertips would otherwise enter the part's front
//! (see [`JointMotion::with_standoff`](crate::motion::placement::JointMotion::with_standoff));
//! a grasp turned about a bar also keeps the fingers out of the part's front (each segment's
//! placement chooses its own grasp angle, the regrasp may change it).
//!
//! **Self-clearance.** The robot's checked link pairs keep a clearance from each other in
//! every phase: the placement's configurations keep
//! [`ManipulationSettings::self_margin`](crate::motion::placement::ManipulationSettings::self_margin)
//! (capped by half the stow's own), the re-checks under the contact rule half of that (they
//! sample more finely than the placement), the free paths to and from the stow the arm's
//! margin or half their ends' clearance.
//!
//! Every path is re-checked densely by
//! [`first_invalid`](crate::motion::paths::first_invalid) at the planner's resolution, with
//! the same collision model but none of OMPL's code (a disagreement is a failed step, not an
//! accepted one). Every phase is time-parameterised under the robot's velocity and
//! acceleration limits. Every timed phase is then certified continuously
//! ([`ContactWalk`](crate::kinematics::robot::ContactWalk), `certify.rs`): the base path
//! (arm stowed), the approach and retreat (stow to grasp and back, blends included) and the
//! manipulation (fixed-base or whole-body) are walked in time with steps no longer than the
//! exact distances allow under the joints' and the base's velocity limits (and, in the
//! manipulation, the grasped part's speed), so no obstacle, however thin, lies unseen between
//! two checked configurations; a contact found is a failed step.

mod arm;
mod certify;
mod reason;
mod refine;
mod segment;
mod shortcut;
mod timing;
mod whole_body;

pub use reason::{
    Contact, PlacementShortfall, SegmentMiss, SegmentTry, SplitMiss, StepPath, StepReason,
};

pub(super) use segment::refine;

use std::fmt;

use std::sync::Mutex;

use nalgebra::DVector;

use super::{PlannerError, PlannerSettings};
use crate::kinematics::ik::IkSolver;
use crate::kinematics::robot::{RobotCollision, RobotConfig, RobotModel, RobotSpheres, SpeedBound};
use crate::motion::paths::{PathFailure, PathOutcome};
use crate::motion::placement::PlacementData;
use crate::motion::timing::TimedPath;
use crate::scene::{JointId, PartId, SceneData, SceneModel, State, forward_kinematics};
use crate::task::{Robot, Step, Termination};

/// The check of a step that failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Check {
    /// No base pose from which the arm reaches every waypoint of the handle trajectory.
    Placement,
    /// No collision-free base path to the chosen base pose.
    BasePath,
    /// No collision-free arm path from the stowed configuration to the grasp (the free path
    /// to the pre-grasp configuration or the straight line in along the handle's normal).
    Approach,
    /// The manipulation trajectory failed the dense re-check.
    Manipulation,
    /// No collision-free arm path back to the stowed configuration (the straight line out
    /// along the handle's normal or the free path from the post-grasp configuration).
    Retreat,
    /// The budget ran out or the cancel flag was set during the step.
    Stopped,
}

impl fmt::Display for Check {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Check::Placement => "base placement",
            Check::BasePath => "base path",
            Check::Approach => "arm approach",
            Check::Manipulation => "manipulation",
            Check::Retreat => "arm retreat",
            Check::Stopped => "stopped",
        })
    }
}

/// A step that could not be refined: which step, which check, why.
#[derive(Debug, Clone, PartialEq)]
pub struct StepFailure {
    /// Index of the step in the task plan tried.
    pub step: usize,
    /// The joint moved.
    pub joint: String,
    /// Its value before the step.
    pub from: f64,
    /// Its target value.
    pub to: f64,
    /// The check that failed.
    pub check: Check,
    /// Why: the phase, the bodies by URDF name, the values (its `Display` is one line).
    pub reason: StepReason,
    /// Where in a segmented step it failed; `None` when the step was being refined as one
    /// segment (its placement, or the phases from the one base pose that covers it).
    pub segment: Option<FailedSegment>,
}

/// The segment of a step that failed (see [segments](crate::planner#segments)).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FailedSegment {
    /// Its index (0 for the first); the segments before it were refined.
    pub index: usize,
    /// The joint's value at its start (where the segments before it left the part).
    pub from: f64,
    /// The value it was to reach: a chosen segment end, or the step's target when the
    /// placement of the rest of the step failed.
    pub to: f64,
}

impl fmt::Display for StepFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "step {} ({:?} {:.4} -> {:.4}",
            self.step + 1,
            self.joint,
            self.from,
            self.to,
        )?;
        if let Some(s) = &self.segment {
            write!(f, ", segment {} {:.4} -> {:.4}", s.index + 1, s.from, s.to)?;
        }
        write!(f, "): {} failed: {}", self.check, self.reason)
    }
}

/// Execution times (s) of the phases of a step.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepTiming {
    /// Driving the base.
    pub base: f64,
    /// Arm from stowed to the grasp.
    pub approach: f64,
    /// Arm along the handle trajectory.
    pub manipulation: f64,
    /// Arm back to stowed.
    pub retreat: f64,
}

impl StepTiming {
    /// Arm time: approach, manipulation and retreat (the paper's Table I "Arm"; a
    /// whole-body manipulation counts here, the base moving with the arm).
    pub fn arm(&self) -> f64 {
        self.approach + self.manipulation + self.retreat
    }

    /// Base plus arm time.
    pub fn total(&self) -> f64 {
        self.base + self.arm()
    }
}

/// How a step's manipulation was executed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StepMode {
    /// From one base pose that covers the whole step (the paper's manipulation planner).
    #[default]
    FixedBase,
    /// As one of the segments of a step that no single base pose covers, each from a base
    /// pose of its own (see [segments](crate::planner#segments)).
    Segment,
    /// With the base moving along with the arm during the manipulation (see
    /// [whole-body manipulation](crate::planner#whole-body-manipulation)).
    WholeBody,
}

/// The execution times (s) of the two ways a step that no single base pose covers was
/// refined, when both succeeded: the planner kept the shorter (ties: the segments).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Compared {
    /// All its segments, phases summed ([`StepTiming::total`]).
    pub segments: f64,
    /// The whole-body execution, phases summed.
    pub whole_body: f64,
}

/// The motion of one step, or of one segment of a segmented step (see
/// [segments](crate::planner#segments)): `from` and `to` are then the segment's, and the next
/// segment starts where this one ends (its `from` is this `to`, its base path starts at this
/// `base`).
#[derive(Debug, Clone, PartialEq)]
pub struct StepMotion {
    /// The joint moved.
    pub joint: String,
    /// Its value before the step (segment).
    pub from: f64,
    /// Its value after the step (segment).
    pub to: f64,
    /// The handle grasped.
    pub handle: String,
    /// The base pose x (m), y (m), yaw (rad) of the manipulation: where the base path ends
    /// and the approach runs. For a whole-body manipulation, the base pose at its first
    /// waypoint ([`StepMotion::end_base`] is the last).
    pub base: [f64; 3],
    /// The base path (x, y, yaw waypoints), timed.
    pub base_path: TimedPath,
    /// The arm path from stowed to the first waypoint, timed: free to the pre-grasp
    /// configuration, then straight in along the handle's normal.
    pub approach: TimedPath,
    /// Index in `approach.positions` of the pre-grasp configuration: from it on, the gripper's
    /// contact shapes may touch the grasped part.
    pub pregrasp: usize,
    /// The arm configurations along the handle trajectory (K + 1 waypoints), timed.
    pub manipulation: TimedPath,
    /// The base poses (x, y, yaw) along the handle trajectory of a whole-body manipulation:
    /// one per waypoint of `manipulation`, with the same `times` and time law (base and arm
    /// were timed together; sample both at the same time). `None`: the base stands at `base`
    /// throughout.
    pub manipulation_base: Option<TimedPath>,
    /// The arm path back to stowed, timed: straight out along the handle's normal to the
    /// post-grasp configuration, then free.
    pub retreat: TimedPath,
    /// Index in `retreat.positions` of the post-grasp configuration: up to it, the gripper's
    /// contact shapes may touch the grasped part.
    pub postgrasp: usize,
    /// Execution times. For a whole-body manipulation, `timing.manipulation` is the time of
    /// base and arm together.
    pub timing: StepTiming,
    /// How the manipulation was executed.
    pub mode: StepMode,
    /// When the step could be executed both in segments and with the whole body: the two
    /// execution times (on every entry of the step).
    pub compared: Option<Compared>,
}

impl StepMotion {
    /// The base pose at the end of the manipulation, where the retreat runs and the next
    /// step's base path starts: the last of `manipulation_base`, else `base`.
    pub fn end_base(&self) -> [f64; 3] {
        self.manipulation_base
            .as_ref()
            .and_then(|p| p.positions.last())
            .map_or(self.base, |b| [b[0], b[1], b[2]])
    }
}

/// What every step needs.
pub(super) struct StepContext<'a> {
    pub robot: &'a RobotModel,
    pub collision: &'a RobotCollision,
    pub spheres: Option<&'a RobotSpheres>,
    pub speeds: &'a SpeedBound,
    pub ik: &'a IkSolver,
    pub settings: &'a PlannerSettings,
    pub model: &'a SceneModel,
    pub stow: &'a DVector<f64>,
    pub placement: &'a Mutex<PlacementData>,
    pub termination: &'a Termination<'a>,
}

/// The base pose the robot starts from when the problem does not give one.
pub(super) fn start_base_of(
    _model: &SceneModel,
    _state: &State,
    _first: &Step,
    robot: &Robot,
) -> Result<[f64; 3], PlannerError> {
    robot.base.ok_or(PlannerError::MissingBasePose)
}

/// The parts that the gripper's contact shapes may touch while it holds `joint`'s part.
fn grasped(model: &SceneModel, joint: JointId) -> Vec<PartId> {
    let part = joint.part();
    model
        .part(part)
        .map(|p| p.subtree().collect())
        .unwrap_or_default()
}

/// A failed step and the parts it depends on (`None`: unknown).
pub(super) type Failed = (StepFailure, Option<Vec<PartId>>);

/// What the robot touches at a base pose and arm configuration in a scene state, if anything.
type ManipulationHit<'a> = dyn Fn(&SceneData, [f64; 3], &[f64]) -> Option<Contact> + 'a;

/// Dense re-check of the manipulation: between consecutive waypoints the arm, the base pose
/// (`bases`, one per waypoint) and the joint are interpolated linearly together, at the
/// planner's arm resolution (and at most 0.01 rad or m of the scene joint per check; a moving
/// base at most the arm resolution in its sweep, the translation plus the turn times the
/// robot's planar reach, [`planar_reach`]). The reported configuration is the arm's, preceded
/// by the base pose when the base moves.
fn check_manipulation(
    ctx: &StepContext<'_>,
    state: &State,
    joint: JointId,
    step: &Step,
    (waypoints, bases): (&[Vec<f64>], &[[f64; 3]]),
    hit: &ManipulationHit<'_>,
) -> Result<Option<StepReason>, PlannerError> {
    let model = ctx.model;
    let k = waypoints.len().saturating_sub(1).max(1);
    let moving = bases.windows(2).any(|w| w[0] != w[1]);
    let lever = if moving {
        planar_reach(ctx, &waypoints[0])
    } else {
        0.0
    };
    let mut data = SceneData::new(model);
    let mut s = state.clone();
    for (i, pair) in waypoints.windows(2).enumerate() {
        let (a, b) = (&pair[0], &pair[1]);
        let (ba, bb) = (bases[i], bases[i + 1]);
        let va = step.from + (step.to - step.from) * i as f64 / k as f64;
        let vb = step.from + (step.to - step.from) * (i + 1) as f64 / k as f64;
        let arm_span = a
            .iter()
            .zip(b)
            .map(|(x, y)| (y - x).abs())
            .fold(0.0, f64::max);
        let sweep = (bb[0] - ba[0]).hypot(bb[1] - ba[1]) + (bb[2] - ba[2]).abs() * lever;
        let n = ((arm_span.max(sweep) / ctx.settings.arm_check_resolution)
            .max((vb - va).abs() / 0.01)
            .ceil() as usize)
            .max(1);
        for j in 0..=n {
            if i > 0 && j == 0 {
                continue;
            }
            let t = j as f64 / n as f64;
            let q: Vec<f64> = a.iter().zip(b).map(|(x, y)| x + (y - x) * t).collect();
            let base = [0, 1, 2].map(|c| ba[c] + (bb[c] - ba[c]) * t);
            let v = va + (vb - va) * t;
            s.set(model, joint, v)?;
            forward_kinematics(model, &mut data, &s)?;
            if let Some(contact) = hit(&data, base, &q) {
                let at = if moving {
                    base.iter().chain(&q).copied().collect()
                } else {
                    q
                };
                return Ok(Some(StepReason::Collision {
                    path: StepPath::Manipulation,
                    segment: i,
                    at,
                    scene_joint: Some(v),
                    contact,
                }));
            }
        }
    }
    Ok(None)
}

/// The largest distance (m) of any of the robot's link origins, or its footprint's edge, from
/// the base's vertical axis with the arm at `q`: how far a turn of the base by 1 rad moves
/// the robot's links, about.
fn planar_reach(ctx: &StepContext<'_>, q: &[f64]) -> f64 {
    let footprint = ctx.robot.base().footprint_radius;
    let cfg = RobotConfig {
        base: [0.0; 3],
        arm: DVector::from_column_slice(q),
    };
    ctx.robot.link_poses(&cfg).map_or(footprint, |poses| {
        poses
            .iter()
            .map(|p| p.translation.x.hypot(p.translation.y))
            .fold(footprint, f64::max)
    })
}

/// The first handle of `joint`'s part.
fn first_handle_name(model: &SceneModel, joint: JointId) -> Result<String, PlannerError> {
    let part = joint.part();
    model
        .handles()
        .find(|(id, _)| id.part() == part)
        .map(|(_, h)| h.name.clone())
        .ok_or_else(|| PlannerError::NoHandle {
            joint: model
                .joint(joint)
                .map(|j| j.name.clone())
                .unwrap_or_default(),
        })
}

/// The navigation grid's extent: x and y minima, x and y maxima (m).
fn grid_bounds(model: &SceneModel) -> ([f64; 2], [f64; 2]) {
    let g = model.base_grid();
    let o = g.origin();
    let r = g.resolution();
    (
        [o.x, o.y],
        [o.x + r * g.width() as f64, o.y + r * g.height() as f64],
    )
}

fn same_pose(a: &[f64; 3], b: &[f64; 3]) -> bool {
    (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9 && (a[2] - b[2]).abs() < 1e-9
}

/// The path of a path query, or why it returned none.
fn path_or_reason(
    outcome: PathOutcome,
    path: StepPath,
    (from, to): (&[f64], &[f64]),
    contact: &dyn Fn(&[f64]) -> Contact,
) -> Result<Vec<Vec<f64>>, Box<StepReason>> {
    Err(Box::new(match outcome {
        PathOutcome::Solved(p) => return Ok(p),
        PathOutcome::Infeasible(
            failure @ (PathFailure::InvalidStart | PathFailure::InvalidGoal),
        ) => {
            let goal = failure == PathFailure::InvalidGoal;
            let at = if goal { to } else { from };
            match contact(at) {
                // The goal out of the planner's bounds rather than touching anything.
                Contact::Unnamed => StepReason::NoPath { path, failure },
                contact => StepReason::BlockedEnd {
                    path,
                    goal,
                    at: at.to_vec(),
                    contact,
                },
            }
        }
        PathOutcome::Infeasible(failure) => StepReason::NoPath { path, failure },
        PathOutcome::Timeout(()) => StepReason::PathStopped {
            path,
            cancelled: false,
        },
        PathOutcome::Cancelled(()) => StepReason::PathStopped {
            path,
            cancelled: true,
        },
    }))
}
