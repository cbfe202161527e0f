//! `kinscene plan --scene S.urdf --goal G.toml [--budget 10s] [--out plan.json]
//! [--strategy search|random|paper] [--seed N] [--robot ROBOT.toml|URDF|gen3]
//! [--base holonomic|differential] [--max-segments N] [--fixed-base] [--bar-turn RAD]
//! [--tool-link LINK] [--srdf FILE]
//! [--arm-root LINK] [--frozen JOINT=VALUE ...] [--contact-link LINK ...] [--tool-approach X,Y,Z]
//! [--package NAME=PATH ...]`:
//! plans the order of single-joint changes that reaches a goal ([`kinscene::task::plan`]) and
//! writes the plan document. With `--robot`, the hierarchical planner refines the order into
//! motion (see [`crate::motion`]).
//!
//! The goal file is TOML, or JSON if its name ends in `.json` (schema:
//! [`kinscene::task::GoalSpec`]). The plan document
//! ([`PlanFile`], schema in [`kinscene::task::PlanFile`]'s module docs) goes to `--out` or,
//! without it, to standard output; it is written for every verdict, with `status` `"solved"`,
//! `"infeasible"` (no steps, `reason` and `conflicts` say why) or `"timeout"` (the best
//! partial plan, `reason` names the unmet goal joints).
//!
//! Exit codes: 0 solved, 3 infeasible, 4 timeout, 2 bad input. On 3 and 4 one line goes to
//! standard error, `kinscene: infeasible: <reason>` or
//! `kinscene: timeout after <budget>: <reason>` (`<reason>` is the document's `reason`): a
//! verdict, not an error.
//!
//! **Conflicting targets.** When the search finds no plan although every goal target was met
//! in some explored state on its own (the document then names no joint), `plan` looks for
//! the targets that conflict: it re-plans without each target in turn, within what is left of
//! the budget, and drops those the goal stays infeasible without (a deletion filter). The
//! standard-error line then ends in
//! `; conflicting targets: <joint>, <joint> (a plan exists when any one of them is dropped)`.
//! The plan document is the planner's own and does not carry this diagnosis; if the budget
//! runs out during it, the line omits it.

use std::io::Write;
use std::path::PathBuf;
use std::time::Duration;

use kinscene::task::{
    NoRefinement, Outcome, PlanFile, Strategy, TaskSettings, Termination, conflicting_targets, plan,
};

use crate::input::{SceneArgs, file_error, load_problem};
use crate::{CliError, Verdict};

/// The budget when `--budget` is not given.
const DEFAULT_BUDGET: &str = "10s";

/// Arguments of `kinscene plan`.
#[derive(Debug, clap::Args)]
#[command(
    about = "Plan the order of single-joint changes that reaches a goal; print the plan as JSON",
    long_about = "Loads a scene URDF and a goal file (TOML, or JSON if the name ends in .json), \
                  searches for the cheapest order of single-joint changes that reaches the goal \
                  and writes the plan document (JSON) to --out or stdout. The document is \
                  written for every verdict. Exit codes: 0 solved, 3 infeasible, 4 timeout \
                  (budget exhausted; the document holds the best partial plan), 2 bad input. \
                  On 3 and 4 one line goes to stderr: `kinscene: infeasible: <reason>` or \
                  `kinscene: timeout after <budget>: <reason>`. When every target is reachable \
                  alone but not all together, the infeasible line also names a minimal set \
                  of conflicting targets, found by re-planning without each target in turn \
                  within the rest of the budget.",
    after_long_help = concat!(
        "Goal file (TOML; the same fields in JSON):\n\n",
        include_str!("goal_schema.txt"),
        "\nPlan document (JSON):\n\n",
        include_str!("plan_schema.txt"),
    )
)]
pub struct Args {
    /// The scene and its mesh packages.
    #[command(flatten)]
    input: SceneArgs,
    /// The goal file: TOML, or JSON if the name ends in `.json`.
    #[arg(long, value_name = "FILE")]
    goal: PathBuf,
    /// Time budget: a number and a unit, `ms`, `s`, `m` or `h` (`500ms`, `1.5s`, `1m`).
    #[arg(
        long,
        value_name = "DURATION",
        default_value = DEFAULT_BUDGET,
        allow_hyphen_values = true
    )]
    budget: String,
    /// Write the plan document here instead of to stdout.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// The planner: the complete lattice search, or one of the paper's baselines.
    #[arg(long, value_enum, default_value_t = StrategyArg::Search)]
    strategy: StrategyArg,
    /// Seed of the `random` and `paper` baselines' order sampler [default: 0], and with
    /// `--robot` of the motion layer (OMPL, IK restarts, base-pose sampling) [default: 1]: the
    /// same inputs and seed give the same plan.
    #[arg(long, value_name = "N")]
    seed: Option<u64>,
    /// Refine the plan with motion for this robot: a robot description (a file ending in
    /// `.toml`: URDF, SRDF, packages, tool, arm root, frozen joints, stow and base in one file;
    /// format in `kinscene::kinematics::robot`'s description docs and the README's "Bring your
    /// robot"), a robot URDF (with the flags below), or `gen3` for the shipped Kinova Gen3 on
    /// an omnidirectional base (the same as `robots/gen3.toml`). The document then also holds base paths, base
    /// poses, arm paths and timing per step, or per segment of a step that no single base pose
    /// covers (schema: `kinscene::planner`'s document module), and the goal file must give the
    /// robot's start pose (`[robot] base = [x, y, yaw]`).
    #[arg(long, value_name = "ROBOT.toml|URDF|gen3")]
    robot: Option<PathBuf>,
    /// With a robot: how its base moves. `holonomic` drives in any direction; `differential`
    /// (TIAGo, Fetch, Stretch) turns in place and drives straight, forward or backward, never
    /// sideways, with the base's x limits as its forward limits.
    #[arg(long, value_enum, default_value_t = BaseArg::Holonomic, requires = "robot")]
    base: BaseArg,
    /// With a robot: the most segments one step may be split into when no single base pose
    /// covers it (the robot lets go, drives to another base pose and grasps again in between);
    /// 1 keeps every step to one base pose [default: 4].
    #[arg(long, value_name = "N", value_parser = parse_segments, requires = "robot")]
    max_segments: Option<usize>,
    /// With a robot: keep the base still whenever the arm moves (the paper's fixed-base
    /// manipulation, in segments up to --max-segments). By default a step that no single base
    /// pose covers is also tried with one grasp and the base moving along with the arm, kept
    /// over segments when it executes faster.
    #[arg(long, requires = "robot", conflicts_with = "whole_body")]
    fixed_base: bool,
    /// With a robot: whole-body manipulation as above; the default, kept so that scripts
    /// written when it was opt-in still run.
    #[arg(long, requires = "robot")]
    whole_body: bool,
    /// With a robot: also grasp a bar handle from directions turned about the bar's long axis,
    /// by up to this angle (radians, 0 to pi/2) either way, when the grasp along the handle's
    /// normal does not cover a step (a door opened far, its handle facing a neighbouring
    /// cabinet); knobs are grasped along the normal only; 0: along the normal only
    /// [default: 1.2].
    #[arg(long, value_name = "RAD", value_parser = parse_bar_turn, requires = "robot")]
    bar_turn: Option<f64>,
    /// With a robot URDF: the link whose frame is the tool (TCP, +z the approach direction)
    /// [default: tool_frame]. The `--package` paths also resolve the robot's mesh URIs.
    #[arg(long, value_name = "LINK", requires = "robot")]
    tool_link: Option<String>,
    /// With a robot URDF: its SRDF, for the self-collision exemptions (`disable_collisions`)
    /// and the stowed configuration (the first `group_state` named stow, tuck, transport, home
    /// or ready). Without it the exemptions are computed by sampling (adjacent links, and
    /// pairs touching in 95 % of 2 000 random configurations or at the stow). Without a stow
    /// state, the stow is computed: the most compact arm configuration clear of itself and
    /// of the floor.
    #[arg(long, value_name = "FILE", requires = "robot")]
    srdf: Option<PathBuf>,
    /// With a robot URDF: the link the arm starts at; movable joints above it on the way from
    /// the base (a torso lift) are frozen [default: the base link].
    #[arg(long, value_name = "LINK", requires = "robot")]
    arm_root: Option<String>,
    /// With a robot URDF: hold a movable joint that is not an arm joint (head, torso, wheels,
    /// fingers) at VALUE (rad or m; repeatable) [default: 0 clamped into its limits].
    #[arg(long = "frozen", value_name = "JOINT=VALUE", value_parser = parse_frozen, requires = "robot")]
    frozen: Vec<(String, f64)>,
    /// With a robot URDF: the approach direction in the tool link's frame when it is not +z
    /// (e.g. `1,0,0` for a hand whose fingers point along its x).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_direction, requires = "robot")]
    tool_approach: Option<[f64; 3]>,
    /// With a robot URDF: a link whose collision elements may touch the grasped part (the
    /// gripper's fingers and pads; repeatable) [default: links and elements below the last
    /// arm joint whose name contains `finger` or `pad`].
    #[arg(long = "contact-link", value_name = "LINK", requires = "robot")]
    contact_links: Vec<String>,
}

/// Parses a segment count, at least 1.
/// Parses an angle in [0, pi/2] radians.
fn parse_bar_turn(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(a) if (0.0..=std::f64::consts::FRAC_PI_2).contains(&a) => Ok(a),
        _ => Err(format!(
            "{s:?} is not an angle from 0 to pi/2 (1.5708) radians"
        )),
    }
}

fn parse_segments(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("{s:?} is not a whole number of at least 1")),
    }
}

/// Parses `X,Y,Z`.
fn parse_direction(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<Option<f64>> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect();
    match parts.as_slice() {
        [Some(x), Some(y), Some(z)] => Ok([*x, *y, *z]),
        _ => Err(format!("expected X,Y,Z (three finite numbers), got {s:?}")),
    }
}

/// Parses `JOINT=VALUE`.
fn parse_frozen(s: &str) -> Result<(String, f64), String> {
    match s.split_once('=') {
        Some((name, value)) if !name.is_empty() => match value.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok((name.to_string(), v)),
            _ => Err(format!("{value:?} is not a finite number")),
        },
        _ => Err(format!("expected JOINT=VALUE, got {s:?}")),
    }
}

/// `--base`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BaseArg {
    /// Omnidirectional: x, y and yaw independently.
    Holonomic,
    /// Differential drive: turns in place and straight drives.
    Differential,
}

/// `--strategy`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum StrategyArg {
    /// The complete lattice search (lazy A* over single-joint changes).
    Search,
    /// The paper's Random baseline: one random order of the goal joints.
    Random,
    /// The paper's planner: rejection-sampled orders, boxes at 6 samples.
    Paper,
}

/// Parses a duration: a non-negative decimal number followed by `ms`, `s`, `m` or `h`.
///
/// # Errors
/// A message for a missing or unknown unit, a number that does not parse, or a duration that
/// is negative, not finite or too large.
fn parse_duration(text: &str) -> Result<Duration, String> {
    let s = text.trim();
    let split = s
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(s.len());
    let (number, unit) = s.split_at(split);
    let expected = "expected a number and a unit (ms, s, m, h), e.g. 2s, 500ms, 1.5s, 1m";
    let scale = match unit {
        "ms" => 1e-3,
        "s" => 1.0,
        "m" => 60.0,
        "h" => 3600.0,
        _ => return Err(expected.to_string()),
    };
    let value: f64 = number.parse().map_err(|_| expected.to_string())?;
    Duration::try_from_secs_f64(value * scale).map_err(|e| format!("{e}"))
}

/// Runs `plan`: loads the inputs, plans within the budget and writes the plan document to
/// `--out` or `out`.
///
/// # Errors
/// A [`CliError`] naming the file for unreadable or malformed inputs, a goal that does not fit
/// the scene (unknown joint, value outside the limits, robot start outside the grid or in an
/// obstacle), a malformed `--budget`, `--seed` with `--strategy search` and no `--robot`, or an `--out` file
/// that cannot be written.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<Verdict, CliError> {
    let budget = parse_duration(&args.budget)
        .map_err(|e| CliError::new(format!("invalid --budget {:?}: {e}", args.budget)))?;
    let seed = args.seed.unwrap_or(0);
    let strategy = match args.strategy {
        StrategyArg::Search if args.seed.is_some() && args.robot.is_none() => {
            return Err(CliError::new(
                "--seed applies to --strategy random and paper, or with --robot",
            ));
        }
        StrategyArg::Search => Strategy::Search,
        StrategyArg::Random => Strategy::Random { seed },
        StrategyArg::Paper => Strategy::Paper { seed },
    };
    let model = args.input.load()?;
    let problem = load_problem(&model, &args.goal)?;
    let settings = TaskSettings {
        strategy,
        ..TaskSettings::default()
    };
    if let Some(robot) = &args.robot {
        let robot = crate::motion::RobotArgs {
            path: robot,
            tool_link: args.tool_link.as_deref(),
            srdf: args.srdf.as_deref(),
            arm_root: args.arm_root.as_deref(),
            frozen: &args.frozen,
            contact_links: &args.contact_links,
            tool_approach: args.tool_approach,
            packages: &args.input.packages,
            base: args.base,
        };
        return crate::motion::run(
            &robot,
            &args.goal,
            &model,
            &problem,
            settings,
            crate::motion::MotionOptions {
                seed: args.seed,
                max_segments: args.max_segments,
                whole_body: !args.fixed_base,
                bar_turn: args.bar_turn,
            },
            (budget, args.budget.trim()),
            args.out.as_deref(),
            out,
        );
    }
    // The budget starts after loading: it bounds the planner and the diagnosis.
    let termination = Termination::after(budget);
    let result = plan(&model, &problem, &settings, &NoRefinement, &termination)
        .map_err(|e| file_error(&args.goal, e))?;
    let document = PlanFile::from_result(&result);
    let reason = document.reason.clone().unwrap_or_default();
    let verdict = match &result.outcome {
        Outcome::Solved(_) => Verdict::Success,
        Outcome::Infeasible(why) => {
            let mut note = format!("infeasible: {reason}");
            // The search names no joint when every target is reachable on its own; then
            // find which targets conflict.
            if why.unreached.is_empty() && strategy == Strategy::Search {
                let conflict = conflicting_targets(&model, &problem, &settings, &termination)
                    .map_err(|e| file_error(&args.goal, e))?;
                if let Some(names) = conflict {
                    note.push_str(&format!(
                        "; conflicting targets: {} (a plan exists when any one of them is \
                         dropped)",
                        names.join(", ")
                    ));
                }
            }
            Verdict::Infeasible { note }
        }
        Outcome::Timeout(_) | Outcome::Cancelled(_) => Verdict::Timeout {
            note: format!("timeout after {}: {reason}", args.budget.trim()),
        },
    };
    // Written last, so that an error leaves no output behind.
    let json = document.to_json() + "\n";
    match &args.out {
        Some(path) => std::fs::write(path, json)
            .map_err(|e| CliError::new(format!("cannot write {}: {e}", path.display())))?,
        None => out
            .write_all(json.as_bytes())
            .map_err(|e| CliError::new(format!("cannot write the plan: {e}")))?,
    }
    Ok(verdict)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_parse_with_units() {
        assert_eq!(parse_duration("2s"), Ok(Duration::from_secs(2)));
        assert_eq!(parse_duration("500ms"), Ok(Duration::from_millis(500)));
        assert_eq!(parse_duration("1.5s"), Ok(Duration::from_millis(1500)));
        assert_eq!(parse_duration("1m"), Ok(Duration::from_secs(60)));
        assert_eq!(parse_duration("0s"), Ok(Duration::ZERO));
        for bad in [
            "", "2", "s", "-1s", "2 s", "1.5.2s", "2sec", "1e3s", "inf s", "1e400s",
        ] {
            assert!(parse_duration(bad).is_err(), "{bad:?}");
        }
    }
}
