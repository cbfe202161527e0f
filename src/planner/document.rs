//! The plan document with motion: the task plan document plus, per step, paths and timing.
//!
//! # Schema (JSON)
//! Every field of the task plan document ([`PlanFile`], see [`crate::task`]'s plan module)
//! at the top level, plus:
//! ```json
//! {
//!   "robot": "kinova_gen3_mobile",
//!   "duration": 41.2,                 // total execution time (s), steps one after another
//!   "task_plans": 2,                  // task orders proposed before one refined
//!   "motion": [                       // solved: one entry per step (per segment of a
//!                                     // segmented step), same order as "steps"
//!     { "joint": "dishwasher_door_hinge", "from": 0.0, "to": 1.2,
//!       "segment": 0, "segments": 1,  // this entry is segment 0 of 1 of its step
//!       "handle": "dishwasher_door_handle",
//!       "base": [1.7, 1.9, -1.57],    // base pose of the manipulation: x (m), y (m), yaw (rad)
//!       "timing": { "base": 6.1, "approach": 2.3, "manipulation": 4.0, "retreat": 2.2 },  // s
//!       "base_path":    { "times": [0.0, ...], "positions": [[x, y, yaw], ...] },
//!       "approach":     { "times": [...], "positions": [[q1, ..., q7], ...] },   // rad
//!       "pregrasp": 12,               // index in approach.positions: straight in from here
//!       "manipulation": { "times": [...], "positions": [...] },  // K+1 waypoints on the handle trajectory
//!       "retreat":      { "times": [...], "positions": [...] },
//!       "postgrasp": 10,              // index in retreat.positions: straight out up to here
//!       "mode": "fixed_base" | "segment" | "whole_body",
//!       "manipulation_base": { "times": [...], "positions": [[x, y, yaw], ...] },  // whole_body only
//!       "compared": { "segments": 31.0, "whole_body": 24.5 } }  // s; only when both refined
//!   ],
//!   "vetoes": [                        // moves the motion layer rejected, in the order found
//!     { "step": 0, "joint": "...", "from": 0.0, "to": 1.2,
//!       "check": "placement" | "base_path" | "approach" | "manipulation" | "retreat" | "stopped",
//!       "reason": "...",
//!       "segment": { "index": 1, "from": 0.6, "to": 1.2 } }  // only when a segment failed
//!   ]
//! }
//! ```
//! **Segments.** A step that no single base pose covers is executed in segments
//! ([`MotionPlan::segments`](super::MotionPlan::segments)): its entries in `"motion"` follow
//! each other, numbered `"segment"` 0 to `"segments"` − 1, each with its own `"from"` and
//! `"to"` (the first from the step's `"from"`, each next from the previous `"to"`, the last to
//! the step's `"to"`), base pose, paths and timing; each base path starts where the previous
//! entry's base pose is. An entry with `"segment": 0` begins the next step of `"steps"`.
//! Documents without these two fields read as one segment per step.
//!
//! **Whole-body manipulation.** An entry with `"mode": "whole_body"` moves the base during
//! the manipulation: `"manipulation_base"` holds its pose at each of the manipulation's
//! waypoints, with the same `times` (base and arm timed together); `"base"` is its first pose
//! (where the base path ends and the approach runs), its last is where the retreat runs and
//! the next entry's base path starts. Without `"mode"`, an entry reads as `"fixed_base"`.
//! `times` are the waypoints' times (s) from the start of the phase under the time
//! parameterisation ([`crate::motion::timing`]); positions between them follow its profile.

use serde::{Deserialize, Serialize};

use super::{
    Check, Compared, FailedSegment, MotionOutcome, MotionPlan, PlannerResult, StepFailure,
    StepMode, StepMotion, StepTiming,
};
use crate::motion::timing::TimedPath;
use crate::task::{Outcome, PlanFile, PlanResult, PlanStatus};

/// A timed path in the document: waypoints and their times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PathDocument {
    /// Time (s) of each waypoint from the start of the phase.
    pub times: Vec<f64>,
    /// The waypoints.
    pub positions: Vec<Vec<f64>>,
}

impl From<&TimedPath> for PathDocument {
    fn from(p: &TimedPath) -> Self {
        PathDocument {
            times: p.times.clone(),
            positions: p.positions.clone(),
        }
    }
}

/// The motion of one step in the document.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepDocument {
    /// The joint moved.
    pub joint: String,
    /// Its value before (rad or m); of the segment in a segmented step.
    pub from: f64,
    /// Its value after (rad or m); of the segment in a segmented step.
    pub to: f64,
    /// The index of this segment in its step (0 for an unsegmented step).
    #[serde(default)]
    pub segment: usize,
    /// The number of segments of its step, >= 1 (1: unsegmented).
    #[serde(default = "one")]
    pub segments: usize,
    /// The handle grasped.
    pub handle: String,
    /// Base pose of the manipulation: x (m), y (m), yaw (rad).
    pub base: [f64; 3],
    /// Execution times of the phases (s).
    pub timing: StepTiming,
    /// Base path (x, y, yaw).
    pub base_path: PathDocument,
    /// Arm: stowed to grasp.
    pub approach: PathDocument,
    /// Index in `approach.positions` of the pre-grasp configuration (the straight approach
    /// along the handle's normal starts there).
    pub pregrasp: usize,
    /// Arm along the handle trajectory.
    pub manipulation: PathDocument,
    /// Arm: back to stowed.
    pub retreat: PathDocument,
    /// Index in `retreat.positions` of the post-grasp configuration (the straight retreat
    /// along the handle's normal ends there).
    pub postgrasp: usize,
    /// How the manipulation was executed.
    #[serde(default)]
    pub mode: StepMode,
    /// The base poses (x, y, yaw) along a whole-body manipulation, one per waypoint of
    /// `manipulation`, same times.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub manipulation_base: Option<PathDocument>,
    /// The execution times of segments and whole-body when both refined.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compared: Option<Compared>,
}

fn one() -> usize {
    1
}

impl From<&StepMotion> for StepDocument {
    /// The entry of an unsegmented step (`segment` 0 of 1).
    fn from(s: &StepMotion) -> Self {
        StepDocument {
            joint: s.joint.clone(),
            from: s.from,
            to: s.to,
            segment: 0,
            segments: 1,
            handle: s.handle.clone(),
            base: s.base,
            timing: s.timing,
            base_path: (&s.base_path).into(),
            approach: (&s.approach).into(),
            pregrasp: s.pregrasp,
            manipulation: (&s.manipulation).into(),
            retreat: (&s.retreat).into(),
            postgrasp: s.postgrasp,
            mode: s.mode,
            manipulation_base: s.manipulation_base.as_ref().map(PathDocument::from),
            compared: s.compared,
        }
    }
}

/// The entries of a solved plan, numbered within their steps (each entry counts as a step of
/// its own if the plan's entries do not chain, see [`MotionPlan::segments`]).
fn step_documents(plan: &MotionPlan) -> Vec<StepDocument> {
    let mut out: Vec<StepDocument> = plan.steps.iter().map(StepDocument::from).collect();
    for range in plan.segments().unwrap_or_default() {
        let n = range.len();
        for (k, doc) in out[range].iter_mut().enumerate() {
            doc.segment = k;
            doc.segments = n;
        }
    }
    out
}

/// The plan document with motion (schema in the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MotionDocument {
    /// The task-level document: status, steps, cost, reason, conflicts, stats.
    #[serde(flatten)]
    pub plan: PlanFile,
    /// The robot's name.
    pub robot: String,
    /// Total execution time (s).
    #[serde(default)]
    pub duration: f64,
    /// Task orders proposed.
    #[serde(default)]
    pub task_plans: usize,
    /// Per step: paths and timing (solved only).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub motion: Vec<StepDocument>,
    /// Moves the motion layer vetoed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vetoes: Vec<VetoDocument>,
}

/// A vetoed move in a [`MotionDocument`]: a [`StepFailure`] with its reason rendered to text.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VetoDocument {
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
    /// Why, in one line ([`StepReason`](super::StepReason)'s text).
    pub reason: String,
    /// Where in a segmented step it failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub segment: Option<FailedSegment>,
}

impl From<&StepFailure> for VetoDocument {
    fn from(f: &StepFailure) -> Self {
        VetoDocument {
            step: f.step,
            joint: f.joint.clone(),
            from: f.from,
            to: f.to,
            check: f.check,
            reason: f.reason.to_string(),
            segment: f.segment,
        }
    }
}

fn vetoes(failures: &[StepFailure]) -> Vec<VetoDocument> {
    failures.iter().map(VetoDocument::from).collect()
}

impl MotionDocument {
    /// The document for a planner result.
    pub fn from_result(result: &PlannerResult, robot: &str) -> Self {
        let stats = result.task_stats.clone();
        let (plan, motion, vetoes, duration) = match &result.outcome {
            MotionOutcome::Solved(p) => {
                let file = PlanFile::from_result(&PlanResult {
                    outcome: Outcome::Solved(p.task.clone()),
                    stats,
                });
                let motion = step_documents(p);
                (file, motion, Vec::new(), p.duration())
            }
            MotionOutcome::Infeasible(why) => {
                let mut file = PlanFile::from_result(&PlanResult {
                    outcome: Outcome::Infeasible(why.task.clone()),
                    stats,
                });
                file.reason = Some(why.to_string());
                (file, Vec::new(), vetoes(&why.vetoes), 0.0)
            }
            MotionOutcome::Timeout(progress) | MotionOutcome::Cancelled(progress) => {
                let file = PlanFile {
                    status: if matches!(result.outcome, MotionOutcome::Cancelled(_)) {
                        PlanStatus::Cancelled
                    } else {
                        PlanStatus::Timeout
                    },
                    steps: Vec::new(),
                    cost: 0.0,
                    reason: Some(progress.to_string()),
                    conflicts: Vec::new(),
                    stats: Some(stats),
                };
                (file, Vec::new(), vetoes(&progress.vetoes), 0.0)
            }
        };
        MotionDocument {
            plan,
            robot: robot.to_string(),
            duration,
            task_plans: result.task_plans,
            motion,
            vetoes,
        }
    }

    /// Parses a document.
    ///
    /// # Errors
    /// serde_json's message (line and column).
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }

    /// The document as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}
