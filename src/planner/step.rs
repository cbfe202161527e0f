//! Refining one single-joint change: base path, base pose, arm paths, manipulation, timing.
//!
//! The robot executes a step in five phases, one after the other:
//! 1. **base**: it drives from its pose to the placement's base pose with the arm stowed
//!    (OMPL in SE(2); the whole robot — base and stowed arm — against the base map and the parts
//!    at the current state, with the planner's margin);
//! 2. **approach**: the arm moves from the stowed configuration to the *pre-grasp*
//!    configuration (OMPL in joint space; nothing exempt: every robot shape keeps the margin
//!    from every body, the part about to be grasped included), then straight in along the
//!    handle's inward normal to the grasp, the first waypoint of the manipulation (the
//!    placement's approach, `placement.approach_distance`, chosen with the base pose);
//! 3. **manipulation**: the arm follows the joint-space trajectory that keeps the tool on the
//!    handle trajectory of Eq. (3)–(5) while the part moves with it;
//! 4. **retreat**: the arm backs straight out along the handle's normal in the new state to
//!    the *post-grasp* configuration, then returns to the stowed configuration (OMPL, nothing
//!    exempt);
//! 5. nothing else moves: the next step starts from the stowed arm at this base pose.
//!
//! **Contact rule.** From the pre-grasp through the manipulation to the post-grasp
//! configuration the robot is checked with [`Exempt::Grasp`]: only the gripper's contact
//! shapes (fingers, pads) may touch the grasped part and its descendants, and every other
//! shape keeps the margin from every body, the grasped part included. The grasp itself stops
//! the tool short of the handle where the fingertips would otherwise enter the part's front
//! (see [`JointMotion::with_standoff`](crate::motion::placement::JointMotion::with_standoff)).
//!
//! Every path is re-checked densely by [`first_invalid`] at the planner's resolution, with
//! the same collision model but none of OMPL's code (a disagreement is a failed step, not an
//! accepted one). Every phase is time-parameterised under the robot's velocity and
//! acceleration limits.

use std::fmt;

use nalgebra::DVector;

use super::arm_check::ArmCheck;
use super::timed::{timed, value_at};
use super::{PlannerError, PlannerSettings};
use crate::kinematics::ik::IkSolver;
use crate::kinematics::robot::{Exempt, RobotCollision, RobotConfig, RobotModel};
use crate::motion::paths::{PathOutcome, first_invalid, plan_arm, plan_base};
use std::sync::Mutex;

use crate::motion::placement::{PlacementData, PlacementOutcome, PlacementProblem, place_and_plan};
use crate::motion::timing::{BlendSettings, TimedPath};
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
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
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
    /// Why, in one line.
    pub reason: String,
}

impl fmt::Display for StepFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "step {} ({:?} {:.4} -> {:.4}): {} failed: {}",
            self.step + 1,
            self.joint,
            self.from,
            self.to,
            self.check,
            self.reason
        )
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
    /// Arm time: approach, manipulation and retreat (the paper's Table I "Arm").
    pub fn arm(&self) -> f64 {
        self.approach + self.manipulation + self.retreat
    }

    /// Base plus arm time.
    pub fn total(&self) -> f64 {
        self.base + self.arm()
    }
}

/// The motion of one step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepMotion {
    /// The joint moved.
    pub joint: String,
    /// Its value before the step.
    pub from: f64,
    /// Its value after the step.
    pub to: f64,
    /// The handle grasped.
    pub handle: String,
    /// The base pose x (m), y (m), yaw (rad) of the manipulation.
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
    /// The arm path back to stowed, timed: straight out along the handle's normal to the
    /// post-grasp configuration, then free.
    pub retreat: TimedPath,
    /// Index in `retreat.positions` of the post-grasp configuration: up to it, the gripper's
    /// contact shapes may touch the grasped part.
    pub postgrasp: usize,
    /// Execution times.
    pub timing: StepTiming,
}

/// What every step needs.
pub(super) struct StepContext<'a> {
    pub robot: &'a RobotModel,
    pub collision: &'a RobotCollision,
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

/// Refines `step` (index `index` of the plan) from `state` with the robot at `robot`. `Ok(Err)`
/// is a failed check (an outcome); `Err` bad input or a broken backend.
pub(super) fn refine(
    ctx: &StepContext<'_>,
    index: usize,
    state: &State,
    joint: JointId,
    step: &Step,
    robot: &RobotConfig,
) -> Result<Result<StepMotion, Failed>, PlannerError> {
    // A failure without known causes: every joint may matter.
    let fail = |check: Check, reason: String| -> Failed {
        let failure = StepFailure {
            step: index,
            joint: step.joint.clone(),
            from: step.from,
            to: step.to,
            check,
            reason,
        };
        (failure, None)
    };
    let model = ctx.model;
    let settings = ctx.settings;
    let handle_name = match &step.handle {
        Some(h) => h.clone(),
        None => first_handle_name(model, joint)?,
    };
    let handle = model.handle_id(&handle_name)?;
    let ignore = grasped(model, joint);
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, state)?;

    // Placement: base pose and the arm along the handle trajectory.
    let placement = {
        let mut scratch = ctx.placement.lock().unwrap_or_else(|e| e.into_inner());
        place_and_plan(
            PlacementProblem {
                robot: ctx.robot,
                collision: ctx.collision,
                ik: ctx.ik,
                model,
                state,
            },
            joint,
            handle,
            step.to,
            robot.base,
            &settings.placement,
            &mut scratch,
            ctx.termination,
        )?
    };
    if !placement.is_complete() {
        let causes = placement_causes(&placement);
        let reason = placement.reason.clone().unwrap_or_else(|| {
            format!(
                "{:.0} % of the waypoints reached",
                100.0 * placement.reached_fraction
            )
        });
        let (failure, _) = fail(Check::Placement, reason);
        return Ok(Err((failure, causes)));
    }
    let base = placement.base;
    // The placement's configurations: the straight approach (pre-grasp to grasp), the handle
    // trajectory, the straight retreat (to post-grasp).
    let all: Vec<Vec<f64>> = placement
        .arm
        .iter()
        .map(|q| q.as_slice().to_vec())
        .collect();
    let trajectory = placement.motion.trajectory();
    let (grasp_at, release_at) = (*trajectory.start(), *trajectory.end());
    let waypoints = &all[trajectory];
    if ctx.termination.should_stop() {
        return Ok(Err(fail(Check::Stopped, "after base placement".into())));
    }

    // Base path, arm stowed, the whole robot against the scene at `state`.
    let stow = ctx.stow.clone();
    let base_valid = |b: &[f64; 3]| -> bool {
        let cfg = RobotConfig {
            base: *b,
            arm: stow.clone(),
        };
        match ctx.robot.link_poses(&cfg) {
            Ok(poses) => ctx
                .collision
                .scene_collision(&poses, model, &data, Exempt::Nothing, settings.margin)
                .is_none(),
            Err(_) => false,
        }
    };
    let bounds = grid_bounds(model);
    let base_path = if same_pose(&robot.base, &base) {
        vec![robot.base.to_vec(), base.to_vec()]
    } else {
        match plan_base(
            robot.base,
            base,
            bounds,
            &base_valid,
            &settings.paths,
            ctx.termination,
        )? {
            PathOutcome::Solved(p) => p,
            other => {
                let check = if ctx.termination.should_stop() {
                    Check::Stopped
                } else {
                    Check::BasePath
                };
                return Ok(Err(fail(check, describe(&other, "base"))));
            }
        }
    };
    let radius = ctx.robot.base().footprint_radius.max(1e-3);
    let scaled: Vec<Vec<f64>> = base_path
        .iter()
        .map(|p| vec![p[0], p[1], p[2] * radius])
        .collect();
    let base_valid_scaled = |p: &[f64]| base_valid(&[p[0], p[1], p[2] / radius]);
    if let Some((seg, at)) = first_invalid(
        &scaled,
        settings.base_check_resolution,
        false,
        &base_valid_scaled,
    ) {
        return Ok(Err(fail(
            Check::BasePath,
            format!(
                "dense re-check: segment {seg} collides at ({:.3}, {:.3}, {:.3})",
                at[0],
                at[1],
                at[2] / radius
            ),
        )));
    }

    // Approach: stowed -> pre-grasp (nothing exempt) -> first waypoint (the grasp rule). The
    // arm phases end or start at the placement's configurations, which keep the placement's
    // margin: the arm keeps no more than that, or the ends of its own paths would be invalid.
    let arm_margin = settings.margin.min(settings.placement.manipulation.margin);
    let (lower, upper) = ctx.robot.arm_bounds();
    let arm_check = |data, exempt| ArmCheck {
        ctx,
        base,
        data,
        exempt,
        margin: arm_margin,
    };
    let free_before = arm_check(&data, Exempt::Nothing);
    let grasping_before = arm_check(&data, Exempt::Grasp(&ignore));
    // A straight part (approach or retreat), densely re-checked under the grasp rule.
    let straight = |path: &[Vec<f64>], arm: &ArmCheck<'_>, check: Check, what: &str| {
        first_invalid(path, settings.arm_check_resolution, false, &|q| {
            arm.valid(q)
        })
        .map(|(seg, at)| {
            fail(
                check,
                format!(
                    "dense re-check: segment {seg} of the straight {what} along the \
                         handle's normal: {}",
                    arm.describe(&at)
                ),
            )
        })
    };
    let inward = &all[..=grasp_at];
    if let Some(f) = straight(inward, &grasping_before, Check::Approach, "approach") {
        return Ok(Err(f));
    }
    let pregrasp_q = inward[0].clone();
    // One arm phase: OMPL, then the dense re-check.
    let arm_phase = |from: &[f64],
                     to: &[f64],
                     arm: &ArmCheck<'_>,
                     check: Check,
                     what: &str|
     -> Result<Result<Vec<Vec<f64>>, Failed>, PlannerError> {
        let outcome = plan_arm(
            from,
            to,
            lower.as_slice(),
            upper.as_slice(),
            &|q: &[f64]| arm.valid(q),
            &settings.paths,
            ctx.termination,
        )?;
        let path = match outcome {
            PathOutcome::Solved(p) => p,
            other => {
                let check = if ctx.termination.should_stop() {
                    Check::Stopped
                } else {
                    check
                };
                return Ok(Err(fail(check, describe(&other, what))));
            }
        };
        if let Some((seg, at)) = first_invalid(&path, settings.arm_check_resolution, false, &|q| {
            arm.valid(q)
        }) {
            return Ok(Err(fail(
                check,
                format!(
                    "dense re-check: segment {seg} of the {what}: {}",
                    arm.describe(&at)
                ),
            )));
        }
        Ok(Ok(path))
    };
    let free_path = match arm_phase(
        stow.as_slice(),
        &pregrasp_q,
        &free_before,
        Check::Approach,
        "arm approach",
    )? {
        Ok(p) => p,
        Err(f) => return Ok(Err(f)),
    };
    let pregrasp = free_path.len() - 1;
    let approach: Vec<Vec<f64>> = free_path
        .into_iter()
        .chain(inward.iter().skip(1).cloned())
        .collect();

    // Manipulation: dense re-check with the part moving along with the arm.
    if let Some(reason) = check_manipulation(ctx, state, joint, step, waypoints, &|d, q| {
        let arm = ArmCheck {
            ctx,
            base,
            data: d,
            exempt: Exempt::Grasp(&ignore),
            margin: arm_margin,
        };
        arm.hit(q)
    })? {
        return Ok(Err(fail(Check::Manipulation, reason)));
    }

    // Retreat in the new state: straight out along the normal, then free to stowed.
    let mut after = state.clone();
    after.set(model, joint, step.to)?;
    let mut data_after = SceneData::new(model);
    forward_kinematics(model, &mut data_after, &after)?;
    let free_after = arm_check(&data_after, Exempt::Nothing);
    let grasping_after = arm_check(&data_after, Exempt::Grasp(&ignore));
    let outward = &all[release_at..];
    if let Some(f) = straight(outward, &grasping_after, Check::Retreat, "retreat") {
        return Ok(Err(f));
    }
    let postgrasp = outward.len() - 1;
    let free_path = match arm_phase(
        &outward[postgrasp],
        stow.as_slice(),
        &free_after,
        Check::Retreat,
        "arm retreat",
    )? {
        Ok(p) => p,
        Err(f) => return Ok(Err(f)),
    };
    let retreat: Vec<Vec<f64>> = outward
        .iter()
        .cloned()
        .chain(free_path.into_iter().skip(1))
        .collect();

    // Timing: without stops at the corners where the blended trajectory passes the same
    // checks, sampled densely; else with stops, exactly on the checked path.
    let b = ctx.robot.base();
    let blend = settings.blend.as_ref();
    let base_timed = timed(
        &base_path,
        (&b.max_velocity, &b.max_acceleration),
        Some(2),
        blend,
        settings.base_check_resolution,
        &|_, _, p| base_valid(&[p[0], p[1], p[2]]),
    )?;
    let vmax: Vec<f64> = ctx
        .robot
        .arm_joints()
        .iter()
        .map(|j| j.max_velocity)
        .collect();
    let amax: Vec<f64> = ctx
        .robot
        .arm_joints()
        .iter()
        .map(|j| j.max_acceleration)
        .collect();
    let limits = (vmax.as_slice(), amax.as_slice());
    let resolution = settings.arm_check_resolution;
    let approach_timed = timed(&approach, limits, None, blend, resolution, &|path, t, q| {
        if t < path.times[pregrasp] {
            free_before.valid(q)
        } else {
            grasping_before.valid(q)
        }
    })?;
    // The manipulation keeps the tool on the handle: its corners are cut by far less.
    let fine = blend.map(|b| BlendSettings {
        max_deviation: b.max_deviation.min(settings.manipulation_blend),
        ..*b
    });
    let scratch = std::cell::RefCell::new((state.clone(), SceneData::new(model)));
    let manipulation_timed = timed(
        waypoints,
        limits,
        None,
        fine.as_ref(),
        resolution,
        &|_, _, q| {
            let value = value_at(waypoints, q, step.from, step.to);
            let mut guard = scratch.borrow_mut();
            let (s, data) = &mut *guard;
            if s.set(model, joint, value).is_err() || forward_kinematics(model, data, s).is_err() {
                return false;
            }
            ArmCheck {
                ctx,
                base,
                data,
                exempt: Exempt::Grasp(&ignore),
                margin: arm_margin,
            }
            .valid(q)
        },
    )?;
    let retreat_timed = timed(&retreat, limits, None, blend, resolution, &|path, t, q| {
        if t <= path.times[postgrasp] {
            grasping_after.valid(q)
        } else {
            free_after.valid(q)
        }
    })?;
    let timing = StepTiming {
        base: base_timed.duration,
        approach: approach_timed.duration,
        manipulation: manipulation_timed.duration,
        retreat: retreat_timed.duration,
    };
    Ok(Ok(StepMotion {
        joint: step.joint.clone(),
        from: step.from,
        to: step.to,
        handle: handle_name,
        base,
        base_path: base_timed,
        approach: approach_timed,
        pregrasp,
        manipulation: manipulation_timed,
        retreat: retreat_timed,
        postgrasp,
        timing,
    }))
}

/// Dense re-check of the manipulation: between consecutive waypoints the arm and the joint are
/// interpolated linearly together, at the planner's arm resolution (and at most 0.01 rad or m of
/// the scene joint per check).
fn check_manipulation(
    ctx: &StepContext<'_>,
    state: &State,
    joint: JointId,
    step: &Step,
    waypoints: &[Vec<f64>],
    hit: &dyn Fn(&SceneData, &[f64]) -> Option<String>,
) -> Result<Option<String>, PlannerError> {
    let model = ctx.model;
    let k = waypoints.len().saturating_sub(1).max(1);
    let mut data = SceneData::new(model);
    let mut s = state.clone();
    for (i, pair) in waypoints.windows(2).enumerate() {
        let (a, b) = (&pair[0], &pair[1]);
        let va = step.from + (step.to - step.from) * i as f64 / k as f64;
        let vb = step.from + (step.to - step.from) * (i + 1) as f64 / k as f64;
        let arm_span = a
            .iter()
            .zip(b)
            .map(|(x, y)| (y - x).abs())
            .fold(0.0, f64::max);
        let n = ((arm_span / ctx.settings.arm_check_resolution)
            .max((vb - va).abs() / 0.01)
            .ceil() as usize)
            .max(1);
        for j in 0..=n {
            if i > 0 && j == 0 {
                continue;
            }
            let t = j as f64 / n as f64;
            let q: Vec<f64> = a.iter().zip(b).map(|(x, y)| x + (y - x) * t).collect();
            s.set(model, joint, va + (vb - va) * t)?;
            forward_kinematics(model, &mut data, &s)?;
            if let Some(what) = hit(&data, &q) {
                return Ok(Some(format!(
                    "between waypoints {i} and {} (scene joint at {:.4}): {what}",
                    i + 1,
                    va + (vb - va) * t
                )));
            }
        }
    }
    Ok(None)
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

fn describe(outcome: &PathOutcome, what: &str) -> String {
    match outcome {
        PathOutcome::Solved(_) => format!("{what}: found"),
        PathOutcome::Infeasible(why) => format!("no {what} path: {why}"),
        PathOutcome::Timeout(()) => format!("no {what} path within the budget"),
        PathOutcome::Cancelled(()) => format!("{what}: cancelled"),
    }
}

/// The parts a failed placement may depend on: the parts any evaluated sample touched. With
/// them at the same values (and the moved part's ancestors, which place its axis), the
/// deterministic placement fails again, whatever the other joints do.
fn placement_causes(placement: &PlacementOutcome) -> Option<Vec<PartId>> {
    Some(placement.obstacle_parts.clone())
}
