//! The three stages on any scene URDF that follows the scene conventions, with a goal file: mapping from viewpoints computed from the base map, discovery of every mapped
//! handle, and the goal (on the true scene's joint names) translated to the estimated model,
//! planned with the hierarchical planner and executed in the simulator.
//!
//! The output folder receives `twin.urdf` (the estimated scene), `discovery.json` (the
//! discovery log), `plans/goal.json` and `plans/goal.exec.json` (the plan document and the
//! execution record) and `report.md` / `report.json` ([`SceneRunReport`]).

use std::path::{Path, PathBuf};
use std::time::Duration;

use kinscene::kinematics::robot::RobotModel;
use kinscene::planner::{HierarchicalPlanner, MotionOutcome};
use kinscene::scene::{JointKind, SceneModel};
use kinscene::task::{GoalSpec, Problem};
use serde::Serialize;

use super::config::Config;
use super::manipulation::{Planning, TrueGoal, Verdict, plan_and_execute, translate};
use super::matching::{self, Match};
use super::output::Outputs;
use super::progress::Progress;
use super::session::{discovery_run, sim_settings, twin};
use super::sim::SimWorld;
use super::stages::{self, MappingSummary, pose};
use super::summary::DiscoveryRun;
use super::viewpoints::{ViewpointSettings, viewpoints};
use super::{PipelineError, planner_settings};

/// What a run on a scene file produced.
#[derive(Debug, Clone, Serialize)]
pub struct SceneRunReport {
    /// The scene file.
    pub scene: String,
    /// The goal file.
    pub goal: String,
    /// The true scene's joints (with a handle).
    pub joints: Vec<String>,
    /// The robot's start pose: x (m), y (m), yaw (rad).
    pub start: [f64; 3],
    /// The computed mapping viewpoints: x (m), y (m), yaw (rad), in order.
    pub viewpoints: Vec<[f64; 3]>,
    /// The mapping stage.
    pub mapping: MappingSummary,
    /// The discovery stage, its parts matched to the true ones.
    pub discovery: DiscoveryRun,
    /// Joints of the estimated twin, and whether it loads back from its URDF.
    pub twin: (usize, Result<usize, String>),
    /// The plan's verdict: solved with its steps (true names), or why there is none.
    pub plan: PlanSummary,
    /// The execution's verdict (when a plan was executed).
    pub execution: Option<Verdict>,
}

/// The plan for the goal on the estimated model.
#[derive(Debug, Clone, Serialize)]
pub struct PlanSummary {
    /// `solved`, `infeasible`, `timeout`, `cancelled`, or `not planned` (the goal has no
    /// estimated part to act on, or the planner rejected its input).
    pub status: String,
    /// The steps, `joint from → to` (true names where known).
    pub steps: Vec<String>,
    /// Why there is no plan, if there is none.
    pub reason: String,
}

/// The goal document at `path`.
///
/// # Errors
/// [`PipelineError::Io`] for an unreadable file, [`PipelineError::Task`] for a malformed one.
fn goal_spec(path: &Path) -> Result<GoalSpec, PipelineError> {
    let text = std::fs::read_to_string(path).map_err(|e| PipelineError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    Ok(GoalSpec::from_toml(&text)?)
}

/// The goal of `problem` (resolved on the true scene) as lower bounds on true joint names:
/// each target's interval must reach its joint's upper limit (`{ min = ... }`), since the
/// translation to the estimated model widens the estimated limits to hold the targets.
fn true_goal(
    truth: &SceneModel,
    problem: &Problem,
    spec: &GoalSpec,
    base: [f64; 3],
) -> Result<TrueGoal, PipelineError> {
    let mut goal = Vec::new();
    for (id, interval) in problem.goal.targets() {
        let joint = &truth.joints()[id.index()];
        if interval.max < joint.limits.upper - 1e-9 {
            return Err(PipelineError::Config(format!(
                "the target of {} is [{}, {}]: a run on a scene file takes opening targets \
                 `{{ min = ... }}` (up to the joint's upper limit {})",
                joint.name, interval.min, interval.max, joint.limits.upper
            )));
        }
        goal.push((joint.name.clone(), interval.min));
    }
    Ok(TrueGoal {
        goal,
        start: spec.start.iter().map(|(j, v)| (j.clone(), *v)).collect(),
        base,
    })
}

/// Runs mapping, discovery and the goal file `goal` on the scene `config.scene` (seed
/// `config.seed`), and writes the outputs to `out`. The robot starts at the goal file's
/// `[robot] base`.
///
/// # Errors
/// [`PipelineError`] for an unreadable scene or goal file, a goal that does not fit the scene
/// or gives no start pose, or an output file that cannot be written. What the stages conclude (handles
/// missed, parts not registered, no plan, a failed execution) is in the report.
pub fn run_scene(
    config: &Config,
    goal: &Path,
    out: Option<&Path>,
    progress: bool,
) -> Result<SceneRunReport, PipelineError> {
    config.validate()?;
    let truth = SceneModel::from_urdf_file(&config.scene)?;
    let scene_dir: PathBuf = config
        .scene
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let truth_parts = matching::part_axes(&truth)?;
    let spec = goal_spec(goal)?;
    let problem = Problem::from_goal_file(&truth, goal)?;
    let start = spec.robot.base.ok_or_else(|| {
        PipelineError::Config(format!(
            "{}: give the robot's start pose as [robot] base = [x, y, yaw]",
            goal.display()
        ))
    })?;
    let true_goal = true_goal(&truth, &problem, &spec, start)?;
    let robot = RobotModel::try_kinova_gen3_mobile()?;
    let ui = Progress::new(progress, 0);
    let views = viewpoints(
        truth.base(),
        robot.base().footprint_radius,
        start,
        &ViewpointSettings::default(),
    )?;
    ui.say(format!(
        "{}: {} parts with handles; {} viewpoints from the base map",
        config.scene.display(),
        truth_parts.len(),
        views.len()
    ));
    let mut world = SimWorld::new(
        &truth,
        &robot,
        pose(start),
        sim_settings(config, config.seed),
    )?;
    let (mut handles, mapping) = stages::map(&mut world, truth.base(), &views, &truth_parts)?;
    stages::selection_order(&mut handles, start);
    ui.say(format!(
        "mapping: {} detections, {} handles registered ({} of {} true handles), {} false",
        mapping.detections,
        mapping.registered,
        mapping.true_mapped.len(),
        truth_parts.len(),
        mapping.false_positives
    ));
    let (discovery, row) = discovery_run(
        &mut world,
        truth.base(),
        &handles,
        config.estimator,
        &config.discovery,
        &truth_parts,
    )?;
    ui.say(format!(
        "discovery ({}): {} parts registered, {} matched to true parts",
        row.estimator,
        row.registered,
        row.matches.len()
    ));
    let est = discovery.model.clone();
    let mut outputs = Outputs::default();
    let (xml, back) = twin(&est, &scene_dir);
    if !xml.is_empty() {
        outputs.add("twin.urdf", xml);
    }
    if let Ok(json) = serde_json::to_string_pretty(&discovery.log) {
        outputs.add("discovery.json", json);
    }
    let planner = HierarchicalPlanner::new(robot.clone(), planner_settings(config))?;
    let planning = Planning {
        truth: &truth,
        planner: &planner,
        budget: Duration::from_secs_f64(config.planner_budget),
    };
    let (plan, execution) = manipulate(
        &planning,
        &mut world,
        &est,
        &row.matches,
        &true_goal,
        &mut outputs,
    )?;
    {
        let p = &plan;
        ui.say(format!(
            "plan: {}{}",
            p.status,
            if p.reason.is_empty() {
                format!(" ({})", p.steps.join(", "))
            } else {
                format!(" ({})", p.reason)
            }
        ));
    }
    if let Some(v) = &execution {
        ui.say(format!(
            "execution: {}{}",
            v.category.name(),
            if v.reason.is_empty() {
                String::new()
            } else {
                format!(" ({})", v.reason)
            }
        ));
    }
    let shown = |p: &Path| {
        p.strip_prefix(crate::repository())
            .unwrap_or(p)
            .display()
            .to_string()
    };
    let report = SceneRunReport {
        scene: shown(&config.scene),
        goal: shown(goal),
        joints: truth_parts.iter().map(|p| p.joint.clone()).collect(),
        start,
        viewpoints: views,
        mapping,
        discovery: row,
        twin: (est.nq(), back),
        plan,
        execution,
    };
    if let Some(out) = out {
        outputs.add("report.md", report.to_markdown());
        outputs.add(
            "report.json",
            serde_json::to_string_pretty(&report).unwrap_or_default(),
        );
        outputs.write(out)?;
        super::copy_meshes(&scene_dir, out)?;
    }
    Ok(report)
}

/// Stage 3 for the goal: translated to the estimated model, planned, executed when solved.
fn manipulate(
    planning: &Planning<'_>,
    world: &mut SimWorld,
    est: &SceneModel,
    matches: &[Match],
    goal: &TrueGoal,
    outputs: &mut Outputs,
) -> Result<(PlanSummary, Option<Verdict>), PipelineError> {
    let translated = match translate(planning.truth, est, matches, goal) {
        Ok(t) => t,
        Err(reason) => {
            let plan = PlanSummary {
                status: "not planned".into(),
                steps: Vec::new(),
                reason,
            };
            return Ok((plan, None));
        }
    };
    let (attempt, result) = plan_and_execute(
        planning,
        world,
        &translated.model,
        &translated.problem,
        goal,
        &translated.names,
        None,
    )?;
    outputs.add_attempt("goal", &attempt);
    let status = match result.as_ref().map(|r| &r.outcome) {
        Some(MotionOutcome::Solved(_)) => "solved",
        Some(MotionOutcome::Infeasible(_)) => "infeasible",
        Some(MotionOutcome::Timeout(_)) => "timeout",
        Some(MotionOutcome::Cancelled(_)) => "cancelled",
        None => "not planned",
    };
    let solved = attempt.plan.is_some();
    let plan = PlanSummary {
        status: status.into(),
        steps: attempt.verdict.steps.clone(),
        reason: if solved {
            String::new()
        } else {
            attempt.verdict.reason.clone()
        },
    };
    Ok((plan, solved.then_some(attempt.verdict)))
}

impl SceneRunReport {
    /// The report as markdown: what was mapped, what was registered (estimated against true
    /// axes), the plan and the execution.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let mut line = |t: String| {
            s.push_str(&t);
            s.push('\n');
        };
        line(format!("# kinscene on {}\n", self.scene));
        line(format!(
            "Goal: {}. Robot start: ({:.2} m, {:.2} m, {:.0}°). True parts with a handle: {} \
             ({}).\n",
            self.goal,
            self.start[0],
            self.start[1],
            self.start[2].to_degrees(),
            self.joints.len(),
            self.joints.join(", ")
        ));
        line("## Mapping\n".into());
        line(format!(
            "{} viewpoints computed from the base map; {} detections, {} handles after fusion, \
             {} registered against the base map ({} rejected), {} of {} true handles mapped, {} \
             false positives; {:.1} s of base motion.\n",
            self.viewpoints.len(),
            self.mapping.detections,
            self.mapping.fused,
            self.mapping.registered,
            self.mapping.rejected,
            self.mapping.true_mapped.len(),
            self.joints.len(),
            self.mapping.false_positives,
            self.mapping.base_time
        ));
        line("| view | x (m) | y (m) | yaw (°) | reached | detections | note |".into());
        line("|---|---|---|---|---|---|---|".into());
        for (k, v) in self.mapping.views.iter().enumerate() {
            line(format!(
                "| {} | {:.2} | {:.2} | {:.0} | {} | {} | {} |",
                k + 1,
                v.pose[0],
                v.pose[1],
                v.pose[2].to_degrees(),
                if v.reached { "yes" } else { "no" },
                v.detections,
                v.note.as_deref().unwrap_or("")
            ));
        }
        let unmapped: Vec<&str> = self
            .joints
            .iter()
            .filter(|j| !self.mapping.true_mapped.contains(j))
            .map(String::as_str)
            .collect();
        if !unmapped.is_empty() {
            line(format!("\nNot mapped: {}.", unmapped.join(", ")));
        }
        line("\n## Discovery\n".into());
        let d = &self.discovery;
        line(format!(
            "{} estimator: {} handles explored, {} parts registered, {} matched to true parts; \
             {:.1} s base, {:.1} s arm.\n",
            d.estimator,
            d.handles.len(),
            d.registered,
            d.matches.len(),
            d.base_time,
            d.arm_time
        ));
        line(
            "| true joint | estimated | true type | estimated type | axis angle error (°) | \
             axis position error (cm) | handle distance (cm) |"
                .into(),
        );
        line("|---|---|---|---|---|---|---|".into());
        let kind = |k: JointKind| match k {
            JointKind::Revolute => "revolute",
            JointKind::Prismatic => "prismatic",
        };
        for m in &d.matches {
            line(format!(
                "| {} | {} | {} | {} | {:.1} | {} | {:.1} |",
                m.true_joint,
                m.est_joint,
                kind(m.true_kind),
                kind(m.est_kind),
                m.registered_angle_error,
                m.position_error
                    .map_or("–".into(), |e| format!("{:.1}", 100.0 * e)),
                100.0 * m.handle_distance
            ));
        }
        let unregistered: Vec<&str> = self
            .joints
            .iter()
            .filter(|j| !d.matches.iter().any(|m| &&m.true_joint == j))
            .map(String::as_str)
            .collect();
        if !unregistered.is_empty() {
            line(format!("\nNot registered: {}.", unregistered.join(", ")));
        }
        line("\nPer explored handle (selection order):\n".into());
        line("| # | true part | outcome |".into());
        line("|---|---|---|".into());
        for (k, h) in d.handles.iter().enumerate() {
            line(format!(
                "| {} | {} | {} |",
                k + 1,
                h.true_joint.as_deref().unwrap_or("(none)"),
                h.outcome
            ));
        }
        line(format!(
            "\nTwin: `twin.urdf`, {} joints; {}.",
            self.twin.0,
            match &self.twin.1 {
                Ok(n) => format!("loads back with {n} joints"),
                Err(e) => format!("does not load back: {e}"),
            }
        ));
        {
            let p = &self.plan;
            line("\n## Plan\n".into());
            line(format!("Status: **{}**.", p.status));
            if !p.steps.is_empty() {
                line(format!("Steps: {}.", p.steps.join("; ")));
            }
            if !p.reason.is_empty() {
                line(format!("Reason: {}.", p.reason));
            }
        }
        if let Some(v) = &self.execution {
            line("\n## Execution\n".into());
            line(format!(
                "Verdict (on the simulator's true state): **{}**{}.",
                v.category.name(),
                if v.reason.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", v.reason)
                }
            ));
            let values: Vec<String> = v
                .final_values
                .iter()
                .map(|(j, x)| format!("{j} = {x:.3}"))
                .collect();
            line(format!(
                "Final goal joints: {}; {:.1} s base, {:.1} s arm.",
                values.join(", "),
                v.base_time,
                v.arm_time
            ));
        }
        s
    }
}
