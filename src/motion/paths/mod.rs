//! Base paths in SE(2) and arm paths in joint space with OMPL, and an independent dense
//! re-check of any path.
//!
//! A thin layer over [`kinscene_ompl`]: [`plan_base`] plans a planar pose `[x, y, yaw]` in a
//! box of the floor (yaw free, wrapping), [`plan_arm`] plans joint values in a box (continuous
//! joints get a finite window, see [`CONTINUOUS_JOINT_WINDOW`]). Validity is a Rust closure
//! the caller gives (the robot's collision check); the planner, the motion validator, the
//! simplifier are OMPL's. Bad input is a [`PathError`]; not finding a path is a
//! [`PathOutcome`].
//!
//! [`differential_drive`] turns an SE(2) path into turn-in-place and drive-straight pieces for
//! a differential-drive base ([`BaseKind::DifferentialDrive`](crate::kinematics::robot::BaseKind)),
//! each piece checked by the caller's motion check.
//!
//! [`first_invalid`] re-checks a returned path with code that shares nothing with OMPL's motion
//! validator: every segment is sampled at a fixed spacing and handed to the closure.
//!
//! # Path conventions
//! Consecutive states are joined by straight lines in the coordinates; for the base, yaw is
//! *unwrapped* along the path (the first state is `start` exactly and consecutive yaws differ
//! by at most π), so the straight line between two states is the shortest-angle SE(2)
//! interpolation OMPL checked. The last state equals `goal` up to OMPL's goal tolerance
//! (1e-6) and, for the base, a multiple of 2π in yaw.
//!
//! # Example
//! ```
//! use std::time::Duration;
//! use kinscene::Termination;
//! use kinscene::motion::paths::{PathOutcome, PathSettings, first_invalid, plan_base};
//!
//! // A 4 m × 4 m room with a wall x ∈ [1.9, 2.1], y ≤ 3; a disc base of radius 0.2 m.
//! let free = |q: &[f64; 3]| {
//!     let dx = (1.9 - q[0]).max(q[0] - 2.1).max(0.0);
//!     let dy = (q[1] - 3.0).max(0.0);
//!     dx.hypot(dy) > 0.2
//! };
//! let settings = PathSettings { seed: Some(7), ..PathSettings::default() };
//! let outcome = plan_base([1.0, 1.0, 0.0], [3.0, 1.0, 1.5], ([0.0, 0.0], [4.0, 4.0]),
//!                         &free, &settings, &Termination::none())?;
//! let PathOutcome::Solved(path) = outcome else { panic!("{outcome:?}") };
//! assert_eq!(path[0], vec![1.0, 1.0, 0.0]);
//! // Independent re-check at a fifth of the planner's spacing.
//! let free_slice = |q: &[f64]| free(&[q[0], q[1], q[2]]);
//! assert_eq!(first_invalid(&path, settings.resolution / 5.0, true, &free_slice), None);
//! # Ok::<(), kinscene::motion::paths::PathError>(())
//! ```

mod differential;
mod error;
mod plan;
mod recheck;

use std::time::Duration;

use crate::InvalidSetting;

pub use differential::{
    DifferentialFailure, SAME_POSITION, STRAIGHT_IN, STRAIGHT_OUT, differential_drive,
};
pub use error::PathError;
pub use kinscene_ompl::{Planner, Simplifier};
pub use plan::{
    ARM_RANGE, CONTINUOUS_JOINT_WINDOW, MotionCheck, plan_arm, plan_arm_checked,
    plan_arm_with_motion, plan_base,
};
pub use recheck::first_invalid;

/// How to plan a path.
#[derive(Debug, Clone, PartialEq)]
pub struct PathSettings {
    /// The OMPL planner. Default RRTConnect.
    pub planner: Planner,
    /// Wall-clock budget for planning and simplification together, capping the caller's
    /// [`Termination`](crate::Termination) for one path. Default 1 s.
    pub budget: Duration,
    /// Validity-check spacing along motions, in the space's distance (SE(2): metres plus
    /// half the yaw difference in radians, OMPL's weighting; joint space: the Euclidean norm,
    /// radians or metres). Handed to OMPL as the fraction `resolution / maximum extent` of the
    /// space (capped at 0.5). Default 0.01. With a validity closure only, an obstacle thinner
    /// than this may be jumped over: the closure should keep a clearance margin that covers
    /// it. [`plan_arm_checked`] with its `ArmCheck`'s default continuous motions does not use
    /// it: every motion is certified whole.
    pub resolution: f64,
    /// Largest extension of the planner's trees, in the same distance as `resolution`
    /// (OMPL's `range`); `None` (default): OMPL's own, a fifth of the space's maximum extent
    /// for most planners, capped at [`ARM_RANGE`] for arm paths (measured there). Ignored by
    /// planners without a range.
    pub range: Option<f64>,
    /// Shorten and smooth the path with OMPL's `PathSimplifier` (within the budget). Default
    /// true.
    pub simplify: bool,
    /// What simplification does when [`PathSettings::simplify`] is on. Default
    /// [`Simplifier::Shortcut`]: most of the shortening for a fraction of the motion checks,
    /// and no new states between the planner's (on the MotionBenchMaker Panda set with
    /// [`plan_arm_checked`], a median plan time about 3× lower than with
    /// [`Simplifier::Full`], and 1 path in 187 instead of 16 failing an exact re-check at a
    /// quarter of the checking resolution: the full simplifier's smoothing puts states where
    /// only the motion check has looked). [`Simplifier::Full`] (OMPL's full simplifier) gives
    /// the shortest, smoothest paths; the hierarchical planner uses it
    /// ([`PlannerSettings`](crate::planner::PlannerSettings)), as its paths are executed and
    /// re-checked densely.
    pub simplifier: Simplifier,
    /// Iteration budget of the planner (OMPL's planners check their termination condition
    /// once per iteration; [`kinscene_ompl::PlanSettings::max_iterations`]). A seeded search
    /// it ends stops at the same point whatever the machine's load, and the outcome is
    /// [`PathFailure::IterationBudget`]; `budget` stays the wall-clock safety net. `None`
    /// (default): the wall clock only. At least 1.
    pub max_iterations: Option<u64>,
    /// Seed for OMPL's random generator: with a seed, the same call gives the same path
    /// (given a deterministic validity closure and a planner that stops before its budget).
    /// Seeded calls are serialised process-wide and no other [`plan_base`]/[`plan_arm`] call
    /// runs meanwhile (OMPL has one global generator); direct `kinscene_ompl` calls from other
    /// threads would break the determinism. Default `None`: OMPL's own seeding.
    pub seed: Option<u64>,
}

impl Default for PathSettings {
    fn default() -> Self {
        PathSettings {
            planner: Planner::RrtConnect,
            budget: Duration::from_secs(1),
            resolution: 0.01,
            range: None,
            simplify: true,
            simplifier: Simplifier::Shortcut,
            max_iterations: None,
            seed: None,
        }
    }
}

impl PathSettings {
    /// Checks the budget (positive), the resolution and the range (positive, finite) and the
    /// iteration budget (at least 1).
    ///
    /// # Errors
    /// [`PathError::InvalidSetting`].
    pub fn validate(&self) -> Result<(), PathError> {
        if self.budget.is_zero() {
            return Err(InvalidSetting::new("budget", 0.0, "positive").into());
        }
        if !(self.resolution.is_finite() && self.resolution > 0.0) {
            return Err(
                InvalidSetting::new("resolution", self.resolution, "finite and > 0").into(),
            );
        }
        if let Some(range) = self.range.filter(|r| !(r.is_finite() && *r > 0.0)) {
            return Err(InvalidSetting::new("range", range, "finite and > 0").into());
        }
        if self.max_iterations == Some(0) {
            return Err(InvalidSetting::new("max_iterations", 0.0, ">= 1").into());
        }
        Ok(())
    }
}

/// How planning ended: [`Solved`](crate::Outcome::Solved) with a collision-free path from
/// start to goal (see the module's path conventions), [`Infeasible`](crate::Outcome::Infeasible)
/// with the reason there is none, or [`Timeout`](crate::Outcome::Timeout) /
/// [`Cancelled`](crate::Outcome::Cancelled) when the budget or the cancel flag stopped planning
/// before any path was found.
pub type PathOutcome = crate::Outcome<Vec<Vec<f64>>, PathFailure>;

/// Why a path planner returned no path.
#[derive(Debug, Clone, PartialEq)]
pub enum PathFailure {
    /// The validity closure rejects the start.
    InvalidStart,
    /// The goal is outside the bounds or the validity closure rejects it.
    InvalidGoal,
    /// OMPL found only an approximate solution, ending this far (the space's distance) from
    /// the goal. Approximate solutions are not paths.
    Approximate {
        /// Distance from the approximate path's end to the goal.
        goal_distance: f64,
        /// Panics caught in the validity closure, each counted as an invalid state.
        checker_panics: usize,
    },
    /// The planner's iteration budget ([`PathSettings::max_iterations`]) ran out before it
    /// found a path.
    IterationBudget {
        /// The budget.
        iterations: u64,
    },
    /// OMPL gave up, crashed or reported an exact solution without states.
    Planner {
        /// OMPL's status.
        status: kinscene_ompl::PlanStatus,
        /// Panics caught in the validity closure, each counted as an invalid state.
        checker_panics: usize,
    },
}

impl std::fmt::Display for PathFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PathFailure::InvalidStart => f.write_str("the start configuration collides"),
            PathFailure::InvalidGoal => {
                f.write_str("the goal configuration collides or is out of bounds")
            }
            PathFailure::Approximate {
                goal_distance,
                checker_panics,
            } => {
                write!(
                    f,
                    "OMPL found only an approximate solution, ending {goal_distance:.4} from the goal"
                )?;
                panics(f, *checker_panics)
            }
            PathFailure::IterationBudget { iterations } => write!(
                f,
                "no path within the planner's iteration budget ({iterations} iterations)"
            ),
            PathFailure::Planner {
                status,
                checker_panics,
            } => {
                write!(f, "OMPL ended with status {status:?}")?;
                panics(f, *checker_panics)
            }
        }
    }
}

fn panics(f: &mut std::fmt::Formatter<'_>, count: usize) -> std::fmt::Result {
    match count {
        0 => Ok(()),
        n => write!(
            f,
            " ({n} panics in the validity closure, counted as invalid states)"
        ),
    }
}
