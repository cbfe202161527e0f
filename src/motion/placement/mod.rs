//! Manipulating one joint: grasp frames along the handle trajectory, IK along it, base placement.
//!
//! # Pipeline
//! 1. **Grasp frames** ([`JointMotion::new`]): the handle trajectory of the paper's
//!    Eq. (3)–(5) ([`grasp_trajectory`](crate::scene::motion::grasp_trajectory)) with `K`
//!    steps; at each of the `K + 1` waypoints the tool origin goes to the grasp point and the
//!    tool's +z axis (the approach direction) to `−normal`, into the surface. The rotation
//!    about that axis is free by default ([`GraspRotation::Free`], IK target
//!    [`IkTarget::PositionAxis`](crate::kinematics::ik::IkTarget::PositionAxis)) or fixed by the
//!    rule documented on [`GraspFrame::world_from_tool`] ([`GraspRotation::Fixed`],
//!    [`IkTarget::Pose`](crate::kinematics::ik::IkTarget::Pose)).
//! 2. **Manipulation plan at a base pose** ([`plan_manipulation`]): IK at every waypoint, the
//!    first with a full solve (restarts) from a seed, each next one with `solve_near` from the
//!    previous configuration (a full solve again after a waypoint that was missed). A waypoint
//!    is *reached* when IK converged, the robot's forward kinematics puts the tool on the
//!    grasp frame within [`ManipulationSettings`]' tolerances, the joints are within their
//!    limits, no joint moved more than `max_joint_jump` from the previous reached waypoint, the
//!    robot's links keep `self_margin` from each other (capped by half the clearance of the
//!    stow, or of the seed without one) and `margin` from the scene — the scene at the
//!    part's value at that waypoint, the grasped part and its descendants excepted for the
//!    arm but not for the base links, which must not be in the moving part's way — and the
//!    same holds along the straight joint-space segment from the previous reached waypoint
//!    (checked every `segment_resolution`, the part's value interpolated alongside).
//! 3. **Base placement**, [`PlacementMethod`]:
//!    - [`Sampled`](PlacementMethod::Sampled), the paper's: the robot's current base pose,
//!      then base poses drawn in the region of [`SamplingSettings`] (an annular sector in
//!      front of the handle trajectory, facing it with a yaw jitter), those outside the
//!      scene's navigation grid or whose base links touch the scene (current state, the moving part at every waypoint) rejected, a
//!      manipulation plan from each of the others; the
//!      plan with the most waypoints reached wins (ties: the lowest estimated execution time,
//!      [`TieBreak::ExecutionTime`], of the base drive and the arm's motions from the stow
//!      and back; or [`TieBreak::PathLength`]). With
//!      [`PlacementObjective::LongestPrefix`] the longest run of reached waypoints from the
//!      first wins instead (same ties), which tells how far one base pose carries the motion.
//!    - [`Optimised`](PlacementMethod::Optimised): the best sample, then one nonlinear program
//!      solved by IPOPT through CasADi (below); its result is verified independently and
//!      accepted only if it reaches **every** waypoint (and, when the sample reached every
//!      waypoint too, its smoothness cost is no larger); otherwise the sampled plan is
//!      returned, with the reason the optimum was rejected.
//!
//! # The placement NLP
//! Variables: the base pose `b = (x, y, ψ)` and the arm configurations `q₀ … q_K`, with the
//! joint limits as bounds. For each waypoint `k`, with `T(b, qₖ)` the tool pose written as
//! CasADi expressions (the planar base transform, `base_from_arm_root`, per joint
//! `parent_from_joint` and its Rodrigues rotation or translation, `last_from_tool`, all from
//! the public [`RobotModel`] data) and `(X, Y, Z)` the axes of the target frame
//! ([`GraspFrame::world_from_tool`], `Z` = approach):
//! - position: `tool origin = grasp point` (3 equalities, IPOPT's constraint tolerance
//!   `1e-8`);
//! - approach: `z_tool · X = 0`, `z_tool · Y = 0`, `z_tool · Z >= 0` (tool +z along the
//!   approach; two regular equalities instead of the degenerate `1 − z·a <= ε`); for
//!   [`GraspRotation::Fixed`] also `x_tool · Y = 0`, `x_tool · X >= 0`;
//! - continuity: `|q_{k+1,j} − q_{k,j}| <= max_joint_jump`;
//! - trust region: `‖(x, y) − (x_s, y_s)‖ <= trust_region[0]`, `|ψ − ψ_s| <= trust_region[1]`
//!   around the sample `s`;
//! - clearance: up to `max_half_planes` linear half-planes `n · (x, y) >= n · c + d`. They
//!   come from the world-aligned boxes of the scene's collision shapes (base map; parts at the
//!   current state, the moving parts at every waypoint) whose height range meets the base
//!   link's (the floor excepted) and whose floor rectangle lies within `obstacle_radius` of
//!   the sampled base centre: `c` is the rectangle's point closest to the sampled centre, `n`
//!   the unit vector from `c` to it, and `d = min(r_base + clearance, ‖sample − c‖)` with
//!   `r_base` the base link's horizontal radius (bounding spheres). The rectangle lies on the
//!   far side of the line through `c` normal to `n` (it is convex), so the base centre keeps at
//!   least `d` from it; the sample itself always satisfies its own half-planes.
//!
//! Cost: `Σₖ ‖q_{k+1} − q_k‖² + w · (Σₖ ‖qₖ − q_{s,k}‖² + ‖b − b_s‖²)`. IPOPT runs with each
//! pull weight `w` of [`OptimisationSettings::pull_weights`] in turn (a small one first: the
//! smoothest trajectory; larger ones stay closer to the verified sample, e.g. keep the
//! gripper's roll that cleared a neighbouring part) until a result passes the verification.
//! The waypoints, the sample, the half-planes and `w` are parameters, so the compiled solver
//! is reused ([`PlacementData`]) for every problem with the same robot, `K` and settings.
//!
//! The NLP knows nothing of the arm's collisions: the verification (Pinocchio's forward
//! kinematics for the tool, then every check of step 2, collisions included) is what makes a
//! reported success trustworthy.

mod error;
mod estimate;
mod grasp;
mod manipulation;
mod motion;
mod optimised;
mod plan;
mod reach;
mod sampled;
mod settings;
mod symbolic;
mod whole_body;

use std::collections::BTreeSet;
use std::time::{Duration, Instant};

use nalgebra::DVector;

pub use error::PlacementError;
pub use grasp::{GraspFrame, GraspRotation, JointMotion};
pub use motion::{grasp_standoff, grasp_standoff_along, placement_motion, placement_motion_turned};
pub use optimised::PlacementData;
pub use plan::{ManipulationPlan, Obstacle, WaypointFailure};
pub use reach::{ArmReach, arm_reach};
pub use settings::{
    DEFAULT_BAR_TURN, MAX_STEPS, ManipulationSettings, OptimisationSettings, PlacementMethod,
    PlacementObjective, PlacementSettings, SamplingSettings, TieBreak,
};
pub use whole_body::{
    WholeBodyAttempt, WholeBodyFailure, WholeBodyOutcome, WholeBodyPlan, WholeBodySettings,
    WholeBodyStart, plan_whole_body, plan_whole_body_from_starts, sideways,
};

use crate::control::Termination;
use crate::kinematics::ik::IkSolver;
use crate::kinematics::robot::{RobotCollision, RobotModel};
use crate::scene::collision::handle_bar_axis;
use crate::scene::{HandleId, JointId, PartId, SceneModel, State};
pub(crate) use manipulation::rest_self_margin;
use manipulation::{Cutoff, Prepared};
use sampled::Stop;

/// `a; b`, or whichever is present.
fn join(a: Option<String>, b: Option<String>) -> Option<String> {
    match (a, b) {
        (Some(a), Some(b)) => Some(format!("{a}; {b}")),
        (a, b) => a.or(b),
    }
}

/// The fixed inputs of a placement: robot, its collision model and IK solver, the scene and
/// its current state.
#[derive(Debug, Clone, Copy)]
pub struct PlacementProblem<'a> {
    /// The robot.
    pub robot: &'a RobotModel,
    /// Its collision geometry.
    pub collision: &'a RobotCollision,
    /// Its IK solver (for the tool frame of [`RobotModel::pinocchio`]).
    pub ik: &'a IkSolver,
    /// The scene.
    pub model: &'a SceneModel,
    /// The scene's current state Θ (the joint moves from its value here).
    pub state: &'a State,
}

/// Timing and counters of a placement.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlacementStats {
    /// Base poses drawn.
    pub samples: usize,
    /// Of those, rejected because the base links touch the scene.
    pub rejected_samples: usize,
    /// Time spent sampling (IK and checks included).
    pub sampling_time: Duration,
    /// Time to compile the NLP (zero when [`PlacementData`] had it, or not optimised).
    pub build_time: Duration,
    /// Time of the IPOPT solve and the verification.
    pub optimisation_time: Duration,
    /// Of that, the IPOPT solves alone.
    pub ipopt_time: Duration,
    /// IPOPT's exit status of the last solve (`None` unless optimised).
    pub ipopt_status: Option<String>,
    /// IPOPT iterations over all solves (one per pull weight tried).
    pub ipopt_iterations: usize,
}

/// The result of [`place_and_plan`]: a base pose and the arm's trajectory along the handle
/// trajectory, with which waypoints it reaches.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacementOutcome {
    /// The chosen base pose: x (m), y (m), yaw (rad). When every sample collided, the robot's
    /// current position facing the handle (and nothing is reached).
    pub base: [f64; 3],
    /// The arm configuration at each waypoint of [`JointMotion::grasps`] (`K + 1` on the
    /// handle trajectory, [`JointMotion::trajectory`], after the straight approach and before
    /// the straight retreat).
    pub arm: Vec<DVector<f64>>,
    /// Whether each waypoint is reached (see the [module docs](self)).
    pub reached: Vec<bool>,
    /// Reached waypoints / all waypoints.
    pub reached_fraction: f64,
    /// The joint change and its grasp frames.
    pub motion: JointMotion,
    /// Which method produced `base` and `arm`: [`PlacementMethod::Sampled`] also when the
    /// optimisation was asked for but its result rejected.
    pub method: PlacementMethod,
    /// The method asked for.
    pub requested: PlacementMethod,
    /// Why not every waypoint is reached, and/or why the optimised result was rejected;
    /// `None` when all is reached with the requested method.
    pub reason: Option<String>,
    /// Why each waypoint not reached failed (`None` where reached).
    pub failures: Vec<Option<WaypointFailure>>,
    /// The scene parts that got in the way of any evaluated candidate: touched by the base
    /// links of a rejected base pose, or by the robot at (or on the way to) a waypoint of an
    /// evaluated base pose or of the optimised plan. Sorted, no repeats. With these parts (and
    /// the moving part's ancestors) at the same values the deterministic placement gives the
    /// same result, whatever the other joints do — the cause of a failed placement.
    pub obstacle_parts: Vec<PartId>,
    /// Wall-clock time of the whole computation.
    pub elapsed: Duration,
    /// Timing and counters.
    pub stats: PlacementStats,
    /// The best sampled plans, best first, at most [`SamplingSettings::keep`] (the first is
    /// the sampled best, which `base` and `arm` are unless optimised): alternative starts
    /// for a whole-body plan. Empty when every sample collided.
    pub ranked: Vec<ManipulationPlan>,
}

impl PlacementOutcome {
    /// True when every waypoint is reached.
    pub fn is_complete(&self) -> bool {
        self.reached.iter().all(|r| *r)
    }

    /// Number of waypoints reached before the first one that is not, counted from the first
    /// of [`JointMotion::grasps`] (the pre-grasp frame when the motion has a straight
    /// approach): what the arm can execute from `base` without letting go.
    pub fn reached_prefix(&self) -> usize {
        plan::reached_prefix(&self.reached)
    }

    /// Smoothness `Σ ‖q_{k+1} − q_k‖²` of the arm trajectory.
    pub fn smoothness(&self) -> f64 {
        self.arm
            .windows(2)
            .map(|w| (&w[1] - &w[0]).norm_squared())
            .sum()
    }
}

/// The manipulation plan for `motion` with the base at `base` (see the [module docs](self),
/// step 2); the first waypoint's IK starts from `seed`.
///
/// # Errors
/// [`PlacementError::InvalidSetting`] for bad settings, [`PlacementError::NonFinite`] for a
/// non-finite base pose, [`PlacementError::Scene`] if `motion` is not from `problem.model`,
/// [`PlacementError::Ik`] / [`PlacementError::Robot`] for a seed of the wrong size.
pub fn plan_manipulation(
    problem: PlacementProblem<'_>,
    motion: &JointMotion,
    base: [f64; 3],
    seed: &DVector<f64>,
    rotation: GraspRotation,
    settings: &ManipulationSettings,
) -> Result<ManipulationPlan, PlacementError> {
    plan_manipulation_met(problem, motion, base, seed, rotation, settings).map(|(plan, _)| plan)
}

/// [`plan_manipulation`] and the scene parts any of its checks found the robot within its
/// margin of (with those at the same values, the plan is the same whatever the other joints
/// do).
pub(crate) fn plan_manipulation_met(
    problem: PlacementProblem<'_>,
    motion: &JointMotion,
    base: [f64; 3],
    seed: &DVector<f64>,
    rotation: GraspRotation,
    settings: &ManipulationSettings,
) -> Result<(ManipulationPlan, BTreeSet<PartId>), PlacementError> {
    settings.validate()?;
    if base.iter().any(|v| !v.is_finite()) {
        return Err(PlacementError::NonFinite { what: "base" });
    }
    check_seed(problem.robot, seed)?;
    let self_margin = rest_self_margin(&problem, settings.self_margin, seed)?;
    let prepared = Prepared::new(problem, motion, rotation, self_margin)?;
    let plan = prepared.plan(base, seed, settings, Cutoff::None)?;
    Ok((plan, prepared.met_parts()))
}

fn check_seed(robot: &RobotModel, seed: &DVector<f64>) -> Result<(), PlacementError> {
    check_arm(robot, seed, "arm seed")
}

/// `q` is an arm configuration of `robot`: its size and finite values (`what` names it).
fn check_arm(
    robot: &RobotModel,
    q: &DVector<f64>,
    what: &'static str,
) -> Result<(), PlacementError> {
    if q.len() != robot.dof() {
        return Err(PlacementError::DimensionMismatch {
            what,
            expected: robot.dof(),
            got: q.len(),
        });
    }
    if q.iter().any(|v| !v.is_finite()) {
        return Err(PlacementError::NonFinite { what });
    }
    Ok(())
}

/// Chooses a base pose for moving `joint` from its value in `problem.state` to `to` by the
/// handle `handle`, and plans the arm along the handle trajectory from there (see the
/// [module docs](self)). `robot_from` is the base's current pose `[x (m), y (m), yaw (rad)]`:
/// a candidate itself ([`SamplingSettings::current_pose`]) and the point the tie-break between
/// equally good samples measures from. The first waypoint's IK starts from
/// [`RobotModel::neutral`]. `data` keeps the compiled placement NLP between calls
/// ([`PlacementData::new`] for a one-off call).
///
/// Sampling stops at the earlier of `termination` and [`SamplingSettings::budget`] from now,
/// or when `termination`'s cancel flag is raised: the best plan so far is returned with the
/// reason in `reason` ("cancelled" skips the optimisation too).
///
/// # Errors
/// [`PlacementError::Scene`] for foreign ids, a handle that does not move with the joint, a
/// state not sized for the scene, or `to` outside the joint's limits;
/// [`PlacementError::InvalidSetting`]; [`PlacementError::NonFinite`] for `robot_from`;
/// [`PlacementError::Casadi`] / [`PlacementError::Pinocchio`] when a backend fails.
/// Unreachable waypoints are an outcome (`reached`, `reason`), not an error.
#[allow(clippy::too_many_arguments)]
pub fn place_and_plan(
    problem: PlacementProblem<'_>,
    joint: JointId,
    handle: HandleId,
    to: f64,
    robot_from: [f64; 3],
    settings: &PlacementSettings,
    data: &mut PlacementData,
    termination: &Termination<'_>,
) -> Result<PlacementOutcome, PlacementError> {
    let start = Instant::now();
    settings.validate()?;
    if robot_from.iter().any(|v| !v.is_finite()) {
        return Err(PlacementError::NonFinite { what: "robot_from" });
    }
    let motion = placement_motion(problem, joint, handle, to, settings)?;
    let mut best = place_motion(problem, motion, robot_from, settings, data, termination)?;
    let turns = match handle_bar_axis(problem.model, handle)? {
        Some(_) if !best.is_complete() => settings.bar_turns(),
        _ => Vec::new(),
    };
    let score = |o: &PlacementOutcome| match settings.sampling.objective {
        PlacementObjective::MostReached => o.reached.iter().filter(|r| **r).count(),
        PlacementObjective::LongestPrefix => o.reached_prefix(),
    };
    for angle in turns {
        if termination.should_stop() {
            break;
        }
        let motion = placement_motion_turned(problem, joint, handle, to, settings, angle)?;
        let outcome = place_motion(problem, motion, robot_from, settings, data, termination)?;
        let mut parts: BTreeSet<PartId> = best.obstacle_parts.iter().copied().collect();
        parts.extend(outcome.obstacle_parts.iter().copied());
        let samples = best.stats.samples + outcome.stats.samples;
        if score(&outcome) > score(&best) {
            best = outcome;
        }
        best.obstacle_parts = parts.into_iter().collect();
        best.stats.samples = samples;
        if best.is_complete() {
            break;
        }
    }
    best.elapsed = start.elapsed();
    Ok(best)
}

/// [`place_and_plan`] for one given joint motion (its grasp frames fixed).
fn place_motion(
    problem: PlacementProblem<'_>,
    motion: JointMotion,
    robot_from: [f64; 3],
    settings: &PlacementSettings,
    data: &mut PlacementData,
    termination: &Termination<'_>,
) -> Result<PlacementOutcome, PlacementError> {
    let start = Instant::now();
    let seed = problem.robot.neutral();
    if let Some(stow) = &settings.stow {
        check_arm(problem.robot, stow, "stow")?;
    }
    let rest = settings.stow.as_ref().unwrap_or(&seed);
    let self_margin = rest_self_margin(&problem, settings.manipulation.self_margin, rest)?;
    let mut prepared = Prepared::new(problem, &motion, settings.grasp, self_margin)?;
    prepared.termination = termination.capped(settings.sampling.budget);
    let sampled = sampled::sample(
        &prepared,
        robot_from,
        &seed,
        settings.stow.as_ref(),
        &settings.sampling,
        &settings.manipulation,
    )?;
    let mut stats = PlacementStats {
        samples: sampled.drawn,
        rejected_samples: sampled.rejected,
        sampling_time: start.elapsed(),
        ..PlacementStats::default()
    };
    let stopped = match sampled.stopped {
        Some(Stop::Budget) => Some(format!(
            "sampling budget of {:?} spent after {} base poses",
            settings.sampling.budget, sampled.drawn
        )),
        Some(Stop::Cancelled) => Some("cancelled".to_owned()),
        None => None,
    };
    let ranked = sampled.ranked;
    let Some(best) = ranked.first().cloned() else {
        let n = motion.len();
        let reason = stopped.unwrap_or_else(|| {
            format!(
                "all {} sampled base poses collide with the scene; nothing reached",
                sampled.drawn
            )
        });
        return Ok(PlacementOutcome {
            base: sampled.fallback,
            arm: vec![seed; n],
            reached: vec![false; n],
            reached_fraction: 0.0,
            failures: vec![None; n],
            obstacle_parts: prepared.met_parts().into_iter().collect(),
            motion,
            method: PlacementMethod::Sampled,
            requested: settings.method,
            reason: Some(reason),
            elapsed: start.elapsed(),
            stats,
            ranked,
        });
    };
    let mut method = PlacementMethod::Sampled;
    let mut plan = best;
    let mut reason = join(plan.reason(), stopped);
    let cancelled = termination.is_cancelled();
    if cancelled && settings.method == PlacementMethod::Optimised {
        reason = join(reason, Some("optimisation skipped: cancelled".to_owned()));
    } else if settings.method == PlacementMethod::Optimised {
        let t = Instant::now();
        let result = optimised::optimise(
            &prepared,
            &plan,
            &settings.manipulation,
            &settings.optimisation,
            data,
        )?;
        stats.build_time = result.build_time;
        stats.optimisation_time = t.elapsed().saturating_sub(result.build_time);
        stats.ipopt_iterations = result.iterations;
        stats.ipopt_time = result.solve_time;
        let rejection = match result.plan {
            Ok(optimum) => {
                plan = optimum;
                method = PlacementMethod::Optimised;
                reason = None;
                None
            }
            Err(why) => Some(format!("optimised plan rejected: {why}")),
        };
        stats.ipopt_status = Some(result.status);
        reason = join(reason, rejection);
    }
    let n = plan.reached.len();
    Ok(PlacementOutcome {
        base: plan.base,
        reached_fraction: plan.reached_count() as f64 / n as f64,
        arm: plan.arm,
        reached: plan.reached,
        failures: plan.failures,
        obstacle_parts: prepared.met_parts().into_iter().collect(),
        motion,
        method,
        requested: settings.method,
        reason,
        elapsed: start.elapsed(),
        stats,
        ranked,
    })
}
