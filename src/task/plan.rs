//! Plans, outcomes and the plan document.
//!
//! # Plan file schema (JSON)
//! ```json
//! {
//!   "status": "solved",            // "solved" | "infeasible" | "timeout"
//!   "steps": [                     // solved: the plan; timeout: the best partial plan
//!     { "joint": "dishwasher_door", "from": 0.0, "to": 1.5708,
//!       "handle": "dishwasher_door_handle", "base": [1.2, -0.4, 1.57],
//!       "travel": 0.85, "cost": 1.92 }
//!   ],
//!   "cost": 1.92,                  // sum of step costs (m), see CostWeights
//!   "reason": null,                // infeasible / timeout: one-line explanation
//!   "conflicts": [],               // infeasible: the failed moves of goal joints, with causes
//!   "stats": { ... }               // search statistics
//! }
//! ```
//! Values are radians (revolute) or metres (prismatic); `base` is x (m), y (m), yaw (rad),
//! yaw facing the grasp point. Only `joint`, `from` and `to` are required when a plan is read
//! back (for `validate`).

use std::time::Duration;

use serde::{Deserialize, Serialize};

use super::Error;

/// One single-joint change θ_i of a plan Π.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Step {
    /// The joint moved.
    pub joint: String,
    /// Its value before the step (rad or m).
    pub from: f64,
    /// Its value after the step (rad or m).
    pub to: f64,
    /// The handle grasped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub handle: Option<String>,
    /// The base pose x (m), y (m), yaw (rad) the robot operates from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<[f64; 3]>,
    /// Length (m) of the grid path driven to `base`.
    #[serde(default)]
    pub travel: f64,
    /// Cost of the step (see [`CostWeights`](super::CostWeights)).
    #[serde(default)]
    pub cost: f64,
}

/// A sequence of single-joint changes.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// The steps, in execution order.
    pub steps: Vec<Step>,
    /// Total cost.
    pub cost: f64,
}

pub use super::shortfall::{ReachLimit, ReachShortfall};
pub use crate::scene::collision::BodyName;

/// Why one move (joint from → to, in some state) is infeasible.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Cause {
    /// The moving subtree hits another body during the sweep (check 1) or at the end state
    /// (check 3).
    Collision {
        /// The moving part that collides.
        moving: BodyName,
        /// What it collides with.
        other: BodyName,
        /// Joint value (rad or m) of the colliding sample.
        value: f64,
    },
    /// The sweep could not be certified free (the parts pass within the sweep resolution);
    /// treated as a collision.
    Inconclusive {
        /// The moving part nearest to contact.
        moving: BodyName,
        /// The body it nearly touches.
        other: BodyName,
        /// Joint value (rad or m).
        value: f64,
    },
    /// The part has no handle to grasp.
    NoHandle,
    /// No base position satisfies the manipulation region's reach and height limits clear of
    /// the base map and of the part's own sweep, whatever the other parts do.
    NoBasePose {
        /// The limit no free base cell meets, in numbers (filled in a search's report, for
        /// the handle that comes nearest; `None` in the move-by-move verdicts).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        shortfall: Option<Box<ReachShortfall>>,
    },
    /// Admissible base positions exist but the robot cannot drive to any of them: the listed
    /// parts' footprints close the way (each alone suffices to block, if any are listed).
    PathBlocked {
        /// Parts whose footprint blocks the path.
        blockers: Vec<String>,
    },
    /// Every reachable base position would be enclosed by the moved part: the robot could not
    /// drive back to its start afterwards.
    Trapped,
    /// The refinement layer vetoed the move.
    Vetoed {
        /// The refiner's reason.
        reason: String,
    },
}

impl std::fmt::Display for Cause {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Cause::Collision {
                moving,
                other,
                value,
            } => write!(f, "{moving} collides with {other} at {value:.4}"),
            Cause::Inconclusive {
                moving,
                other,
                value,
            } => write!(
                f,
                "{moving} passes too close to {other} at {value:.4} (sweep not certifiable)"
            ),
            Cause::NoHandle => f.write_str("the part has no handle"),
            Cause::NoBasePose { shortfall: None } => f.write_str("no base pose within reach"),
            Cause::NoBasePose { shortfall: Some(s) } => write!(f, "no base pose within reach: {s}"),
            Cause::PathBlocked { blockers } if blockers.is_empty() => {
                f.write_str("the robot's path is blocked")
            }
            Cause::PathBlocked { blockers } => {
                write!(f, "the robot's path is blocked by {}", blockers.join(", "))
            }
            Cause::Trapped => f.write_str("the move would trap the robot"),
            Cause::Vetoed { reason } => write!(f, "vetoed by refinement: {reason}"),
        }
    }
}

/// A failed move.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Failure {
    /// The joint.
    pub joint: String,
    /// Value before the move.
    pub from: f64,
    /// Value the move aimed at.
    pub to: f64,
    /// Why it is infeasible.
    pub cause: Cause,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "moving {:?} from {:.4} to {:.4}: {}",
            self.joint, self.from, self.to, self.cause
        )
    }
}

/// Why no plan exists in the lattice.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Infeasibility {
    /// One-line summary.
    pub message: String,
    /// Goal joints no explored state satisfied.
    pub unreached: Vec<String>,
    /// Failed moves of those goal joints towards their targets, one per (joint, cause),
    /// most frequent first.
    pub conflicts: Vec<Failure>,
    /// Pairs colliding already at the start state (bodies), if any.
    pub start_collisions: Vec<(BodyName, BodyName)>,
}

/// What the search has when the budget runs out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Partial {
    /// The plan to the explored state closest to the goal (fewest unmet targets, then lowest
    /// heuristic).
    pub plan: Plan,
    /// Goal joints that plan leaves unmet.
    pub unmet: Vec<String>,
}

/// The result of task planning: [`Solved`](crate::Outcome::Solved) with a plan that reaches
/// the goal (every step passed the feasibility checks), [`Infeasible`](crate::Outcome::Infeasible)
/// when no plan exists in the lattice (complete search, or the baseline's failure), or
/// [`Timeout`](crate::Outcome::Timeout) / [`Cancelled`](crate::Outcome::Cancelled) with the plan
/// to the explored state closest to the goal.
pub type Outcome = crate::Outcome<Plan, Infeasibility, Partial>;

impl std::fmt::Display for Infeasibility {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::fmt::Display for Partial {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} steps planned; unmet goal joints: {}",
            self.plan.steps.len(),
            self.unmet.join(", ")
        )
    }
}

/// Search statistics.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SearchStats {
    /// States expanded (closed).
    pub expanded: usize,
    /// Moves whose feasibility was evaluated.
    pub evaluated: usize,
    /// Sweep checks run (memo misses).
    pub sweeps: usize,
    /// Sweep checks answered from the memo.
    pub memo_hits: usize,
    /// Refiner calls that vetoed (each (state, move) is asked once).
    pub vetoes: usize,
    /// Rounds of the active-joint set (1 if no blocker outside the goal joints mattered).
    pub rounds: usize,
    /// Joints active in the last round.
    pub active_joints: usize,
    /// Orders sampled (baselines).
    pub samples: usize,
    /// Passes of the anytime search (1: the first plan was already within
    /// [`TaskSettings::heuristic_weight`](super::TaskSettings::heuristic_weight) of the bound;
    /// 2: a second pass tried to improve it). 0 for the baselines.
    #[serde(default)]
    pub passes: usize,
    /// Wall-clock time to the first plan found (the search's; `None` when none was found or
    /// for the baselines).
    #[serde(default, with = "opt_secs")]
    pub first_plan: Option<Duration>,
    /// Whether the search's first plan came from its greedy dive (goal joints straight to
    /// their targets, nearest handle first) rather than from the lattice search.
    #[serde(default)]
    pub greedy_first_plan: bool,
    /// Moves the partial-order reduction did not push
    /// ([`TaskSettings::reduction`](super::TaskSettings::reduction)): per expanded state, the
    /// lattice moves of active joints outside the reduced set.
    #[serde(default)]
    pub pruned: usize,
    /// For a plan the search returns: a proven factor `≥ 1` with cost ≤ factor × the least
    /// cost of any plan over the joints active at the end (1: minimal; see the [module
    /// docs](super#anytime)). `None` for other outcomes and for the baselines.
    #[serde(default)]
    pub suboptimality: Option<f64>,
    /// Wall-clock time.
    #[serde(with = "secs")]
    pub elapsed: Duration,
}

mod secs {
    use serde::{Deserialize, Deserializer, Serializer};
    use std::time::Duration;
    pub fn serialize<S: Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_f64(d.as_secs_f64())
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Duration, D::Error> {
        let v = f64::deserialize(d)?;
        Ok(Duration::try_from_secs_f64(v).unwrap_or_default())
    }
}

mod opt_secs {
    use serde::{Deserialize, Deserializer, Serializer};
    use std::time::Duration;
    pub fn serialize<S: Serializer>(d: &Option<Duration>, s: S) -> Result<S::Ok, S::Error> {
        match d {
            Some(d) => s.serialize_some(&d.as_secs_f64()),
            None => s.serialize_none(),
        }
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Duration>, D::Error> {
        let v = Option::<f64>::deserialize(d)?;
        Ok(v.and_then(|v| Duration::try_from_secs_f64(v).ok()))
    }
}

/// [`Outcome`] plus statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanResult {
    /// The outcome.
    pub outcome: Outcome,
    /// Statistics.
    pub stats: SearchStats,
}

/// `status` of a [`PlanFile`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlanStatus {
    /// A plan was found.
    Solved,
    /// No plan exists.
    Infeasible,
    /// The budget ran out.
    Timeout,
    /// The cancel flag stopped the search.
    Cancelled,
}

/// The plan document (see the module docs for the schema).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanFile {
    /// Solved, infeasible, timeout or cancelled.
    pub status: PlanStatus,
    /// The plan (solved) or best partial plan (timeout); empty when infeasible.
    pub steps: Vec<Step>,
    /// Total cost of `steps`.
    #[serde(default)]
    pub cost: f64,
    /// One-line explanation (infeasible, timeout).
    #[serde(default)]
    pub reason: Option<String>,
    /// Infeasible: the failed moves of goal joints.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub conflicts: Vec<Failure>,
    /// Search statistics.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stats: Option<SearchStats>,
}

impl PlanFile {
    /// The document for a planning result.
    pub fn from_result(result: &PlanResult) -> Self {
        let stats = Some(result.stats.clone());
        match &result.outcome {
            Outcome::Solved(plan) => PlanFile {
                status: PlanStatus::Solved,
                steps: plan.steps.clone(),
                cost: plan.cost,
                reason: None,
                conflicts: Vec::new(),
                stats,
            },
            Outcome::Infeasible(why) => PlanFile {
                status: PlanStatus::Infeasible,
                steps: Vec::new(),
                cost: 0.0,
                reason: Some(why.message.clone()),
                conflicts: why.conflicts.clone(),
                stats,
            },
            Outcome::Timeout(partial) | Outcome::Cancelled(partial) => PlanFile {
                status: if matches!(result.outcome, Outcome::Cancelled(_)) {
                    PlanStatus::Cancelled
                } else {
                    PlanStatus::Timeout
                },
                steps: partial.plan.steps.clone(),
                cost: partial.plan.cost,
                reason: Some(format!(
                    "{}; unmet goal joints: {}",
                    if matches!(result.outcome, Outcome::Cancelled(_)) {
                        "cancelled"
                    } else {
                        "budget exhausted"
                    },
                    partial.unmet.join(", ")
                )),
                conflicts: Vec::new(),
                stats,
            },
        }
    }

    /// Parses a plan document.
    ///
    /// # Errors
    /// [`Error::Parse`] with serde_json's message (line and column).
    pub fn from_json(text: &str) -> Result<Self, Error> {
        serde_json::from_str(text).map_err(|e| Error::Parse {
            what: "plan JSON".into(),
            message: e.to_string(),
        })
    }

    /// Reads the plan document at `path`.
    ///
    /// # Errors
    /// [`Error::Io`] if the file cannot be read; [`Error::InFile`] naming the file around
    /// [`Error::Parse`].
    pub fn from_file(path: impl AsRef<std::path::Path>) -> Result<Self, Error> {
        let path = path.as_ref();
        let text = super::goal::read_text(path)?;
        Self::from_json(&text).map_err(|e| super::goal::in_file(path, e))
    }

    /// The document as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }
}
