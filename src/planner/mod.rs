//! The hierarchical planner: task-level sequencing refined by motion planning, end to end.
//!
//! One call, [`HierarchicalPlanner::plan`], turns (scene, robot, start, goal) into an executable
//! plan: for every single-joint change, the base path, the base pose, the arm path to the handle,
//! the manipulation trajectory in joint space, the retreat, and their timing — or the reason it
//! cannot.
//!
//! # How the layers meet (lazy refinement)
//! 1. The task search ([`crate::task::plan`]) proposes the cheapest order of single-joint changes
//!    that passes its checks (part collisions, grid paths).
//! 2. This layer refines the steps **in order**, replaying the robot: arm stowed, base driven to
//!    the chosen pose, arm to the grasp, the handle trajectory, the arm back to its stowed
//!    configuration (see [`StepMotion`]). A step that no single base pose covers is executed
//!    in segments, letting go and grasping again from another base pose in between (at most
//!    [`PlannerSettings::max_segments`]; see [`StepMotion`] and [`MotionPlan::segments`]).
//! 3. When a step cannot be refined, its move is **vetoed** — the task search is given a
//!    [`Refiner`](crate::task::Refiner) that answers from the table of vetoes — in every state
//!    that agrees with this one on the joints the failure depends on: the moved part's
//!    ancestors and the parts its checks met (any placement's and whole-body attempt's, a
//!    rejected IK restart's included), and for a failed arm phase also every part within the
//!    robot's reach of its base poses; a failed base path depends on the whole map (every
//!    joint). The search runs again and returns a different order (possibly with extra moves,
//!    such as closing a door the arm hits), or proves that none is left.
//!
//! Each round adds one rule to the table, and the lattice is finite, so the loop ends. A veto
//! carried to another state rests on monotonicity: the parts the failed checks never met can
//! only add obstacles where they stand elsewhere, so the same seeded search fails again (the
//! verdicts of the motion layer are those of sampling-based planners with a budget: a failure
//! there means "not found", not "impossible", and a changed scene may change which states a
//! search draws).
//!
//! # Segments
//! When no base pose covers a step's whole handle trajectory, the robot regrasps: the step's
//! interval `[from, to]` is covered by consecutive segments `[θ0, θ1], [θ1, θ2], …`
//! (`θ0 = from`, the last ending at `to`), each executed as the full sequence of phases (base
//! path, approach, manipulation, retreat) from a base pose of its own, starting from the state
//! and the base pose the previous segment left (the part partly moved, the arm stowed). Each
//! segment is one [`StepMotion`] of [`MotionPlan::steps`]; [`MotionPlan::segments`] says which
//! entries refine which task step. The ends are chosen from what the placement reports:
//! 1. the placement of the rest `[θi, to]`, as for an unsegmented step; if it covers every
//!    waypoint, that is the last segment (so the single placement stays the first choice,
//!    and a step that one base pose covers is refined exactly as without segments);
//! 2. otherwise, unless this would be segment [`PlannerSettings::max_segments`] already, the
//!    placement of the rest again with the objective
//!    [`LongestPrefix`](crate::motion::placement::PlacementObjective::LongestPrefix) (sampled):
//!    the base pose from which the arm follows the motion furthest without letting go,
//!    straight approach included. The last waypoint `e` of the handle trajectory it reaches
//!    that way (at most the one before the last, and past the first) gives the candidate ends
//!    `θ(e)`, `θ(e − 1)` and `θ(⌊e/2⌋)` (past the first waypoint, longest first);
//! 3. for a candidate end, the segment `[θi, θ(e)]` (its own `K` steps, approach and retreat)
//!    is evaluated at that base pose, and if it does not reach every waypoint there, placed
//!    anew; the first candidate that is covered, from a base pose where the stowed robot is
//!    clear (a base path can end there), is the segment.
//!
//! Everything is seeded (the sampler, the IK, OMPL), so the segments are the same for the same
//! input. A step that cannot be covered in `max_segments` segments fails with
//! [`Check::Placement`] and the segment it stopped at ([`FailedSegment`]); a segment whose
//! phases fail fails the step with that check. `max_segments = 1` is the paper's manipulation
//! planner: one base pose per step.
//!
//! # Whole-body manipulation
//! With [`PlannerSettings::whole_body`] set, a step whose placement does not cover it is also
//! tried with one grasp while the base moves along with the arm
//! ([`plan_whole_body`](crate::motion::placement::plan_whole_body)): from the base pose and
//! first configuration of the placement with the objective
//! [`LongestPrefix`](crate::motion::placement::PlacementObjective::LongestPrefix) (where the
//! arm alone follows the handle furthest), else of the step's placement. Its phases: the base
//! path to the first waypoint's base pose, the approach there (free, then straight in), the
//! manipulation with a base pose per waypoint (its base and arm timed together as one path
//! `[x, y, yaw, q…]`: a holonomic base under its per-axis limits, a differential-drive base
//! exactly under its forward speed and yaw rate; densely re-checked with base, arm and part
//! interpolated together), the retreat at the last waypoint's base pose, where the next step
//! starts ([`StepMotion::end_base`]). The base must stand still during the straight approach
//! and retreat. The segmented refinement runs as well (up to `max_segments`); when both
//! refine, the one with the shorter execution time is kept ([`StepMotion::mode`],
//! [`StepMotion::compared`]); when neither does, the step fails with both reasons
//! ([`StepReason::WholeBodyMissed`]). A step that one base pose covers is refined as without
//! the setting. It is on by default (with [`WholeBodySettings::default`]): a consumer that
//! executes a plan follows [`StepMotion::manipulation_base`] when it is `Some`. `None` is the
//! paper's fixed-base manipulation, under which the base stands still whenever the arm moves.
//!
//! [`WholeBodySettings::default`]: crate::motion::placement::WholeBodySettings
//!
//! # Approximations
//! One approximation: whether the *base path* to a move exists also depends on where the robot
//! comes from, which is not part of the task state; a base-path failure is nevertheless vetoed
//! for the state. The task layer's grid path check makes such failures rare.

mod arm_check;
mod document;
mod outcome;
mod reach;
mod settings;
mod step;
mod timed;
mod veto;

pub use document::{MotionDocument, StepDocument, VetoDocument};
pub use outcome::{
    MotionInfeasibility, MotionOutcome, MotionPlan, PlannerResult, Progress, RefineOutcome,
    StopPoint,
};
pub use reach::arm_reach;
pub use settings::{PLANNER_PATH_ITERATIONS, PlannerSettings};
pub use step::{
    Check, Compared, Contact, FailedSegment, PlacementShortfall, SegmentMiss, SegmentTry,
    SplitMiss, StepFailure, StepMode, StepMotion, StepPath, StepReason, StepTiming,
};

use std::sync::Mutex;
use std::time::Instant;

use nalgebra::DVector;

use crate::kinematics::ik::{IkError, IkSolver};
use crate::kinematics::robot::{
    RobotCollision, RobotConfig, RobotError, RobotModel, RobotSpheres, SpeedBound,
};
use crate::motion::paths::PathError;
use crate::motion::placement::{PlacementData, PlacementError};
use crate::motion::timing::TimingError;
use crate::scene::SceneModel;
use crate::task::{
    self, Infeasibility, MoveContext, Outcome, Plan, Problem, Refinement, SearchStats, Termination,
};
use veto::VetoRule;

/// Errors of the hierarchical planner: bad input and broken backends only.
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum PlannerError {
    /// The scene model rejected a query.
    #[error("scene: {0}")]
    Scene(#[from] crate::scene::Error),
    /// The task layer rejected its input.
    #[error("task: {0}")]
    Task(#[from] crate::task::Error),
    /// The robot model rejected its input.
    #[error("robot: {0}")]
    Robot(#[from] RobotError),
    /// Inverse kinematics rejected its input or its backend failed.
    #[error("IK: {0}")]
    Ik(#[from] IkError),
    /// Base placement rejected its input or its backend failed.
    #[error("placement: {0}")]
    Placement(#[from] PlacementError),
    /// Path planning rejected its input or OMPL failed.
    #[error("paths: {0}")]
    Path(#[from] PathError),
    /// Time parameterisation rejected its input.
    #[error("timing: {0}")]
    Timing(#[from] TimingError),
    /// A setting is out of range.
    #[error("{0}")]
    InvalidSetting(#[from] crate::InvalidSetting),
    /// The problem gives no start pose for the robot's base (`problem.robot.base`), which
    /// the hierarchical planner starts from.
    #[error(
        "the hierarchical planner needs the robot's start pose ([robot] base = [x, y, yaw]); the problem gives none"
    )]
    MissingBasePose,
    /// A step moves a joint whose part carries no handle, so the arm has nothing to grasp.
    #[error("joint {joint:?} moves a part without a handle")]
    NoHandle {
        /// The joint.
        joint: String,
    },
}

/// Task search plus motion refinement for one robot. Build once, plan many times; the robot's
/// collision model and IK solver are shared by all calls (`Send + Sync`).
#[derive(Debug)]
pub struct HierarchicalPlanner {
    robot: RobotModel,
    collision: RobotCollision,
    /// The sphere model of the arm checks' fast path (`settings.arm_spheres`).
    spheres: Option<RobotSpheres>,
    ik: IkSolver,
    /// How fast the robot's points move for given joint speeds (the certification's bound).
    speeds: SpeedBound,
    settings: PlannerSettings,
    /// The compiled placement NLP, reused between steps and calls.
    placement: Mutex<PlacementData>,
}

impl HierarchicalPlanner {
    /// A planner for `robot`.
    ///
    /// # Errors
    /// Invalid settings; a robot whose collision model or IK solver cannot be built.
    pub fn new(robot: RobotModel, settings: PlannerSettings) -> Result<Self, PlannerError> {
        let mut settings = settings;
        settings.validate(&robot)?;
        let collision = RobotCollision::new(&robot)?;
        // The task level must not rule out a move the motion layer can make in segments, or,
        // with whole-body manipulation, with the base at another position for every waypoint
        // (as many runs as the task level's grasp points: its nearest rule).
        settings.task.manipulation.segments = match settings.whole_body {
            Some(_) => settings
                .max_segments
                .max(settings.task.manipulation.steps + 1)
                .min(1000),
            None => settings.max_segments,
        };
        if settings.task.manipulation.arm.is_none() {
            let standoff = collision.fingertip_reach(&robot).unwrap_or(0.0).max(0.0)
                + settings.placement.manipulation.finger_clearance;
            let mut arm = reach::arm_reach(&robot, standoff);
            // The IK's tolerances: the tool within `position_tolerance` of its target and its
            // axis within `rotation_tolerance` (plus the approach cone), which moves the wrist
            // point by up to that angle times its distance from the tool.
            let tilt =
                settings.ik.rotation_tolerance + settings.placement.manipulation.approach_cone;
            arm.wrist_radius += settings.ik.position_tolerance
                + tilt * arm.wrist_out[1].abs().hypot(arm.wrist_radius);
            settings.task.manipulation.arm = Some(arm);
        }
        if settings.placement.stow.is_none() {
            // Base poses from which the arm cannot be stowed at the step's start or end are
            // not drawn: the arm comes from the stow and goes back to it.
            settings.placement.stow = Some(settings.stow.clone().unwrap_or(robot.neutral()));
        }
        let ik = IkSolver::new(robot.pinocchio(), robot.tool_frame(), settings.ik.clone())?;
        let spheres = match &settings.arm_spheres {
            Some(s) => Some(RobotSpheres::new(&robot, &collision, s)?),
            None => None,
        };
        Ok(HierarchicalPlanner {
            speeds: collision.speed_bound(&robot),
            robot,
            collision,
            spheres,
            ik,
            settings,
            placement: Mutex::new(PlacementData::new()),
        })
    }

    /// The robot.
    pub fn robot(&self) -> &RobotModel {
        &self.robot
    }

    /// The settings.
    pub fn settings(&self) -> &PlannerSettings {
        &self.settings
    }

    /// The arm configuration the robot drives with and returns to after every step.
    pub fn stow(&self) -> DVector<f64> {
        self.settings
            .stow
            .clone()
            .unwrap_or_else(|| self.robot.neutral())
    }

    /// Plans `problem` in `model`: the task order and the motion of every step.
    ///
    /// The task level checks paths for the disc of `problem.robot.radius` (default 0.3 m); the
    /// base paths of this layer check the robot's real geometry (chassis and stowed arm), so a
    /// disc smaller than the robot's footprint costs refinement rounds (vetoed base paths), not
    /// soundness. The start base pose is `problem.robot.base`, or the task level's choice when it
    /// is `None` (yaw 0); the arm starts stowed.
    ///
    /// # Errors
    /// Only for bad input or a broken backend (see [`PlannerError`]), such as
    /// [`PlannerError::MissingBasePose`] for a problem without the robot's start pose.
    /// Infeasible goals and exhausted budgets are [`MotionOutcome`]s.
    pub fn plan(
        &self,
        model: &SceneModel,
        problem: &Problem,
        termination: &Termination<'_>,
    ) -> Result<PlannerResult, PlannerError> {
        // The base paths live on the navigation grid: grow it to the robot's start once here,
        // so the task layer and every step see the same grid.
        let model = &*model.covering(&problem.robot.start_point())?;
        let vetoes: Mutex<Vec<VetoRule>> = Mutex::new(Vec::new());
        let mut failures: Vec<StepFailure> = Vec::new();
        let mut rounds = Rounds::default();
        let refiner = |ctx: &MoveContext<'_>| {
            let table = vetoes.lock().unwrap_or_else(|e| e.into_inner());
            match table
                .iter()
                .find(|r| r.matches(ctx.state, ctx.joint, ctx.to))
            {
                Some(rule) => Refinement::Veto {
                    reason: rule.reason.clone(),
                    blockers: rule.blockers.clone(),
                },
                None => Refinement::Accept,
            }
        };
        loop {
            let stopped = |at, vetoes| MotionOutcome::stopped(termination, Progress { at, vetoes });
            if termination.should_stop() {
                let outcome = stopped(StopPoint::BetweenTaskPlans, failures);
                return Ok(rounds.result(outcome, SearchStats::default()));
            }
            let t0 = Instant::now();
            let result = task::plan(model, problem, &self.settings.task, &refiner, termination)?;
            rounds.task_time += t0.elapsed().as_secs_f64();
            rounds.task_plans += 1;
            let plan = match result.outcome {
                Outcome::Solved(plan) => plan,
                Outcome::Infeasible(why) => {
                    let outcome = MotionOutcome::Infeasible(MotionInfeasibility {
                        task: why,
                        vetoes: failures,
                    });
                    return Ok(rounds.result(outcome, result.stats));
                }
                Outcome::Timeout(partial) | Outcome::Cancelled(partial) => {
                    let outcome = stopped(StopPoint::TaskSearch(partial), failures);
                    return Ok(rounds.result(outcome, result.stats));
                }
            };
            let t1 = Instant::now();
            let refined = self.refine_plan(model, problem, &plan, termination)?;
            rounds.motion_time += t1.elapsed().as_secs_f64();
            match refined {
                Refined::All(steps) => {
                    let outcome = MotionOutcome::Solved(MotionPlan { task: plan, steps });
                    return Ok(rounds.result(outcome, result.stats));
                }
                Refined::Failed { rule, failure } => {
                    if !matches!(self.settings.task.strategy, task::Strategy::Search) {
                        // The baselines do not consult the refiner: they would propose the
                        // same order again. Their verdict is the failed step.
                        let message = format!("the baseline's order does not refine: {failure}");
                        failures.push(failure);
                        let outcome = MotionOutcome::Infeasible(MotionInfeasibility {
                            task: Infeasibility {
                                message,
                                unreached: Vec::new(),
                                conflicts: Vec::new(),
                                start_collisions: Vec::new(),
                            },
                            vetoes: failures,
                        });
                        return Ok(rounds.result(outcome, result.stats));
                    }
                    vetoes.lock().unwrap_or_else(|e| e.into_inner()).push(rule);
                    failures.push(failure);
                }
                Refined::Stopped(step) => {
                    let outcome = stopped(StopPoint::Refining(Box::new(step)), failures);
                    return Ok(rounds.result(outcome, result.stats));
                }
            }
        }
    }

    /// Refines one given order of moves, `plan`, without searching for another: the motion of
    /// every step, or the first step that fails and why. For orders chosen elsewhere (a user's
    /// own sequence, the paper's *Random* baseline); [`plan`](Self::plan) is this plus the
    /// search for an order that refines. `plan` must be a task plan for `problem`'s start
    /// (its steps are replayed from `problem.start`; the task layer's own checks are not
    /// repeated).
    ///
    /// # Errors
    /// Only for bad input (a step naming an unknown joint, a value outside its limits) or a
    /// broken backend. A failed step or an exhausted budget is a [`RefineOutcome`].
    pub fn refine(
        &self,
        model: &SceneModel,
        problem: &Problem,
        plan: &Plan,
        termination: &Termination<'_>,
    ) -> Result<RefineOutcome, PlannerError> {
        Ok(match self.refine_plan(model, problem, plan, termination)? {
            Refined::All(steps) => RefineOutcome::Solved(MotionPlan {
                task: plan.clone(),
                steps,
            }),
            Refined::Failed { failure, .. } => RefineOutcome::Infeasible(failure),
            Refined::Stopped(step) => RefineOutcome::stopped(termination, step),
        })
    }

    /// Refines the steps of `plan` in order.
    fn refine_plan(
        &self,
        model: &SceneModel,
        problem: &Problem,
        plan: &Plan,
        termination: &Termination<'_>,
    ) -> Result<Refined, PlannerError> {
        let mut state = problem.start.clone();
        let stow = self.stow();
        let start_base = match (problem.robot.base, plan.steps.first()) {
            (Some(b), _) => b,
            (None, Some(first)) => step::start_base_of(model, &state, first, &problem.robot)?,
            (None, None) => [0.0; 3],
        };
        let mut robot = RobotConfig {
            base: start_base,
            arm: stow.clone(),
        };
        let mut steps = Vec::with_capacity(plan.steps.len());
        for (index, s) in plan.steps.iter().enumerate() {
            if termination.should_stop() {
                return Ok(Refined::Stopped(StepFailure {
                    step: index,
                    joint: s.joint.clone(),
                    from: state.value_by_name(model, &s.joint)?,
                    to: s.to,
                    check: Check::Stopped,
                    reason: StepReason::Stopped {
                        when: "before the step began",
                    },
                    segment: None,
                }));
            }
            let joint = model.joint_id(&s.joint)?;
            let ctx = step::StepContext {
                robot: &self.robot,
                collision: &self.collision,
                spheres: self.spheres.as_ref(),
                speeds: &self.speeds,
                ik: &self.ik,
                settings: &self.settings,
                model,
                stow: &stow,
                placement: &self.placement,
                termination,
            };
            match step::refine(&ctx, index, &state, joint, s, &robot)? {
                Ok(segments) => {
                    if let Some(last) = segments.last() {
                        robot.base = last.end_base();
                    }
                    state.set(model, joint, s.to)?;
                    steps.extend(segments);
                }
                Err((failure, _)) if failure.check == Check::Stopped => {
                    return Ok(Refined::Stopped(failure));
                }
                Err((failure, causes)) => {
                    let rule = VetoRule::new(
                        model,
                        &state,
                        joint,
                        s.to,
                        causes.as_deref(),
                        failure.to_string(),
                    );
                    return Ok(Refined::Failed { rule, failure });
                }
            }
        }
        Ok(Refined::All(steps))
    }
}

/// What the rounds of [`HierarchicalPlanner::plan`] have counted: task searches and the time in
/// each layer.
#[derive(Default)]
struct Rounds {
    task_plans: usize,
    task_time: f64,
    motion_time: f64,
}

impl Rounds {
    fn result(&self, outcome: MotionOutcome, task_stats: SearchStats) -> PlannerResult {
        PlannerResult {
            outcome,
            task_plans: self.task_plans,
            task_stats,
            task_time: self.task_time,
            motion_time: self.motion_time,
        }
    }
}

/// How refining a task plan ended.
enum Refined {
    All(Vec<StepMotion>),
    Failed {
        rule: VetoRule,
        failure: StepFailure,
    },
    Stopped(StepFailure),
}
