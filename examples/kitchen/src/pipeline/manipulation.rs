//! Stage 3: goals on true joint names translated to the estimated model, planned (Ours on the
//! estimated model, Oracle on the true one, Random's order refined), executed in the simulator
//! and judged on the true state.

use std::collections::{BTreeMap, BTreeSet};
use std::time::Duration;

use kinscene::discovery::{Observation, reconcile};
use kinscene::planner::{
    HierarchicalPlanner, MotionDocument, MotionInfeasibility, MotionOutcome, MotionPlan,
    PlannerResult, RefineOutcome,
};
use kinscene::scene::collision::SweepSettings;
use kinscene::scene::{BaseShape, JointKind, SceneData, SceneModel, State, forward_kinematics};
use kinscene::task::{
    self, Cause, Infeasibility, NoRefinement, Outcome, Problem, SearchStats, Strategy,
    TaskSettings, Termination,
};
use serde::Serialize;

use super::PipelineError;
use super::matching::Match;
use super::sequences::goal_spec;
use super::sim::{Execution, FailureCategory, SimWorld};
use super::stages::pose;

/// A revolute goal counts as reached within this much (rad, about 2.9°) below its target: the
/// compliant grasp lags the commanded trajectory by a little.
pub const REVOLUTE_TOLERANCE: f64 = 0.05;
/// A prismatic goal counts as reached within this much (m) below its target.
pub const PRISMATIC_TOLERANCE: f64 = 0.01;

/// How an attempt ended (the paper's Fig. 5 classes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub enum Category {
    /// The true state met the goal.
    Success,
    /// A moving part hit another part or the kitchen (in the simulator, or predicted by the
    /// task layer for Random's order).
    PartCollision,
    /// The robot's way was blocked by a part (in the simulator, the task layer's path check,
    /// or no base path in the motion layer).
    PathBlocking,
    /// Everything else: no plan, a planner timeout, a lost grasp, an arm collision, a goal
    /// missed by model error.
    Other,
}

impl Category {
    /// Every category, in report order.
    pub const ALL: [Category; 4] = [
        Category::Success,
        Category::PartCollision,
        Category::PathBlocking,
        Category::Other,
    ];

    /// The name in the report.
    pub fn name(self) -> &'static str {
        match self {
            Category::Success => "success",
            Category::PartCollision => "part collision",
            Category::PathBlocking => "path blocking",
            Category::Other => "other",
        }
    }
}

/// The verdict of one attempt.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    /// The class.
    pub category: Category,
    /// Why, in one line (empty on success).
    pub reason: String,
    /// The order the plan moved the joints in (true names where known): `joint from → to`.
    pub steps: Vec<String>,
    /// The goal joints' true values afterwards (rad or m); empty when nothing was executed.
    pub final_values: Vec<(String, f64)>,
    /// Simulated execution time of the base (s).
    pub base_time: f64,
    /// Simulated execution time of the arm (s).
    pub arm_time: f64,
}

impl Verdict {
    /// A verdict without execution.
    pub fn failed(category: Category, reason: impl Into<String>) -> Self {
        Verdict {
            category,
            reason: reason.into(),
            steps: Vec::new(),
            final_values: Vec::new(),
            base_time: 0.0,
            arm_time: 0.0,
        }
    }
}

/// What one attempt produced besides its verdict: the planner's document and the execution.
pub struct Attempt {
    /// The verdict.
    pub verdict: Verdict,
    /// The plan document, when a planner ran.
    pub document: Option<MotionDocument>,
    /// The executed plan.
    pub plan: Option<MotionPlan>,
    /// The execution record.
    pub execution: Option<Execution>,
    /// The executed base trace.
    pub trace: Vec<nalgebra::Isometry2<f64>>,
}

impl Attempt {
    fn without_plan(verdict: Verdict, document: Option<MotionDocument>) -> Self {
        Attempt {
            verdict,
            document,
            plan: None,
            execution: None,
            trace: Vec::new(),
        }
    }
}

/// A goal on true joint names: `(joint, min)` targets and start values.
#[derive(Debug, Clone, PartialEq)]
pub struct TrueGoal {
    /// Targets `joint >= min` (rad or m).
    pub goal: Vec<(String, f64)>,
    /// Start values of joints that do not start closed.
    pub start: Vec<(String, f64)>,
    /// The robot's start base pose: x (m), y (m), yaw (rad).
    pub base: [f64; 3],
}

impl TrueGoal {
    /// The start state of the true model.
    ///
    /// # Errors
    /// [`PipelineError::Scene`] for an unknown joint or a value outside its limits.
    pub fn start_state(&self, truth: &SceneModel) -> Result<State, PipelineError> {
        let mut s = truth.zero_state();
        for (j, v) in &self.start {
            s.set_by_name(truth, j, *v)?;
        }
        Ok(s)
    }

    /// The planning problem on the true model.
    ///
    /// # Errors
    /// [`PipelineError::Task`] for unknown joints or targets outside the limits.
    pub fn true_problem(&self, truth: &SceneModel) -> Result<Problem, PipelineError> {
        let spec = goal_spec(self.goal.clone(), self.start.clone(), self.base);
        Ok(Problem::from_spec(truth, &spec)?)
    }
}

/// A goal translated to the estimated model.
pub struct Translated {
    /// The estimated model, with the limits of the named joints widened to hold the start
    /// values and targets (an observed opening is a possible one; the discovery stage only
    /// guessed the upper limit).
    pub model: SceneModel,
    /// The problem on it.
    pub problem: Problem,
    /// Estimated joint name → true joint name.
    pub names: BTreeMap<String, String>,
}

/// Translates `goal` to the estimated model `est` through `matches`. `Err` is the reason it
/// cannot (a goal joint without an estimated part), an outcome of the run, not bad input.
///
/// The true parts no estimated part matches (discovery did not register them, or their
/// handles were never mapped) join the model as static obstacles at their start pose
/// ([`seen_unregistered`]): the map holds what the robot sees, articulated or not.
/// The colliders of the true parts no match names, at the true start state of `goal`, as
/// base shapes named `seen_<part>_<k>`: the kitchen's map is the true static geometry (a
/// perfect SLAM map, see `stages::map`), and a SLAM map of the scene the robot starts in
/// holds these fronts too — only their joints are unknown, so they are fixed. A part whose
/// parent part is registered is left out (it moves with its parent, which the planner may
/// move); parts on an unregistered parent are kept with it.
///
/// # Errors
/// The reason, if the truth rejects the start state (a bug of the sequence table).
pub fn seen_unregistered(
    truth: &SceneModel,
    matches: &[Match],
    goal: &TrueGoal,
) -> Result<Vec<BaseShape>, String> {
    let registered: BTreeSet<&str> = matches.iter().map(|m| m.true_joint.as_str()).collect();
    let start = State::from_values_clamped(truth, goal.start.iter().map(|(n, v)| (n.as_str(), *v)))
        .map_err(|e| format!("the start does not fit the true model: {e}"))?;
    let mut data = SceneData::new(truth);
    forward_kinematics(truth, &mut data, &start).map_err(|e| e.to_string())?;
    let mut shapes = Vec::new();
    for part in truth.parts() {
        let unregistered = truth.path_to_base(part.id()).all(|p| {
            let joint = &truth.joints()[p.joint().index()];
            !registered.contains(joint.name.as_str())
        });
        if !unregistered {
            continue;
        }
        let world_from_part = data.world_from_parts()[part.id().index()];
        for (k, c) in part.colliders().iter().enumerate() {
            shapes.push(BaseShape::new(
                format!("seen_{}_{k}", part.name()),
                c.shape.clone(),
                world_from_part * c.part_from_shape,
            ));
        }
    }
    Ok(shapes)
}

pub fn translate(
    truth: &SceneModel,
    est: &SceneModel,
    matches: &[Match],
    goal: &TrueGoal,
) -> Result<Translated, String> {
    let to_est: BTreeMap<&str, &Match> =
        matches.iter().map(|m| (m.true_joint.as_str(), m)).collect();
    let mut needed: BTreeMap<String, f64> = BTreeMap::new();
    let mut est_goal = Vec::new();
    for (j, min) in &goal.goal {
        let m = to_est
            .get(j.as_str())
            .ok_or_else(|| format!("the estimated model has no part for {j}"))?;
        if m.est_kind != m.true_kind {
            return Err(format!(
                "{j} was estimated as {:?}, not {:?}",
                m.est_kind, m.true_kind
            ));
        }
        est_goal.push((m.est_joint.clone(), *min));
        let e = needed.entry(m.est_joint.clone()).or_insert(*min);
        *e = e.max(*min);
    }
    let mut est_start = Vec::new();
    for (j, v) in &goal.start {
        match to_est.get(j.as_str()) {
            Some(m) if m.est_kind == m.true_kind => {
                est_start.push((m.est_joint.clone(), *v));
                let e = needed.entry(m.est_joint.clone()).or_insert(*v);
                *e = e.max(*v);
            }
            // Start joints the estimated model has no part for stay unknown to the planner.
            _ => {}
        }
    }
    let mut builder = est.to_builder();
    for shape in seen_unregistered(truth, matches, goal)? {
        builder.add_base_shape(shape);
    }
    for part in &mut builder.parts {
        if let Some(v) = needed.get(&part.joint.name) {
            if *v > part.joint.limits.upper {
                part.joint.limits.upper = *v;
            }
        }
    }
    let model = builder
        .build()
        .map_err(|e| format!("the estimated model with widened limits is invalid: {e}"))?;
    // The robot sees the start state, so it is collision-free: boxes overlapping there (a
    // door wide open next to closed drawers) are cut back, as discovery did for the closed
    // scene and each opening it executed.
    let start = State::from_values_clamped(&model, est_start.iter().map(|(n, v)| (n.as_str(), *v)))
        .map_err(|e| format!("the start does not fit the estimated model: {e}"))?;
    let (model, _) = reconcile(
        &model,
        &[Observation::State(start)],
        &SweepSettings::default(),
        None,
    )
    .map_err(|e| format!("cutting back the boxes at the start state: {e}"))?;
    let spec = goal_spec(est_goal, est_start, goal.base);
    let problem = Problem::from_spec(&model, &spec)
        .map_err(|e| format!("the goal does not fit the estimated model: {e}"))?;
    let names = matches
        .iter()
        .map(|m| (m.est_joint.clone(), m.true_joint.clone()))
        .collect();
    Ok(Translated {
        model,
        problem,
        names,
    })
}

/// The planners and budget shared by the attempts.
pub struct Planning<'a> {
    /// The true model.
    pub truth: &'a SceneModel,
    /// The hierarchical planner (lattice search strategy).
    pub planner: &'a HierarchicalPlanner,
    /// Budget of each planner call.
    pub budget: Duration,
}

/// The category of a task-level failure cause.
fn cause_category(cause: &Cause) -> Category {
    match cause {
        Cause::Collision { .. } | Cause::Inconclusive { .. } => Category::PartCollision,
        Cause::PathBlocked { .. } | Cause::Trapped => Category::PathBlocking,
        _ => Category::Other,
    }
}

/// The category of an execution failure.
fn exec_category(c: FailureCategory) -> Category {
    match c {
        FailureCategory::PartCollision => Category::PartCollision,
        FailureCategory::PathBlocked => Category::PathBlocking,
        FailureCategory::GraspLost | FailureCategory::Other => Category::Other,
    }
}

/// The joint type's goal tolerance.
fn tolerance(kind: JointKind) -> f64 {
    match kind {
        JointKind::Revolute => REVOLUTE_TOLERANCE,
        JointKind::Prismatic => PRISMATIC_TOLERANCE,
    }
}

/// Executes `plan` from `goal`'s start and judges the true state.
///
/// # Errors
/// [`PipelineError::Sim`] if the world cannot be reset (a contract violation).
pub fn execute(
    world: &mut SimWorld,
    truth: &SceneModel,
    goal: &TrueGoal,
    plan: &MotionPlan,
    names: &BTreeMap<String, String>,
) -> Result<(Verdict, Execution, Vec<nalgebra::Isometry2<f64>>), PipelineError> {
    world.reset(&goal.start_state(truth)?, pose(goal.base))?;
    let execution = world.execute(plan);
    let state = world.true_state();
    let mut final_values = Vec::new();
    let mut unmet = Vec::new();
    for (j, min) in &goal.goal {
        let id = truth.joint_id(j)?;
        let v = state.value(id).unwrap_or(f64::NAN);
        final_values.push((j.clone(), v));
        let kind = truth.joints()[id.index()].kind;
        if v.is_nan() || v < min - tolerance(kind) {
            unmet.push(format!("{j} at {v:.3} < {min:.3}"));
        }
    }
    let steps = plan
        .steps
        .iter()
        .map(|s| {
            let name = names.get(&s.joint).unwrap_or(&s.joint);
            format!("{name} {:.2}→{:.2}", s.from, s.to)
        })
        .collect();
    let (category, reason) = match (&execution.failure, unmet.is_empty()) {
        (Some(f), _) => (
            exec_category(f.category),
            format!("execution: {}", f.reason),
        ),
        (None, true) => (Category::Success, String::new()),
        (None, false) => (
            Category::Other,
            format!("executed, but the goal is missed: {}", unmet.join(", ")),
        ),
    };
    let verdict = Verdict {
        category,
        reason,
        steps,
        final_values,
        base_time: execution.steps.iter().map(|s| s.base_time).sum(),
        arm_time: execution.steps.iter().map(|s| s.arm_time).sum(),
    };
    let trace = world.base_trace().to_vec();
    Ok((verdict, execution, trace))
}

/// Plans with the hierarchical planner on `model` and executes a solved plan. A planner
/// `Err` on an estimated model is an outcome of the run ("other"), not an error of the
/// pipeline.
///
/// # Errors
/// [`PipelineError::Sim`] if the world cannot be reset.
pub fn plan_and_execute(
    p: &Planning<'_>,
    world: &mut SimWorld,
    model: &SceneModel,
    problem: &Problem,
    goal: &TrueGoal,
    names: &BTreeMap<String, String>,
    cached: Option<&PlannerResult>,
) -> Result<(Attempt, Option<PlannerResult>), PipelineError> {
    let result = match cached {
        Some(r) => r.clone(),
        None => match p
            .planner
            .plan(model, problem, &Termination::after(p.budget))
        {
            Ok(r) => r,
            Err(e) => {
                let v = Verdict::failed(Category::Other, format!("planner error: {e}"));
                return Ok((Attempt::without_plan(v, None), None));
            }
        },
    };
    let document = MotionDocument::from_result(&result, p.planner.robot().name());
    let attempt = match &result.outcome {
        MotionOutcome::Solved(plan) => {
            let (verdict, execution, trace) = execute(world, p.truth, goal, plan, names)?;
            Attempt {
                verdict,
                document: Some(document),
                plan: Some(plan.clone()),
                execution: Some(execution),
                trace,
            }
        }
        MotionOutcome::Infeasible(why) => {
            let mut reason = format!("no plan: {}", why.task.message);
            if let Some(v) = why.vetoes.first() {
                reason.push_str(&format!(" (first veto: {v})"));
            }
            Attempt::without_plan(Verdict::failed(Category::Other, reason), Some(document))
        }
        MotionOutcome::Timeout(progress) | MotionOutcome::Cancelled(progress) => {
            Attempt::without_plan(
                Verdict::failed(Category::Other, format!("planner timeout: {progress}")),
                Some(document),
            )
        }
    };
    Ok((attempt, Some(result)))
}

/// The paper's Random baseline on `model`: one random order of the goal joints (task layer,
/// [`Strategy::Random`]); an order the task layer rejects fails with its cause's category
/// (the failure it predicts), one it accepts is refined with
/// [`HierarchicalPlanner::refine`] and executed.
///
/// # Errors
/// [`PipelineError::Sim`] if the world cannot be reset.
pub fn random(
    p: &Planning<'_>,
    world: &mut SimWorld,
    t: &Translated,
    goal: &TrueGoal,
    seed: u64,
) -> Result<Attempt, PipelineError> {
    let settings = TaskSettings {
        strategy: Strategy::Random { seed },
        ..p.planner.settings().task.clone()
    };
    let termination = Termination::after(p.budget);
    let result = match task::plan(&t.model, &t.problem, &settings, &NoRefinement, &termination) {
        Ok(r) => r,
        Err(e) => {
            let v = Verdict::failed(Category::Other, format!("task layer error: {e}"));
            return Ok(Attempt::without_plan(v, None));
        }
    };
    let robot = p.planner.robot().name().to_string();
    let doc = |outcome: MotionOutcome, stats: &SearchStats| {
        MotionDocument::from_result(
            &PlannerResult {
                outcome,
                task_plans: 1,
                task_stats: stats.clone(),
                task_time: 0.0,
                motion_time: 0.0,
            },
            &robot,
        )
    };
    let plan = match result.outcome {
        Outcome::Solved(plan) => plan,
        Outcome::Infeasible(why) => {
            let category = why
                .conflicts
                .first()
                .map_or(Category::Other, |f| cause_category(&f.cause));
            let document = doc(
                MotionOutcome::Infeasible(MotionInfeasibility {
                    task: why.clone(),
                    vetoes: Vec::new(),
                }),
                &result.stats,
            );
            let v = Verdict::failed(
                category,
                format!("task layer rejects the order: {}", why.message),
            );
            return Ok(Attempt::without_plan(v, Some(document)));
        }
        Outcome::Timeout(_) | Outcome::Cancelled(_) => {
            let v = Verdict::failed(Category::Other, "task layer timeout");
            return Ok(Attempt::without_plan(v, None));
        }
    };
    let refined = match p.planner.refine(&t.model, &t.problem, &plan, &termination) {
        Ok(r) => r,
        Err(e) => {
            let v = Verdict::failed(Category::Other, format!("refinement error: {e}"));
            return Ok(Attempt::without_plan(v, None));
        }
    };
    match refined {
        RefineOutcome::Solved(mplan) => {
            let document = doc(MotionOutcome::Solved(mplan.clone()), &result.stats);
            let (verdict, execution, trace) = execute(world, p.truth, goal, &mplan, &t.names)?;
            Ok(Attempt {
                verdict,
                document: Some(document),
                plan: Some(mplan),
                execution: Some(execution),
                trace,
            })
        }
        RefineOutcome::Infeasible(failure) => {
            // A step the motion layer cannot refine (no base pose, no arm or base path) is
            // "other": path blocking is the task layer's path check or the simulator's.
            let category = Category::Other;
            let reason = format!("the order does not refine: {failure}");
            let document = doc(
                MotionOutcome::Infeasible(MotionInfeasibility {
                    task: Infeasibility {
                        message: reason.clone(),
                        unreached: Vec::new(),
                        conflicts: Vec::new(),
                        start_collisions: Vec::new(),
                    },
                    vetoes: vec![failure],
                }),
                &result.stats,
            );
            Ok(Attempt::without_plan(
                Verdict::failed(category, reason),
                Some(document),
            ))
        }
        RefineOutcome::Timeout(step) | RefineOutcome::Cancelled(step) => Ok(Attempt::without_plan(
            Verdict::failed(Category::Other, format!("refinement timeout: {step}")),
            None,
        )),
    }
}
