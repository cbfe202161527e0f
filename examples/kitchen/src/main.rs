//! The kitchen: the paper's three stages on a simulated kitchen, and its experiments.
//!
//! ```sh
//! bash setup.sh && cargo run --release -p kinscene-kitchen              # the full run
//! cargo run --release -p kinscene-kitchen -- --quick                    # small sizes
//! cargo run --release -p kinscene-kitchen -- --experiments fig5,table2 --runs 3 --seed 7
//! cargo run --release -p kinscene-kitchen -- --quick --experiments table1 --fixed-base
//! cargo run --release -p kinscene-kitchen -- --scene examples/scenes/galley.urdf \
//!     --goal examples/scenes/goals/galley.toml --out out/galley    # another scene
//! ```
//!
//! A mobile manipulator (the Kinova Gen3 on an omnidirectional base) in a rapier3d physics
//! world of `examples/scenes/kitchen.urdf` maps the kitchen's handles, explores every handle
//! physically to discover the joints (Algorithm 1), and then plans and executes goal sequences
//! with the hierarchical planner on the model it built. The output folder (default
//! `out/kitchen`) receives `report.md` (every figure; the paper's Fig. 5, Table I, Table II and
//! Fig. 6), `report.json`, `plans/*.json` (the plan documents and execution records),
//! `twin.urdf` (the estimated scene) and SVG pictures.
//!
//! With `--scene FILE.urdf --goal FILE.toml` the three stages run once on that scene instead
//! (any scene URDF that follows the scene conventions of `kinscene::scene::urdf`): mapping
//! from viewpoints computed from its base map, discovery of every mapped handle, and the goal
//! (true joint names, `{ min = ... }` targets, the start pose in `[robot] base`) planned on the
//! estimated model and executed. The output folder (default `out/<scene name>`) receives
//! `twin.urdf`, `discovery.json`, `plans/goal.json`, `plans/goal.exec.json` and `report.md`.
//! The paper's experiments need the kitchen's ground truth (its goal sequences and Table I
//! parts): `--experiments`, `--runs`, `--sequences` and `--needed-only` with `--scene` are
//! usage errors.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

use kinscene_kitchen::pipeline::{
    self, Config, EstimatorChoice, Experiment, ExploreScope, ViewpointChoice,
};

/// The kitchen example: mapping → articulation discovery → scene-level manipulation in a
/// simulated kitchen, and the paper's experiments.
#[derive(Debug, Parser)]
#[command(name = "kitchen")]
struct Args {
    /// Seed of everything random (run r uses seed + r).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output folder (default out/kitchen, or out/SCENE (the scene file name) with --scene).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Run mapping, discovery and the --goal file on this scene URDF instead of the paper's
    /// experiments on the kitchen.
    #[arg(long, requires = "goal", conflicts_with_all = ["experiments", "runs", "sequences", "needed_only"])]
    scene: Option<PathBuf>,
    /// The goal of a --scene run (TOML, kinscene::task::GoalSpec; true joint names, the robot's
    /// start in the robot table's base key).
    #[arg(long, requires = "scene")]
    goal: Option<PathBuf>,
    /// Depth noise of the cameras (m, standard deviation).
    #[arg(long, default_value_t = 0.005)]
    depth_noise: f64,
    /// Position noise of the handle detector (m, standard deviation).
    #[arg(long, default_value_t = 0.01)]
    detector_noise: f64,
    /// The soft fingers' deflection from one pull step to the next (m, standard deviation per
    /// axis).
    #[arg(long, default_value_t = 0.001)]
    grasp_deflection: f64,
    /// The soft fingers' tilt of the approach axis from one pull step to the next (degrees,
    /// standard deviation).
    #[arg(long, default_value_t = 1.0)]
    grasp_tilt: f64,
    /// Probability of each injected fault (grasp slip, early joint limit, tracker loss).
    #[arg(long, default_value_t = 0.0)]
    fault_rate: f64,
    /// Independent runs of the whole pipeline (default 5; 1 with --quick).
    #[arg(long)]
    runs: Option<usize>,
    /// Comma list of experiments: task, fig5, table1, table2, fig6 (or all).
    #[arg(long, default_value = "all")]
    experiments: String,
    /// Small sizes: one run, two sequences, two Table I parts, a coarser head camera.
    #[arg(long)]
    quick: bool,
    /// The discovery stage's articulation estimator: two-view, proprioceptive or fused.
    #[arg(long, default_value = "two-view")]
    estimator: String,
    /// The discovery stage's gravity prior (degrees): an estimated axis within this angle of
    /// horizontal or vertical is registered level (0: off; default: the library's, 10°).
    #[arg(long)]
    axis_snap: Option<f64>,
    /// Budget of each planner call (s).
    #[arg(long, default_value_t = 60.0)]
    budget: f64,
    /// Only these Fig. 5 sequences (comma list of names).
    #[arg(long)]
    sequences: Option<String>,
    /// Explore only the handles the selected sequences and Table I parts need (uses the
    /// ground truth to choose: an experiment shortcut).
    #[arg(long)]
    needed_only: bool,
    /// Head camera rays, COLUMNSxROWS (default 320x240; 160x120 with --quick).
    #[arg(long, value_parser = parse_rays)]
    head_rays: Option<(usize, usize)>,
    /// The mapping viewpoints of the kitchen run: kitchen (the hand-placed list) or computed
    /// (from the base map, as a --scene run always does).
    #[arg(long, default_value = "kitchen")]
    viewpoints: String,
    /// Put wall-clock times into the report.
    #[arg(long)]
    wall_clock: bool,
    /// The paper's fixed-base manipulation: no step moves the base along with the arm
    /// (default: whole-body manipulation for steps no single base pose covers).
    #[arg(long)]
    fixed_base: bool,
    /// Grasps turned about a bar handle by up to this angle (rad, 0 to π/2; default 1.2; 0:
    /// the fingers across the bar only).
    #[arg(long)]
    bar_turn: Option<f64>,
    /// Further pulls per handle while the estimate is not confident (discovery's
    /// keep-pulling loop; default 0: the paper's Algorithm 1).
    #[arg(long)]
    extra_pulls: Option<usize>,
    /// No progress output.
    #[arg(long)]
    quiet: bool,
}

/// Parses `COLUMNSxROWS`.
fn parse_rays(text: &str) -> Result<(usize, usize), String> {
    let (c, r) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{text:?} is not COLUMNSxROWS"))?;
    let n = |s: &str| {
        s.trim()
            .parse::<usize>()
            .map_err(|e| format!("{s:?} in {text:?}: {e}"))
    };
    Ok((n(c)?, n(r)?))
}

fn config(args: &Args) -> Result<Config, pipeline::PipelineError> {
    let base = if args.quick {
        Config::quick()
    } else {
        Config::default()
    };
    Ok(Config {
        seed: args.seed,
        runs: args.runs.unwrap_or(base.runs),
        depth_noise: args.depth_noise,
        detector_noise: args.detector_noise,
        grasp_deflection: args.grasp_deflection,
        grasp_tilt: args.grasp_tilt.to_radians(),
        fault_rate: args.fault_rate,
        experiments: Experiment::parse_list(&args.experiments)?,
        estimator: EstimatorChoice::parse(&args.estimator)?,
        planner_budget: args.budget,
        wall_clock: args.wall_clock,
        whole_body: base.whole_body && !args.fixed_base,
        bar_turn: args.bar_turn.unwrap_or(base.bar_turn),
        head_rays: args.head_rays.or(base.head_rays),
        sequences: args.sequences.as_ref().map(|s| {
            s.split(',')
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .map(str::to_string)
                .collect()
        }),
        explore: if args.needed_only {
            ExploreScope::Needed
        } else {
            ExploreScope::All
        },
        discovery: kinscene::discovery::DiscoverySettings {
            axis_snap: args
                .axis_snap
                .map_or(base.discovery.axis_snap, f64::to_radians),
            max_extra_pulls: args.extra_pulls.unwrap_or(base.discovery.max_extra_pulls),
            ..base.discovery
        },
        scene: args.scene.clone().unwrap_or(base.scene.clone()),
        viewpoints: match args.viewpoints.trim() {
            "kitchen" => ViewpointChoice::Kitchen,
            "computed" => ViewpointChoice::Computed,
            other => {
                return Err(pipeline::PipelineError::Config(format!(
                    "unknown viewpoints {other:?} (expected kitchen or computed)"
                )));
            }
        },
        ..base
    })
}

/// The `--scene` run: prints the stages' lines and where the report is.
fn scene_main(args: &Args, scene: &std::path::Path, goal: &std::path::Path) -> ExitCode {
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = scene
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy());
        PathBuf::from("out").join(stem.as_ref())
    });
    let result = config(args).and_then(|c| pipeline::run_scene(&c, goal, Some(&out), !args.quiet));
    match result {
        Ok(report) => {
            let mut stdout = std::io::stdout().lock();
            let _ = writeln!(
                stdout,
                "kitchen: {}: {} of {} true handles mapped, {} parts registered ({} matched); \
                 plan {}; execution {}",
                report.scene,
                report.mapping.true_mapped.len(),
                report.joints.len(),
                report.discovery.registered,
                report.discovery.matches.len(),
                report.plan.status,
                report
                    .execution
                    .as_ref()
                    .map_or("not run", |v| v.category.name())
            );
            let _ = writeln!(stdout, "wrote {}", out.join("report.md").display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("kitchen: error: {e}");
            ExitCode::from(2)
        }
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    if let (Some(scene), Some(goal)) = (&args.scene, &args.goal) {
        return scene_main(&args, scene, goal);
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/kitchen"));
    let result = config(&args).and_then(|c| {
        let started = std::time::Instant::now();
        let report = pipeline::run(&c, Some(&out), !args.quiet)?;
        Ok((report, started.elapsed()))
    });
    match result {
        Ok((report, elapsed)) => {
            let rate = |m| {
                report
                    .success_rate(m)
                    .map_or("–".to_string(), |r| format!("{:.0} %", 100.0 * r))
            };
            // Write errors (a closed pipe) are ignored: the report is on disk.
            let mut stdout = std::io::stdout().lock();
            let _ = writeln!(
                stdout,
                "kitchen: done in {:.1} s; scene success Ours {}, Random {}, Oracle {}; base \
                 repositioning Exploration-only / Ours {}",
                elapsed.as_secs_f64(),
                rate(pipeline::Method::Ours),
                rate(pipeline::Method::Random),
                rate(pipeline::Method::Oracle),
                report
                    .base_ratio()
                    .map_or("–".to_string(), |r| format!("{r:.2}×"))
            );
            let _ = writeln!(stdout, "wrote {}", out.join("report.md").display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("kitchen: error: {e}");
            ExitCode::from(2)
        }
    }
}
