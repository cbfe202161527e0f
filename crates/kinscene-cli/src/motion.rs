//! `kinscene plan --robot ROBOT.toml|URDF|gen3`: the hierarchical planner (task order refined by motion
//! planning, [`kinscene::planner`]) behind `plan`.
//!
//! The document is [`kinscene::planner::MotionDocument`]: the task plan document plus, per
//! step, the base path, the base pose, the arm paths, the manipulation trajectory and their
//! timing (per segment, numbered within the step, for a step that no single base pose covers;
//! at most `--max-segments` of them; unless `--fixed-base`, the base poses of a manipulation
//! during which the base moves), and the moves the motion layer vetoed. Exit codes as
//! `plan`.

use std::io::Write;
use std::path::Path;
use std::time::Duration;

use kinscene::scene::SceneModel;
use kinscene::task::{Problem, TaskSettings};

use crate::{CliError, Verdict};

/// The robot of `plan --robot`: a description (`.toml`), a URDF path or `gen3`; for a URDF,
/// its tool link, SRDF, mesh packages and the rest of the import options.
pub struct RobotArgs<'a> {
    /// A robot description (`.toml`), a URDF path, or `gen3` for the shipped robot.
    pub path: &'a Path,
    /// The link whose frame is the tool (`None`: `tool_frame`).
    pub tool_link: Option<&'a str>,
    /// The robot's SRDF (`None`: exemptions computed by sampling).
    pub srdf: Option<&'a Path>,
    /// The link the arm starts at (`None`: the base link).
    pub arm_root: Option<&'a str>,
    /// Values of frozen joints.
    pub frozen: &'a [(String, f64)],
    /// The gripper's contact links (empty: the naming convention).
    pub contact_links: &'a [String],
    /// The approach direction in the tool link's frame (`None`: +z).
    pub tool_approach: Option<[f64; 3]>,
    /// `package://NAME` roots for the robot's meshes.
    pub packages: &'a [(String, std::path::PathBuf)],
    /// How the base moves (`--base`).
    pub base: crate::plan::BaseArg,
}

/// The motion layer's options from the command line.
#[derive(Debug, Clone, Copy, Default)]
pub struct MotionOptions {
    /// The planner's seed (`None`: its default).
    pub seed: Option<u64>,
    /// The most segments per step (`None`: the planner's default).
    pub max_segments: Option<usize>,
    /// Whether whole-body manipulation is tried.
    pub whole_body: bool,
    /// The largest turn (rad) of a bar grasp about the bar (`None`: along the normal only).
    pub bar_turn: Option<f64>,
}

/// Plans with motion for `robot` (a description, a URDF path, or `gen3`) and writes the document to
/// `out_path` or `out`, with the motion layer's `motion_options`.
///
/// # Errors
/// An unreadable or malformed robot URDF, a goal without a robot start pose, a backend
/// failure, or an output file that cannot be written; without the `ompl`, `pinocchio` and
/// `casadi` features, any use.
#[allow(clippy::too_many_arguments)]
pub fn run(
    robot: &RobotArgs<'_>,
    goal: &Path,
    model: &SceneModel,
    problem: &Problem,
    settings: TaskSettings,
    motion_options: MotionOptions,
    budget: (Duration, &str),
    out_path: Option<&Path>,
    out: &mut dyn Write,
) -> Result<Verdict, CliError> {
    imp::run(
        robot,
        goal,
        model,
        problem,
        settings,
        motion_options,
        budget,
        out_path,
        out,
    )
}

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
mod imp {
    use super::*;
    use kinscene::kinematics::robot::{
        PairSampling, RobotImportOptions, RobotModel, Srdf, StowSearch,
    };
    use kinscene::motion::placement::WholeBodySettings;
    use kinscene::planner::{
        HierarchicalPlanner, MotionDocument, MotionOutcome, PlannerError, PlannerSettings,
    };
    use kinscene::task::Termination;

    #[allow(clippy::too_many_arguments)]
    pub fn run(
        robot: &RobotArgs<'_>,
        goal: &Path,
        model: &SceneModel,
        problem: &Problem,
        settings: TaskSettings,
        MotionOptions {
            seed,
            max_segments,
            whole_body,
            bar_turn,
        }: MotionOptions,
        (budget, budget_text): (Duration, &str),
        out_path: Option<&Path>,
        out: &mut dyn Write,
    ) -> Result<Verdict, CliError> {
        let description = robot.path.extension().is_some_and(|e| e == "toml");
        let robot_model = if robot.path.as_os_str() == "gen3" || description {
            if robot.tool_link.is_some()
                || robot.srdf.is_some()
                || robot.arm_root.is_some()
                || !robot.frozen.is_empty()
                || !robot.contact_links.is_empty()
                || robot.tool_approach.is_some()
            {
                let what = if description {
                    "a robot description (they go in the .toml)"
                } else {
                    "the shipped gen3"
                };
                return Err(CliError::new(format!(
                    "--tool-link, --tool-approach, --srdf, --arm-root, --frozen and --contact-link apply to a robot URDF, not {what}"
                )));
            }
            if description {
                RobotModel::from_description_file(robot.path)
                    .map_err(|e| CliError::new(format!("{}: {e}", robot.path.display())))?
            } else {
                RobotModel::kinova_gen3_mobile()
            }
        } else {
            let mut options = RobotImportOptions::default();
            if let Some(link) = robot.tool_link {
                options.tool_link = link.to_owned();
            }
            options.package_paths = robot.packages.iter().cloned().collect();
            options.arm_root = robot.arm_root.map(str::to_owned);
            options.frozen = robot.frozen.iter().cloned().collect();
            options.tool_approach = robot.tool_approach;
            if !robot.contact_links.is_empty() {
                options.contact_links = Some(robot.contact_links.to_vec());
            }
            let loaded = RobotModel::from_urdf_file_with(robot.path, &options)
                .map_err(|e| CliError::new(format!("{}: {e}", robot.path.display())))?;
            match robot.srdf {
                Some(path) => {
                    let at = |e: kinscene::kinematics::robot::RobotError| {
                        CliError::new(format!("{}: {e}", path.display()))
                    };
                    let srdf = Srdf::from_file(path).map_err(at)?;
                    let unknown = loaded.srdf_unknown_links(&srdf);
                    if !unknown.is_empty() {
                        eprintln!(
                            "kinscene: {}: disable_collisions pairs skipped, links not in the robot model: {}",
                            path.display(),
                            unknown.join(", ")
                        );
                    }
                    let stowed = loaded.srdf_stow(&srdf).is_some();
                    let described = loaded.with_srdf(&srdf).map_err(at)?;
                    if stowed {
                        described
                    } else {
                        described
                            .with_computed_stow(&StowSearch::default())
                            .map_err(at)?
                    }
                }
                None => loaded
                    .with_computed_stow(&StowSearch::default())
                    .and_then(|r| r.with_sampled_pairs(&PairSampling::default()))
                    .map_err(|e| CliError::new(format!("{}: {e}", robot.path.display())))?,
            }
        };
        let robot_model = match robot.base {
            crate::plan::BaseArg::Holonomic => robot_model,
            crate::plan::BaseArg::Differential => {
                let base = robot_model.base().to_differential_drive();
                robot_model
                    .with_base(base)
                    .map_err(|e| CliError::new(format!("{}: {e}", robot.path.display())))?
            }
        };
        let name = robot_model.name().to_string();
        let planner = HierarchicalPlanner::new(robot_model, {
            let defaults = PlannerSettings::default();
            let mut placement = defaults.placement.clone();
            if let Some(turn) = bar_turn {
                placement.bar_turn = turn;
            }
            let s = PlannerSettings {
                task: settings,
                placement,
                max_segments: max_segments.unwrap_or(defaults.max_segments),
                whole_body: whole_body.then(WholeBodySettings::default),
                ..defaults
            };
            match seed {
                Some(seed) => s.seeded(seed),
                None => s,
            }
        })
        .map_err(|e| CliError::new(format!("{}: {e}", robot.path.display())))?;
        let termination = Termination::after(budget);
        let result = planner
            .plan(model, problem, &termination)
            .map_err(|e| match e {
                PlannerError::Task(_)
                | PlannerError::InvalidSetting(_)
                | PlannerError::MissingBasePose
                | PlannerError::NoHandle { .. } => {
                    CliError::new(format!("{}: {e}", goal.display()))
                }
                e => CliError::new(format!("planning failed: {e}")),
            })?;
        let document = MotionDocument::from_result(&result, &name);
        let reason = document.plan.reason.clone().unwrap_or_default();
        let verdict = match &result.outcome {
            MotionOutcome::Solved(_) => Verdict::Success,
            MotionOutcome::Infeasible(_) => Verdict::Infeasible {
                note: format!("infeasible: {reason}"),
            },
            MotionOutcome::Timeout(_) | MotionOutcome::Cancelled(_) => Verdict::Timeout {
                note: format!("timeout after {budget_text}: {reason}"),
            },
        };
        let json = document.to_json() + "\n";
        match out_path {
            Some(path) => std::fs::write(path, json)
                .map_err(|e| CliError::new(format!("cannot write {}: {e}", path.display())))?,
            None => out
                .write_all(json.as_bytes())
                .map_err(|e| CliError::new(format!("cannot write the plan: {e}")))?,
        }
        Ok(verdict)
    }
}

#[cfg(not(all(feature = "ompl", feature = "pinocchio", feature = "casadi")))]
mod imp {
    use super::*;

    #[allow(clippy::too_many_arguments)]
    pub fn run(
        _robot: &RobotArgs<'_>,
        _goal: &Path,
        _model: &SceneModel,
        _problem: &Problem,
        _settings: TaskSettings,
        _motion_options: MotionOptions,
        _budget: (Duration, &str),
        _out_path: Option<&Path>,
        _out: &mut dyn Write,
    ) -> Result<Verdict, CliError> {
        Err(CliError::new(
            "--robot needs the ompl, pinocchio and casadi features (this binary was built \
             without them)",
        ))
    }
}
