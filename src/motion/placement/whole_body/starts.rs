//! Whole-body plans from several starts ([`plan_whole_body_from_starts`]): where one start
//! squeezes the robot between cabinets or turns the arm's approach into a neighbouring run, the
//! tracking (local IK, backtracking a few waypoints) cannot leave the posture it began in; a
//! different base pose, or a different IK branch (elbow, wrist) at the first waypoint, can.

use std::f64::consts::PI;

use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{WholeBodyOutcome, WholeBodySettings, plan_whole_body};
use crate::control::Termination;
use crate::motion::placement::{
    GraspRotation, JointMotion, ManipulationSettings, PlacementError, PlacementProblem, check_arm,
};

/// A base pose and an arm seed a whole-body plan may start from (e.g. one of
/// [`PlacementOutcome::ranked`](crate::motion::placement::PlacementOutcome::ranked): its
/// base pose and first configuration).
#[derive(Debug, Clone, PartialEq)]
pub struct WholeBodyStart {
    /// The base pose: x (m), y (m), yaw (rad).
    pub base: [f64; 3],
    /// The arm seed of the first waypoint's IK.
    pub seed: DVector<f64>,
}

/// One whole-body plan tried by [`plan_whole_body_from_starts`].
#[derive(Debug, Clone, PartialEq)]
pub struct WholeBodyAttempt {
    /// Index of the start in the given list.
    pub start: usize,
    /// Which arm seed: 0 the start's own, `i >= 1` the `i`-th drawn one.
    pub arm_seed: usize,
    /// The start's base pose.
    pub base: [f64; 3],
    /// What the whole-body plan from there did.
    pub outcome: WholeBodyOutcome,
}

impl WholeBodyAttempt {
    /// Waypoints reached before the first failure (all of them when tracked).
    pub fn reached(&self) -> usize {
        match &self.outcome {
            WholeBodyOutcome::Tracked(plan) => plan.bases.len(),
            WholeBodyOutcome::Failed { waypoint, .. } => *waypoint,
        }
    }

    /// One line: the start's base pose, the arm seed and what happened.
    pub fn summary(&self) -> String {
        let b = self.base;
        let from = format!(
            "from ({:.3}, {:.3}, {:.3}) arm seed {}",
            b[0], b[1], b[2], self.arm_seed
        );
        match &self.outcome {
            WholeBodyOutcome::Tracked(plan) => format!(
                "{from}: tracked, base travel {:.3} m, arm path {:.3}",
                plan.base_travel(),
                arm_path(&plan.arm)
            ),
            failed => format!("{from}: {}", failed.reason().unwrap_or_default()),
        }
    }
}

/// Joint-space path length `Σ ‖q_{k+1} − q_k‖` of an arm trajectory (rad or m).
fn arm_path(arm: &[DVector<f64>]) -> f64 {
    arm.windows(2).map(|w| (&w[1] - &w[0]).norm()).sum()
}

/// The arm seeds tried from every start after its own: `n − 1` configurations drawn
/// uniformly within the arm's joint limits (`(−π, π]` for a continuous joint) from a
/// ChaCha8 generator seeded with `seed`, the same for every start.
fn drawn_seeds(problem: PlacementProblem<'_>, n: usize, seed: u64) -> Vec<DVector<f64>> {
    let (lower, upper) = problem.robot.arm_bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (1..n)
        .map(|_| {
            DVector::from_iterator(
                lower.len(),
                lower.iter().zip(upper.iter()).map(|(&lo, &hi)| {
                    let (lo, hi) = if lo.is_finite() && hi.is_finite() {
                        (lo, hi)
                    } else {
                        (-PI, PI)
                    };
                    lo + (hi - lo) * rng.random::<f64>()
                }),
            )
        })
        .collect()
}

/// [`plan_whole_body`] from each of the first [`WholeBodySettings::starts`] of `starts` in
/// order, each with [`WholeBodySettings::arm_seeds`] arm seeds: the start's own, then
/// configurations drawn within the joint limits from [`WholeBodySettings::seed`] (the first
/// waypoint's IK, which restarts from its seed, lands on other elbow and wrist branches from
/// them). Stops at the first plan that tracks every waypoint (the last attempt returned) or
/// when `termination` says so; every attempt is returned, in order, with its outcome: the
/// furthest waypoint and why each failed when none tracks. Deterministic for given inputs.
///
/// # Errors
/// As [`plan_whole_body`] (bad settings, a non-finite start, a bad seed, a backend failing).
#[allow(clippy::too_many_arguments)]
pub fn plan_whole_body_from_starts(
    problem: PlacementProblem<'_>,
    motion: &JointMotion,
    starts: &[WholeBodyStart],
    rotation: GraspRotation,
    manipulation: &ManipulationSettings,
    settings: &WholeBodySettings,
    termination: &Termination<'_>,
) -> Result<Vec<WholeBodyAttempt>, PlacementError> {
    settings.validate()?;
    for start in starts {
        check_arm(problem.robot, &start.seed, "arm seed")?;
    }
    let drawn = drawn_seeds(problem, settings.arm_seeds, settings.seed);
    let mut attempts = Vec::new();
    for (i, start) in starts.iter().take(settings.starts).enumerate() {
        for (j, seed) in std::iter::once(&start.seed).chain(&drawn).enumerate() {
            if termination.should_stop() {
                return Ok(attempts);
            }
            let outcome = plan_whole_body(
                problem,
                motion,
                start.base,
                seed,
                rotation,
                manipulation,
                settings,
            )?;
            let tracked = outcome.plan().is_some();
            attempts.push(WholeBodyAttempt {
                start: i,
                arm_seed: j,
                base: start.base,
                outcome,
            });
            if tracked {
                return Ok(attempts);
            }
        }
    }
    Ok(attempts)
}
