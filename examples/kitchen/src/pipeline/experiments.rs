//! The pieces of the experiments that are not stages: the task-level checks of the goal
//! sequences, the old task-level table, the per-handle discovery rows, Fig. 6 and the type
//! checks of Table II, and the Table I measurement of one part.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant};

use kinscene::articulation::ArticulationEstimator;
use kinscene::discovery::{
    Discovery, DiscoverySettings, Exploration, MappedHandle, Stage, discover,
};
use kinscene::scene::{BaseMap, JointKind, SceneModel};
use kinscene::task::{
    self, GoalSpec, NoRefinement, Outcome, Problem, Strategy, TaskSettings, Termination, validate,
};

use super::PipelineError;
use super::manipulation::{Attempt, Category, Planning, TrueGoal, plan_and_execute, translate};
use super::matching::{MATCH_RADIUS, Match, PartAxis, nearest_part};
use super::sequences::{START_BASE, Sequence};
use super::sim::{Clock, SimWorld};
use super::stages::{Recorder, pose};
use super::summary::{
    Fig6Row, HandleRow, SequenceCheck, THRESHOLD_PRISMATIC, THRESHOLD_REVOLUTE, Table1Row,
    TaskLevelRow, TypeCheck,
};

/// Random orders tried per sequence in the task-level check.
const RANDOM_CHECKS: u64 = 12;

/// `joint from → to` of a task step.
fn step_text(s: &task::Step) -> String {
    format!("{} {:.2}→{:.2}", s.joint, s.from, s.to)
}

/// Checks every sequence on the true model at the task level: the lattice search solves it,
/// and how many of the Random orders (seeds `0..12`) the task layer rejects, by category.
///
/// # Errors
/// [`PipelineError::Task`] for a sequence that does not fit the model.
pub fn check_sequences(
    truth: &SceneModel,
    sequences: &[Sequence],
    settings: &TaskSettings,
) -> Result<Vec<SequenceCheck>, PipelineError> {
    let mut out = Vec::new();
    for q in sequences {
        let problem = Problem::from_spec(truth, &q.spec(START_BASE))?;
        let result = task::plan(
            truth,
            &problem,
            settings,
            &NoRefinement,
            &Termination::after(Duration::from_secs(30)),
        )?;
        let (search, order) = match &result.outcome {
            Outcome::Solved(p) => (
                format!("solved, {} steps", p.steps.len()),
                p.steps.iter().map(step_text).collect(),
            ),
            Outcome::Infeasible(why) => (format!("infeasible ({})", why.message), Vec::new()),
            Outcome::Timeout(_) | Outcome::Cancelled(_) => ("timeout".to_string(), Vec::new()),
        };
        let mut rejected = BTreeMap::new();
        for seed in 0..RANDOM_CHECKS {
            let s = TaskSettings {
                strategy: Strategy::Random { seed },
                ..settings.clone()
            };
            let r = task::plan(
                truth,
                &problem,
                &s,
                &NoRefinement,
                &Termination::after(Duration::from_secs(30)),
            )?;
            if let Outcome::Infeasible(why) = r.outcome {
                let category = why
                    .conflicts
                    .first()
                    .map_or(Category::Other, |f| match f.cause {
                        task::Cause::Collision { .. } | task::Cause::Inconclusive { .. } => {
                            Category::PartCollision
                        }
                        task::Cause::PathBlocked { .. } | task::Cause::Trapped => {
                            Category::PathBlocking
                        }
                        _ => Category::Other,
                    });
                *rejected.entry(category.name().to_string()).or_insert(0) += 1;
            }
        }
        let text = |v: &[(&str, f64)], op: &str| {
            v.iter()
                .map(|(j, x)| format!("{j} {op} {x}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        out.push(SequenceCheck {
            name: q.name.to_string(),
            about: q.about.to_string(),
            goal: text(q.goal, "≥"),
            start: text(q.start, "="),
            search,
            order,
            random_rejected: rejected,
            random_tried: RANDOM_CHECKS as usize,
        });
    }
    Ok(out)
}

/// The old example's table: every goal file in `goals` on `truth` with the lattice search, the
/// validator and the Random and Paper baselines (seed 1). Unreadable files are rows saying so;
/// goal files of other scenes (whose targets name no joint of `truth`, such as the counter's
/// and the galley's) are left out.
///
/// # Errors
/// [`PipelineError::Io`] if the directory cannot be listed.
pub fn task_level(truth: &SceneModel, goals: &Path) -> Result<Vec<TaskLevelRow>, PipelineError> {
    let io = |e: std::io::Error| PipelineError::Io {
        path: goals.display().to_string(),
        message: e.to_string(),
    };
    let mut files: Vec<_> = std::fs::read_dir(goals)
        .map_err(io)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    let mut rows = Vec::new();
    for f in files {
        let name = f
            .file_stem()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_default();
        let row = |search: String| TaskLevelRow {
            goal: name.clone(),
            search,
            steps: "–".into(),
            valid: "–".into(),
            random: "–".into(),
            paper: "–".into(),
            wall_ms: 0.0,
        };
        let spec = std::fs::read_to_string(&f)
            .map_err(|e| e.to_string())
            .and_then(|t| GoalSpec::from_toml(&t).map_err(|e| e.to_string()));
        if let Ok(spec) = &spec
            && !spec.goal.is_empty()
            && spec.goal.keys().all(|j| truth.joint_id(j).is_err())
        {
            continue;
        }
        let problem = match spec
            .and_then(|spec| Problem::from_spec(truth, &spec).map_err(|e| e.to_string()))
        {
            Ok(p) => p,
            Err(e) => {
                rows.push(row(format!("bad goal file: {e}")));
                continue;
            }
        };
        let settings = TaskSettings::default();
        let t0 = Instant::now();
        let result = task::plan(
            truth,
            &problem,
            &settings,
            &NoRefinement,
            &Termination::after(Duration::from_secs(30)),
        )?;
        let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        let mut r = row(String::new());
        r.wall_ms = wall_ms;
        match &result.outcome {
            Outcome::Solved(p) => {
                let v = validate(truth, &problem, &p.steps, &settings)?;
                r.search = "solved".into();
                r.steps = p.steps.len().to_string();
                r.valid = if v.valid { "valid" } else { "INVALID" }.into();
            }
            Outcome::Infeasible(_) => r.search = "infeasible".into(),
            Outcome::Timeout(_) | Outcome::Cancelled(_) => r.search = "timeout".into(),
        }
        let baseline = |strategy| -> Result<String, PipelineError> {
            let s = TaskSettings {
                strategy,
                ..TaskSettings::default()
            };
            let b = task::plan(
                truth,
                &problem,
                &s,
                &NoRefinement,
                &Termination::after(Duration::from_secs(10)),
            )?;
            Ok(match b.outcome {
                Outcome::Solved(p) if validate(truth, &problem, &p.steps, &settings)?.valid => {
                    "solved".into()
                }
                Outcome::Solved(_) => "solved, invalid".into(),
                Outcome::Infeasible(_) => "failed".into(),
                Outcome::Timeout(_) | Outcome::Cancelled(_) => "timeout".into(),
            })
        };
        r.random = baseline(Strategy::Random { seed: 1 })?;
        r.paper = baseline(Strategy::Paper { seed: 1 })?;
        rows.push(r);
    }
    Ok(rows)
}

/// One row per explored handle of `d` (`handles` is the input in exploration order).
pub fn handle_rows(truth: &[PartAxis], handles: &[MappedHandle], d: &Discovery) -> Vec<HandleRow> {
    d.log
        .iter()
        .map(|l| {
            let mapped = handles.get(l.index).map_or(l.mapped, |h| h.position);
            HandleRow {
                index: l.index,
                mapped: [mapped.x, mapped.y, mapped.z],
                true_joint: nearest_part(truth, &mapped, MATCH_RADIUS)
                    .map(|i| truth[i].joint.clone()),
                outcome: match &l.outcome {
                    Exploration::Registered { joint, parent, .. } => match parent {
                        Some(p) => format!("registered {joint} (on {p})"),
                        None => format!("registered {joint}"),
                    },
                    Exploration::Failed { stage, reason } => {
                        format!("failed at {stage:?}: {reason}")
                    }
                },
                attempts: l.attempts.len(),
                pull: l.pull_distance,
                estimate: l.estimate.as_ref().map(|e| e.kind.clone()),
            }
        })
        .collect()
}

/// The Fig. 6 row of one run over the true parts `considered`.
pub fn fig6_row(
    run: usize,
    considered: &[&PartAxis],
    all_truth: &[PartAxis],
    handles: &[MappedHandle],
    d: &Discovery,
    matches: &[Match],
) -> Fig6Row {
    let mut row = Fig6Row {
        run,
        handles: considered.len(),
        mapping: 0,
        navigation: 0,
        exploration: 0,
        estimation: 0,
        false_positives: (0, 0),
    };
    for t in considered {
        let log = d
            .log
            .iter()
            .filter_map(|l| {
                let h = handles.get(l.index)?;
                let dist = (h.position - t.handle).norm();
                (dist <= MATCH_RADIUS).then_some((dist, l))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, l)| l);
        let Some(l) = log else {
            continue;
        };
        row.mapping += usize::from(l.passed(Stage::Mapping));
        row.navigation += usize::from(l.passed(Stage::Navigation));
        row.exploration += usize::from(l.passed(Stage::Exploration));
        if let Exploration::Registered { joint, .. } = &l.outcome {
            let right = matches.iter().any(|m| {
                &m.est_joint == joint && m.true_joint == t.joint && m.est_kind == m.true_kind
            });
            row.estimation += usize::from(right);
        }
    }
    for l in &d.log {
        let Some(h) = handles.get(l.index) else {
            continue;
        };
        if nearest_part(all_truth, &h.position, MATCH_RADIUS).is_none() {
            row.false_positives.0 += 1;
            row.false_positives.1 += usize::from(l.succeeded());
        }
    }
    row
}

/// The type check of every estimate of a true part's handle.
pub fn type_checks(
    run: usize,
    estimator: &str,
    truth: &[PartAxis],
    handles: &[MappedHandle],
    d: &Discovery,
) -> Vec<TypeCheck> {
    d.log
        .iter()
        .filter_map(|l| {
            let e = l.estimate.as_ref()?;
            let h = handles.get(l.index)?;
            let t = &truth[nearest_part(truth, &h.position, MATCH_RADIUS)?];
            Some(TypeCheck {
                run,
                estimator: estimator.to_string(),
                joint: t.joint.clone(),
                estimated: e.kind.clone(),
                correct: e.kind == t.kind.as_str(),
            })
        })
        .collect()
}

/// What Table I needs from a run.
pub struct Table1Context<'a> {
    /// Planners and budget.
    pub planning: &'a Planning<'a>,
    /// The static base map.
    pub base: &'a BaseMap,
    /// The run's estimator.
    pub estimator: &'a dyn ArticulationEstimator,
    /// Discovery settings.
    pub settings: &'a DiscoverySettings,
    /// True parts.
    pub truth: &'a [PartAxis],
    /// The run's mapped handles.
    pub handles: &'a [MappedHandle],
    /// The run's estimated model and matches.
    pub estimated: (&'a SceneModel, &'a [Match]),
}

/// The Table I rows of one part and the planner attempts behind them (method name, attempt).
pub type Table1Part = (Vec<Table1Row>, Vec<(&'static str, Attempt)>);

/// Table I for one part: Exploration-only (Algorithm 1 on its handle alone, from the start
/// pose), then Ours and Oracle from the pose the exploration's global navigation reached.
/// Returns the three rows and the two planner attempts (for the plan files).
///
/// # Errors
/// Simulator resets and discovery contract violations.
pub fn table1_part(
    c: &Table1Context<'_>,
    world: &mut SimWorld,
    run: usize,
    joint: &str,
    target: f64,
) -> Result<Table1Part, PipelineError> {
    let truth_model = c.planning.truth;
    let Some(t) = c.truth.iter().find(|t| t.joint == joint) else {
        return Err(PipelineError::Config(format!(
            "no true part has joint {joint}"
        )));
    };
    let jid = truth_model.joint_id(joint)?;
    let row = |method: &str| Table1Row {
        run,
        joint: joint.to_string(),
        kind: t.kind,
        method: method.to_string(),
        target,
        reached: None,
        base_time: None,
        arm_time: None,
        global_time: None,
        to_threshold: None,
        note: String::new(),
    };
    // The paper's execution time runs until the joint has moved 30° / 5 cm; every reset
    // below starts the watch over.
    let threshold = match t.kind {
        JointKind::Revolute => THRESHOLD_REVOLUTE,
        JointKind::Prismatic => THRESHOLD_PRISMATIC,
    };
    world.watch(joint, threshold)?;
    let since =
        |at: Option<Clock>, start: Clock| at.map(|c| (c.base - start.base, c.arm - start.arm));
    let mut rows = Vec::new();
    let mut approach = START_BASE;
    let mapped = c
        .handles
        .iter()
        .filter(|h| (h.position - t.handle).norm() <= MATCH_RADIUS)
        .min_by(|a, b| {
            (a.position - t.handle)
                .norm()
                .total_cmp(&(b.position - t.handle).norm())
        });
    let mut explored = row("Exploration-only");
    match mapped {
        None => explored.note = "the handle was not mapped in this run".into(),
        Some(h) => {
            world.reset(&truth_model.zero_state(), pose(START_BASE))?;
            let mut rec = Recorder::new(world);
            let d = discover(
                &mut rec,
                c.base,
                std::slice::from_ref(h),
                c.estimator,
                c.settings,
            )?;
            let legs = rec.legs.clone();
            let end = world.clock();
            let after = legs.first().map(|l| l.after).unwrap_or(end);
            if let Some(p) = legs.first().and_then(|l| l.reached) {
                approach = super::stages::pose_array(&p);
            }
            explored.global_time = legs.first().map(|l| l.after.base - l.before.base);
            explored.to_threshold = since(world.threshold_reached(), after);
            explored.base_time = Some(end.base - after.base);
            explored.arm_time = Some(end.arm - after.arm);
            explored.reached = world.true_state().value(jid);
            if let Some(l) = d.log.first() {
                if let Exploration::Failed { stage, reason } = &l.outcome {
                    explored.note = format!("discovery failed at {stage:?}: {reason}");
                }
            }
        }
    }
    rows.push(explored);
    let goal = TrueGoal {
        goal: vec![(joint.to_string(), target)],
        start: Vec::new(),
        base: approach,
    };
    let mut attempts = Vec::new();
    let (est, matches) = c.estimated;
    let ours_start = world.clock();
    let ours = match translate(truth_model, est, matches, &goal) {
        Ok(tr) => Some(plan_and_execute(
            c.planning,
            world,
            &tr.model,
            &tr.problem,
            &goal,
            &tr.names,
            None,
        )?),
        Err(reason) => {
            let mut r = row("Ours");
            r.note = reason;
            rows.push(r);
            None
        }
    };
    let ours_reached = world.threshold_reached();
    let problem = goal.true_problem(truth_model)?;
    let names: BTreeMap<String, String> = [(joint.to_string(), joint.to_string())].into();
    let oracle_start = world.clock();
    let oracle = plan_and_execute(
        c.planning,
        world,
        truth_model,
        &problem,
        &goal,
        &names,
        None,
    )?;
    let oracle_reached = world.threshold_reached();
    for (method, a, start, at) in [
        ("Ours", ours, ours_start, ours_reached),
        ("Oracle", Some(oracle), oracle_start, oracle_reached),
    ] {
        let Some((a, _)) = a else {
            continue;
        };
        let mut r = row(method);
        let v = &a.verdict;
        if a.execution.is_some() {
            r.reached = v.final_values.first().map(|x| x.1);
            r.base_time = Some(v.base_time);
            r.arm_time = Some(v.arm_time);
            r.to_threshold = since(at, start);
        }
        if v.category != Category::Success {
            r.note = format!("{}: {}", v.category.name(), v.reason);
        }
        rows.push(r);
        attempts.push((method, a));
    }
    Ok((rows, attempts))
}
