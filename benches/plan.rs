//! The hierarchical planner on the shipped goal files with the shipped Gen3: the plan time
//! (task search plus motion refinement) per goal, and the executed time of the same plan timed
//! with corners blended (the default, [`time_optimal`]) and with a stop at every corner
//! (`blend: None`, [`time_parameterise`]), and without the time shortcuts of the free arm
//! paths (`arm_time_shortcuts: 0`, `arm_random_shortcuts: 0`).
//!
//! `cargo bench --bench plan` (optionally `-- RUNS`, default 3; `-- RUNS GOAL_NAME…` for some
//! goals only; `fixed-base` among the arguments sets [`PlannerSettings::whole_body`] to `None` and
//! `bar-turn=RAD` [`PlacementSettings::bar_turn`](kinscene::motion::placement::PlacementSettings::bar_turn) in every configuration, to measure a
//! setting against the defaults in two commands).
//!
//! Every goal in `examples/scenes/goals/` is planned on the scene its header names
//! (`examples/scenes/<scene>.urdf`: the kitchen, the appliances, the counter, the galley)
//! `RUNS` times with
//! [`PlannerSettings::default`] (seeded: every run gives the same plan, so the runs measure the
//! time only), once more with `blend: None` and once without the time shortcuts. The table
//! gives the outcome, the median and largest plan time (wall clock, 2 cores shared with
//! nothing else in this process), the steps, the executed time as planned, without blending
//! and without shortcuts, each with its ratio to the default's, and the target of issue 19:
//! under 2 s for a one-part goal (one goal joint, in however many steps), under 10 s for the
//! four-step breakfast.
//!
//! [`time_optimal`]: kinscene::motion::timing::time_optimal
//! [`time_parameterise`]: kinscene::motion::timing::time_parameterise

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use kinscene::prelude::*;

const GOALS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/scenes/goals");
const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/scenes");

/// The safety net of one plan; seeded runs end on their iteration counts well before it.
const BUDGET: Duration = Duration::from_secs(120);

/// The goal files with the scene their header names (`examples/scenes/<scene>.urdf`), by
/// name.
fn scene_goals(only: &[String]) -> Vec<(String, PathBuf, PathBuf)> {
    let mut goals: Vec<(String, PathBuf, PathBuf)> = std::fs::read_dir(GOALS)
        .expect("the goal directory is readable")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .filter_map(|p| {
            let text = std::fs::read_to_string(&p).ok()?;
            let scene = text
                .lines()
                .take_while(|l| l.starts_with('#'))
                .find_map(|l| {
                    let rest = &l[l.find("examples/scenes/")? + "examples/scenes/".len()..];
                    Some(rest[..rest.find(".urdf")? + ".urdf".len()].to_owned())
                })?;
            Some((stem(&p), p, Path::new(SCENES).join(scene)))
        })
        .filter(|(name, _, _)| only.is_empty() || only.contains(name))
        .collect();
    goals.sort();
    goals
}

fn stem(p: &Path) -> String {
    p.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// One plan: the outcome's name, the wall-clock plan time (s), the task steps, the executed
/// time (s, solved only).
fn plan_once(
    scene: &SceneModel,
    problem: &Problem,
    settings: PlannerSettings,
) -> (String, f64, usize, Option<f64>) {
    let planner = HierarchicalPlanner::new(RobotModel::kinova_gen3_mobile(), settings)
        .expect("the default settings are valid");
    let t0 = Instant::now();
    let result = planner.plan(scene, problem, &Termination::after(BUDGET));
    let seconds = t0.elapsed().as_secs_f64();
    match result {
        Ok(r) => match &r.outcome {
            Outcome::Solved(p) => (
                "solved".into(),
                seconds,
                p.task.steps.len(),
                Some(p.duration()),
            ),
            Outcome::Infeasible(why) => {
                let first = why.to_string();
                let first = first.lines().next().unwrap_or_default();
                (format!("infeasible ({first})"), seconds, 0, None)
            }
            Outcome::Timeout(_) => ("timeout".into(), seconds, 0, None),
            Outcome::Cancelled(_) => ("cancelled".into(), seconds, 0, None),
        },
        Err(e) => (format!("error: {e}"), seconds, 0, None),
    }
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let runs: usize = args
        .first()
        .and_then(|a| a.parse().ok())
        .unwrap_or(3)
        .max(1);
    let mut base = PlannerSettings::default();
    let mut only: Vec<String> = Vec::new();
    for a in args.iter().skip(1) {
        if a == "fixed-base" {
            base.whole_body = None;
        } else if let Some(v) = a.strip_prefix("bar-turn=") {
            base.placement.bar_turn = v.parse().expect("bar-turn=RAD takes a number");
        } else {
            only.push(a.clone());
        }
    }
    println!(
        "plan: the Gen3 on the shipped goals, {runs} run(s) each, budget {} s, whole body {}, bar turn {} rad",
        BUDGET.as_secs(),
        if base.whole_body.is_some() {
            "on"
        } else {
            "off"
        },
        base.placement.bar_turn
    );
    println!(
        "{:<18} {:<12} {:>9} {:>9} {:>6} {:>10} {:>10} {:>6} {:>12} {:>6}  target",
        "goal",
        "outcome",
        "median s",
        "max s",
        "steps",
        "exec s",
        "no-blend s",
        "ratio",
        "no-shortcut s",
        "ratio"
    );
    for (name, path, scene) in scene_goals(&only) {
        let scene = match SceneModel::from_urdf_file(&scene) {
            Ok(s) => s,
            Err(e) => {
                println!("{name:<18} bad scene {}: {e}", scene.display());
                continue;
            }
        };
        let problem = match Problem::from_goal_file(&scene, &path) {
            Ok(p) => p,
            Err(e) => {
                println!("{name:<18} bad goal: {e}");
                continue;
            }
        };
        let mut times = Vec::with_capacity(runs);
        let mut last = None;
        for _ in 0..runs {
            let (outcome, seconds, steps, exec) = plan_once(&scene, &problem, base.clone());
            times.push(seconds);
            last = Some((outcome, steps, exec));
        }
        times.sort_by(f64::total_cmp);
        let (outcome, steps, exec) = last.unwrap_or_default();
        let stops = PlannerSettings {
            blend: None,
            ..base.clone()
        };
        let (_, _, _, exec_stops) = plan_once(&scene, &problem, stops);
        let straight = PlannerSettings {
            arm_time_shortcuts: 0,
            arm_random_shortcuts: 0,
            ..base.clone()
        };
        let (_, _, _, exec_straight) = plan_once(&scene, &problem, straight);
        let target = match (steps, problem.goal.targets().len()) {
            (0, _) => "-".to_owned(),
            (_, 1) => format!("< 2 s: {}", verdict(times[times.len() / 2] < 2.0)),
            _ if name == "breakfast" => {
                format!("< 10 s: {}", verdict(times[times.len() / 2] < 10.0))
            }
            _ => "-".to_owned(),
        };
        let fmt = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{v:.1}"));
        let ratio = |other: Option<f64>| match (exec, other) {
            (Some(a), Some(b)) if a > 0.0 => format!("{:.2}", b / a),
            _ => "-".to_owned(),
        };
        let outcome_short = outcome.split(' ').next().unwrap_or_default();
        println!(
            "{name:<18} {outcome_short:<12} {:>9.2} {:>9.2} {steps:>6} {:>10} {:>10} {:>6} {:>12} {:>6}  {target}",
            times[times.len() / 2],
            times[times.len() - 1],
            fmt(exec),
            fmt(exec_stops),
            ratio(exec_stops),
            fmt(exec_straight),
            ratio(exec_straight),
        );
        if outcome != "solved" {
            println!("{:<18} {outcome}", "");
        }
    }
}

fn verdict(met: bool) -> &'static str {
    if met { "met" } else { "missed" }
}
