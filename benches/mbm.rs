//! MotionBenchMaker on the Panda (VAMP's 700 problems: 7 scene families × 100), planned with
//! the crate's public arm planner ([`plan_arm`], OMPL RRTConnect) in six modes from the same
//! run: validity by the exact parry check, by the sphere fast path ([`RobotSpheres`] against
//! [`SphereObstacles`], exact fallback), both with OMPL's discrete motion check, and
//! [`ArmCheck`] ([`plan_arm_checked`]) with its discrete motions and OMPL's full simplifier, with [`Simplifier::Shortcut`], and with the
//! shortcut simplifier and [`ArmCheck::with_spans`] off (every state of a motion evaluated,
//! the same answers: the spans' saving from the same run), and with the shortcut simplifier
//! and every motion certified continuously ([`ArmCheck::with_continuous`]). Prints the
//! success rate, the median and p95 planning time (wall clock, planning plus simplification)
//! and the ratio of the medians.
//!
//! `cargo bench --bench mbm` (optionally `-- PER_SET`, the first `PER_SET` problems of each
//! family, default 100, all; `-- no-exact` to skip the exact-check mode; `-- only=K` to run
//! mode K alone, 0-based in the printed order; `-- budget=S` for another budget than 2 s;
//! `-- iterations=N` to end RRTConnect after N iterations as well, for instruction counts;
//! `-- range=R` for RRTConnect's range in rad instead of the default
//! [`ARM_RANGE`](kinscene::motion::paths::ARM_RANGE) (`range=2.6`: OMPL's own on the Panda);
//! the printed `paths` digest is equal between builds that return the same paths).
//!
//! **Set-up (not timed, not in the tests).** The problems ship in the `vamp-planner` sdist on
//! PyPI (`resources/panda/problems.tar.bz2`, MoveIt scene and request YAML). The first run
//! fetches the pinned sdist (0.6.4, SHA-256 checked) into `target/mbm/` (under
//! `$CARGO_TARGET_DIR` when that is set) with
//! `benches/mbm/fetch.py` (PyPI's JSON API; no build step), unpacks the problems with `tar` and
//! converts them with `benches/mbm/convert.py` into `target/mbm/problems.json`; later runs
//! reuse that file. Python is `$PYTHON`, default the bench venv's (`bash setup.sh --bench`
//! installs PyYAML there), else `python3`.
//!
//! **Robot.** The Panda of the PyPI package `example-robot-data` with its SRDF (mesh collision
//! geometry as convex hulls), fingers frozen open at 0.04 m, base at the origin as in the
//! problems. Its meshes and limits are not VAMP's, so a start or goal may collide here, or lie
//! outside this Panda's joint limits (four goals of the set have joint 4 above its upper limit
//! of −0.0698 rad, which OMPL rejects as an invalid goal): such problems are counted apart
//! ("invalid endpoints", the out-of-limit ones listed) and the success rate is over the
//! others. Each mode's line lists the problems it did not solve (index in the set, 0-based).
//! `-- problems=I,J,…` runs those problems alone.
//!
//! **Checks.** Clearance 0 (touching is a collision, as in MoveIt), OMPL's resolution 0.01 rad
//! ([`PathSettings::default`]), seeded, 2 s budget per problem. Every returned path is
//! re-checked with the exact check at a quarter of the planner's spacing ([`first_invalid`]);
//! paths failing it are reported (issue 23's thin-obstacle problem).
//!
//! [`plan_arm`]: kinscene::motion::paths::plan_arm
//! [`plan_arm_with_motion`]: kinscene::motion::paths::plan_arm_with_motion
//! [`first_invalid`]: kinscene::motion::paths::first_invalid
//! [`PathSettings::default`]: kinscene::motion::paths::PathSettings

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use kinscene::Termination;
use kinscene::kinematics::robot::{
    ArmCheck, EdgeScene, Exempt, RobotCollision, RobotConfig, RobotImportOptions, RobotModel,
    RobotSpheres, SphereData, SphereObstacles, SphereSettings, Srdf,
};
use kinscene::motion::paths::{
    MotionCheck, PathOutcome, PathSettings, Simplifier, first_invalid, plan_arm, plan_arm_checked,
    plan_arm_with_motion,
};
use kinscene::scene::{
    BaseShape, SceneData, SceneModel, SceneModelBuilder, Shape, State, forward_kinematics,
};
use nalgebra::{DVector, Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use serde::Deserialize;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Planning modes: exact, sphere fast path, [`ArmCheck`] with OMPL's full
/// simplifier and with [`Simplifier::Shortcut`], the latter evaluating every state of a
/// motion ([`ArmCheck::with_spans`] off, for the spans' saving), and the latter certifying
/// every motion continuously ([`ArmCheck::with_continuous`]).
const MODES: usize = 6;

#[derive(Deserialize)]
struct Problem {
    set: String,
    start: Vec<f64>,
    goal: Vec<f64>,
    obstacles: Vec<Obstacle>,
}

#[derive(Deserialize)]
struct Obstacle {
    kind: String,
    dims: Vec<f64>,
    position: [f64; 3],
    orientation: [f64; 4],
}

fn run(cmd: &mut Command) {
    let status = cmd.status().unwrap_or_else(|e| panic!("{cmd:?}: {e}"));
    assert!(status.success(), "{cmd:?} failed: {status}");
}

/// `target/mbm/problems.json` (under `$CARGO_TARGET_DIR` when that is set), fetched and
/// converted on the first run.
fn problems() -> Vec<Problem> {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map_or_else(|| Path::new(ROOT).join("target"), PathBuf::from);
    let dir = target.join("mbm");
    let json = dir.join("problems.json");
    if !json.exists() {
        std::fs::create_dir_all(&dir).expect("target/mbm is writable");
        let find_sdist = || {
            std::fs::read_dir(&dir)
                .ok()?
                .filter_map(Result::ok)
                .map(|e| e.path())
                .find(|p| {
                    p.file_name()
                        .is_some_and(|n| n.to_string_lossy().starts_with("vamp_planner-"))
                        && p.to_string_lossy().ends_with(".tar.gz")
                })
        };
        let python = std::env::var("PYTHON").unwrap_or_else(|_| default_python());
        if find_sdist().is_none() {
            run(Command::new(&python)
                .arg(Path::new(ROOT).join("benches/mbm/fetch.py"))
                .arg(&dir));
        }
        let sdist = find_sdist().expect("fetch.py left the vamp-planner sdist in target/mbm");
        let stem = sdist
            .file_name()
            .unwrap()
            .to_string_lossy()
            .replace(".tar.gz", "");
        let inner = format!("{stem}/resources/panda/problems.tar.bz2");
        run(Command::new("tar")
            .arg("xzf")
            .arg(&sdist)
            .arg("-C")
            .arg(&dir)
            .arg(&inner));
        run(Command::new("tar")
            .arg("xjf")
            .arg(dir.join(&inner))
            .arg("-C")
            .arg(&dir));
        run(Command::new(&python)
            .arg(Path::new(ROOT).join("benches/mbm/convert.py"))
            .arg(dir.join("problems"))
            .arg(&json));
    }
    let text = std::fs::read_to_string(&json).expect("problems.json is readable");
    serde_json::from_str(&text).expect("problems.json parses")
}

/// The bench venv's Python (`setup.sh --bench`, which installs PyYAML), else `python3`.
fn default_python() -> String {
    let venv = Path::new(ROOT).join(".deps/bench-venv/bin/python");
    if venv.exists() {
        venv.to_string_lossy().into_owned()
    } else {
        "python3".into()
    }
}

fn example_robot_data() -> PathBuf {
    let lib = Path::new(ROOT).join(".deps/venv/lib");
    std::fs::read_dir(&lib)
        .ok()
        .and_then(|entries| {
            entries
                .filter_map(Result::ok)
                .map(|e| {
                    e.path()
                        .join("site-packages/cmeel.prefix/share/example-robot-data")
                })
                .find(|p| p.is_dir())
        })
        .unwrap_or_else(|| panic!("example-robot-data is not in {lib:?}"))
}

fn panda() -> RobotModel {
    let erd = example_robot_data();
    let root = erd.join("robots/panda_description");
    let mut options = RobotImportOptions {
        tool_link: "panda_hand".into(),
        ..RobotImportOptions::default()
    };
    options
        .package_paths
        .insert("example-robot-data".into(), erd);
    for finger in ["panda_finger_joint1", "panda_finger_joint2"] {
        options.frozen.insert(finger.into(), 0.04);
    }
    let robot = RobotModel::from_urdf_file_with(&root.join("urdf/panda.urdf"), &options)
        .expect("the Panda loads");
    let srdf = std::fs::read_to_string(root.join("srdf/panda.srdf")).expect("SRDF readable");
    robot
        .with_srdf(&Srdf::parse(&srdf).expect("SRDF parses"))
        .expect("SRDF fits")
}

fn scene(problem: &Problem) -> (SceneModel, SceneData) {
    let mut b = SceneModelBuilder::new();
    for (k, o) in problem.obstacles.iter().enumerate() {
        let shape = match o.kind.as_str() {
            "box" => Shape::box_size(Vector3::new(o.dims[0], o.dims[1], o.dims[2])),
            "cylinder" => Shape::cylinder(o.dims[1], o.dims[0]),
            "sphere" => Shape::sphere(o.dims[0]),
            other => panic!("unknown primitive {other}"),
        };
        let [x, y, z, w] = o.orientation;
        let pose = Isometry3::from_parts(
            Translation3::from(Vector3::from(o.position)),
            UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)),
        );
        b.add_base_shape(BaseShape::new(format!("o{k}"), shape, pose));
    }
    let model = b.build().expect("the scene builds");
    let mut data = SceneData::new(&model);
    let state = State::from_slice(&model, &[]).expect("no joints");
    forward_kinematics(&model, &mut data, &state).expect("no joints");
    (model, data)
}

/// A validity closure as `plan_arm` takes it.
type Checker<'a> = dyn Fn(&[f64]) -> bool + Sync + 'a;

struct Stats {
    times: Vec<Duration>,
    recheck_failures: usize,
    /// Returned paths with a segment the continuous check certifies in neither direction (it
    /// touches, or comes within `CONTACT_CLEARANCE`, 10 µm).
    uncertified: usize,
    /// The problems not solved (indices in the set).
    unsolved: Vec<usize>,
    /// FNV-1a over the bits of every returned path's values, in problem order: equal digests
    /// from two builds mean the same paths (the validity answers did not change).
    digest: u64,
}

fn quantile(sorted: &[Duration], q: f64) -> Duration {
    if sorted.is_empty() {
        return Duration::ZERO;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn main() {
    let per_set: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(100);
    let with_exact = !std::env::args().any(|a| a == "no-exact");
    let with_fast = !std::env::args().any(|a| a == "no-fast");
    let profile = std::env::args().any(|a| a == "profile");
    // `only=K`: run mode K alone (0-based, the order of `names` below; for instruction counts
    // under callgrind).
    let only: Option<usize> =
        std::env::args().find_map(|a| a.strip_prefix("only=").and_then(|k| k.parse().ok()));
    // `no-spans`: the two `ArmCheck` modes evaluate every state too (a cross-check).
    let no_spans = std::env::args().any(|a| a == "no-spans");
    let mut profiles: Vec<Profile> = Vec::new();
    let mut problems = problems();
    let mut taken = std::collections::BTreeMap::<String, usize>::new();
    problems.retain(|p| {
        let n = taken.entry(p.set.clone()).or_default();
        *n += 1;
        *n <= per_set
    });
    let robot = panda();
    let collision = RobotCollision::new(&robot).expect("collision model");
    // `spheres=N`: at most N spheres per link (default: SphereSettings::default()).
    let sphere_settings = SphereSettings {
        max_per_link: std::env::args()
            .find_map(|a| a.strip_prefix("spheres=").and_then(|n| n.parse().ok()))
            .unwrap_or(SphereSettings::default().max_per_link),
        ..SphereSettings::default()
    };
    let spheres = RobotSpheres::new(&robot, &collision, &sphere_settings).expect("sphere model");
    let (lower, upper) = robot.arm_bounds();
    let (lower, upper) = (lower.as_slice().to_vec(), upper.as_slice().to_vec());
    // `budget=S`: the budget per problem in seconds (default 2; raise it under callgrind,
    // where a 2 s budget cuts planning and simplification short).
    let budget = std::env::args()
        .find_map(|a| a.strip_prefix("budget=").and_then(|s| s.parse().ok()))
        .unwrap_or(2.0);
    // `iterations=N`: RRTConnect also ends after N iterations (PathSettings::max_iterations),
    // so that a problem it does not solve costs the same work on every machine (for
    // instruction counts under callgrind with a large budget).
    let max_iterations =
        std::env::args().find_map(|a| a.strip_prefix("iterations=").and_then(|n| n.parse().ok()));
    // `range=R`: RRTConnect's range (rad) instead of the arm paths' default (`ARM_RANGE`).
    let range =
        std::env::args().find_map(|a| a.strip_prefix("range=").and_then(|r| r.parse().ok()));
    let settings = PathSettings {
        budget: Duration::from_secs_f64(budget),
        max_iterations,
        range,
        seed: Some(1),
        // The full simplifier, the hierarchical planner's (the paths' default is Shortcut).
        simplifier: Simplifier::Full,
        ..PathSettings::default()
    };
    let shortcut = PathSettings {
        simplifier: Simplifier::Shortcut,
        ..settings.clone()
    };
    println!(
        "MotionBenchMaker Panda: {} problems, {} spheres on the robot",
        problems.len(),
        spheres.count()
    );
    let mut stats = [(); MODES].map(|_| Stats {
        times: Vec::new(),
        recheck_failures: 0,
        uncertified: 0,
        unsolved: Vec::new(),
        digest: 0xcbf2_9ce4_8422_2325,
    });
    // The problems run (all, or those of `problems=`) and those of them not attempted.
    let mut considered = 0;
    let mut invalid_endpoints = 0;
    // Problems with a start or goal outside the joint limits (index, which, joint, value).
    let mut out_of_limits: Vec<(usize, &str, usize, f64)> = Vec::new();
    // `problems=I,J,…`: only these problems (indices in the set).
    let chosen: Option<Vec<usize>> = std::env::args().find_map(|a| {
        a.strip_prefix("problems=")
            .map(|l| l.split(',').filter_map(|i| i.trim().parse().ok()).collect())
    });
    let mut warmed = false;
    for (index, problem) in problems.iter().enumerate() {
        if chosen.as_ref().is_some_and(|c| !c.contains(&index)) {
            continue;
        }
        considered += 1;
        let outside = [("start", &problem.start), ("goal", &problem.goal)]
            .into_iter()
            .flat_map(|(which, q)| q.iter().enumerate().map(move |(j, &v)| (which, j, v)))
            .find(|&(_, j, v)| !(lower[j]..=upper[j]).contains(&v));
        if let Some((which, j, v)) = outside {
            out_of_limits.push((index, which, j, v));
            invalid_endpoints += 1;
            continue;
        }
        let (model, data) = scene(problem);
        let poses = |q: &[f64]| {
            robot
                .link_poses(&RobotConfig {
                    base: [0.0; 3],
                    arm: DVector::from_column_slice(q),
                })
                .ok()
        };
        let exact = |q: &[f64]| {
            poses(q).is_some_and(|p| {
                collision.self_collision(&p).is_none()
                    && collision
                        .scene_collision(&p, &model, &data, Exempt::Nothing, 0.0)
                        .is_none()
            })
        };
        if !exact(&problem.start) || !exact(&problem.goal) {
            invalid_endpoints += 1;
            continue;
        }
        let obstacles = SphereObstacles::new(&model, &data, Exempt::Nothing, 0.0);
        let fast = |q: &[f64]| {
            let Some(p) = poses(q) else { return false };
            let mut placed = SphereData::default();
            spheres.place(&p, &mut placed);
            spheres
                .self_collision_exact(&placed, &collision, &p)
                .is_none()
                && (obstacles.first_hit(&placed).is_none()
                    || collision
                        .scene_collision(&p, &model, &data, Exempt::Nothing, 0.0)
                        .is_none())
        };
        let edge_scene = EdgeScene {
            model: &model,
            data: &data,
            exempt: Exempt::Nothing,
            margin: 0.0,
        };
        let arm_check = || {
            ArmCheck::new(&robot, &collision, &spheres, edge_scene, [0.0; 3]).expect("arm check")
        };
        let arm = arm_check().with_continuous(false).with_spans(!no_spans);
        let dense = arm_check().with_continuous(false).with_spans(false);
        let continuous = arm_check();
        let arm_valid = |q: &[f64]| arm.is_valid(q);
        let arm_motion = |a: &[f64], b: &[f64]| arm.check_motion(a, b, settings.resolution);
        let dense_valid = |q: &[f64]| dense.is_valid(q);
        let dense_motion = |a: &[f64], b: &[f64]| dense.check_motion(a, b, settings.resolution);
        let continuous_valid = |q: &[f64]| continuous.is_valid(q);
        let continuous_motion =
            |a: &[f64], b: &[f64]| continuous.check_motion(a, b, settings.resolution);
        let modes: [(&Checker<'_>, Option<&MotionCheck<'_>>, &PathSettings); MODES] = [
            (&exact, None, &settings),
            (&fast, None, &settings),
            (&arm_valid, Some(&arm_motion), &settings),
            (&arm_valid, Some(&arm_motion), &shortcut),
            (&dense_valid, Some(&dense_motion), &shortcut),
            (&continuous_valid, Some(&continuous_motion), &shortcut),
        ];
        if profile {
            let settings_off = PathSettings {
                simplify: false,
                ..settings.clone()
            };
            for (k, name) in [
                (1, "fast"),
                (2, "arm"),
                (3, "arm shortcut"),
                (4, "dense shortcut"),
                (5, "continuous shortcut"),
            ] {
                if k == 1 && !with_fast {
                    continue;
                }
                let (check, motion, s) = modes[k];
                let runs: &[(bool, &PathSettings)] = if k == 3 || k == 4 {
                    &[(true, s)]
                } else {
                    &[(true, s), (false, &settings_off)]
                };
                for &(simplified, s) in runs {
                    profiles.push(profile_one(
                        name, simplified, problem, &lower, &upper, check, motion, s,
                    ));
                }
            }
            continue;
        }
        if !warmed {
            // The first call loads the OMPL shim: not charged to any problem.
            let _ = plan_arm(
                &problem.start,
                &problem.goal,
                &lower,
                &upper,
                &exact,
                &settings,
                &Termination::none(),
            );
            warmed = true;
        }
        for (k, (stat, (check, motion, settings))) in stats.iter_mut().zip(modes).enumerate() {
            if k == 0 && !with_exact || k == 1 && !with_fast || only.is_some_and(|o| o != k) {
                continue;
            }
            // The `ArmCheck` modes through the public call a user makes, `plan_arm_checked`.
            let arm_check = match k {
                2 | 3 => Some(&arm),
                4 => Some(&dense),
                5 => Some(&continuous),
                _ => None,
            };
            let t0 = Instant::now();
            let outcome = match arm_check {
                Some(arm_check) => plan_arm_checked(
                    &problem.start,
                    &problem.goal,
                    &lower,
                    &upper,
                    arm_check,
                    settings,
                    &Termination::none(),
                ),
                None => plan_arm_with_motion(
                    &problem.start,
                    &problem.goal,
                    &lower,
                    &upper,
                    check,
                    motion,
                    settings,
                    &Termination::none(),
                ),
            }
            .expect("valid input");
            let elapsed = t0.elapsed();
            stat.times.push(elapsed);
            let PathOutcome::Solved(path) = outcome else {
                stat.unsolved.push(index);
                continue;
            };
            for v in path.iter().flatten() {
                for byte in v.to_bits().to_le_bytes() {
                    stat.digest = (stat.digest ^ u64::from(byte)).wrapping_mul(0x100_0000_01b3);
                }
            }
            if first_invalid(&path, settings.resolution / 4.0, false, &exact).is_some() {
                stat.recheck_failures += 1;
            }
            if path.windows(2).any(|w| {
                !continuous.check_motion(&w[0], &w[1], settings.resolution)
                    && !continuous.check_motion(&w[1], &w[0], settings.resolution)
            }) {
                stat.uncertified += 1;
            }
        }
    }
    if profile {
        report_profiles(&profiles);
        return;
    }
    let attempted = considered - invalid_endpoints;
    let limits: Vec<String> = out_of_limits
        .iter()
        .map(|(i, which, j, v)| format!("{i} ({which} joint {} at {v:.4} rad)", j + 1))
        .collect();
    println!(
        "invalid endpoints: {invalid_endpoints} (start or goal collides with this Panda model, \
         or lies outside its joint limits: {})",
        if limits.is_empty() {
            "none".to_string()
        } else {
            limits.join(", ")
        }
    );
    let mut medians = Vec::new();
    let names = [
        "exact parry",
        "sphere fast path",
        "ArmCheck, motions in Rust",
        "ArmCheck, shortcut simplifier",
        "shortcut, no spans",
        "shortcut, continuous",
    ];
    for (name, stat) in names.iter().zip(&mut stats) {
        if stat.times.is_empty() {
            medians.push(Duration::ZERO);
            continue;
        }
        stat.times.sort();
        let median = quantile(&stat.times, 0.5);
        let solved = stat.times.len() - stat.unsolved.len();
        medians.push(median);
        println!(
            "{name:>26}: solved {}/{attempted} ({:.1} %), median {:.2} ms, p95 {:.2} ms, \
             exact re-check at 1/4 spacing fails on {}, continuous check rejects {} (touching \
             or within 10 um), paths {:016x}, unsolved {:?}",
            solved,
            100.0 * solved as f64 / attempted.max(1) as f64,
            median.as_secs_f64() * 1e3,
            quantile(&stat.times, 0.95).as_secs_f64() * 1e3,
            stat.recheck_failures,
            stat.uncertified,
            stat.digest,
            stat.unsolved
        );
    }
    // 0 where either mode was skipped (its median is zero), not a quotient by zero.
    let ratio = |a: usize, b: usize| {
        let (x, y) = (medians[a].as_secs_f64(), medians[b].as_secs_f64());
        if x > 0.0 && y > 0.0 { x / y } else { 0.0 }
    };
    println!(
        "median ratios against ArmCheck (full simplifier): exact {:.2}, fast path {:.2}, \
         ArmCheck with shortcut simplifier {:.2}; against the fast path: \
         ArmCheck {:.2}, ArmCheck with shortcut {:.2}; shortcut without spans against with \
         them {:.2}; shortcut with continuous motions against discrete {:.2} (0 where a mode \
         was skipped; targets: 100 % of solvable, median <= 1 ms, p95 <= 20 ms)",
        ratio(0, 2),
        ratio(1, 2),
        ratio(3, 2),
        ratio(2, 1),
        ratio(3, 1),
        ratio(4, 3),
        ratio(5, 3)
    );
}

/// One plan's time split: wall clock, time inside the Rust callbacks, calls.
struct Profile {
    mode: &'static str,
    simplified: bool,
    solved: bool,
    wall: Duration,
    in_checks: Duration,
    states: u64,
    motions: u64,
}

/// Plans `problem` once with counting wrappers around the callbacks.
#[allow(clippy::too_many_arguments)]
fn profile_one(
    mode: &'static str,
    simplified: bool,
    problem: &Problem,
    lower: &[f64],
    upper: &[f64],
    check: &Checker<'_>,
    motion: Option<&MotionCheck<'_>>,
    settings: &PathSettings,
) -> Profile {
    use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
    let (states, motions, ns) = (AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0));
    let timed = |f: &dyn Fn() -> bool, count: &AtomicU64| {
        let t = Instant::now();
        let v = f();
        ns.fetch_add(t.elapsed().as_nanos() as u64, Relaxed);
        count.fetch_add(1, Relaxed);
        v
    };
    let valid = |q: &[f64]| timed(&|| check(q), &states);
    let (timed, motions_count) = (&timed, &motions);
    let whole = motion.map(|m| move |a: &[f64], b: &[f64]| timed(&|| m(a, b), motions_count));
    let whole = whole.as_ref().map(|m| m as &MotionCheck<'_>);
    let t0 = Instant::now();
    let outcome = plan_arm_with_motion(
        &problem.start,
        &problem.goal,
        lower,
        upper,
        &valid,
        whole,
        settings,
        &Termination::none(),
    )
    .expect("valid input");
    Profile {
        mode,
        simplified,
        solved: matches!(outcome, PathOutcome::Solved(_)),
        wall: t0.elapsed(),
        in_checks: Duration::from_nanos(ns.load(Relaxed)),
        states: states.load(Relaxed),
        motions: motions.load(Relaxed),
    }
}

/// Medians per mode, with and without simplification, over the problems both solved.
fn report_profiles(profiles: &[Profile]) {
    for mode in [
        "fast",
        "arm",
        "arm shortcut",
        "dense shortcut",
        "continuous shortcut",
    ] {
        for simplified in [true, false] {
            let mut rows: Vec<&Profile> = profiles
                .iter()
                .filter(|p| p.mode == mode && p.simplified == simplified && p.solved)
                .collect();
            if rows.is_empty() {
                continue;
            }
            let median = |f: &dyn Fn(&Profile) -> f64, rows: &mut Vec<&Profile>| {
                rows.sort_by(|a, b| f(a).total_cmp(&f(b)));
                f(rows[rows.len() / 2])
            };
            let wall = median(&|p| p.wall.as_secs_f64() * 1e3, &mut rows);
            let share = median(
                &|p| p.in_checks.as_secs_f64() / p.wall.as_secs_f64(),
                &mut rows,
            );
            let states = median(&|p| p.states as f64, &mut rows);
            let motions = median(&|p| p.motions as f64, &mut rows);
            let per_call = median(
                &|p| p.in_checks.as_secs_f64() * 1e6 / (p.states + p.motions).max(1) as f64,
                &mut rows,
            );
            println!(
                "profile {mode:>12} simplify {simplified:>5}: {} solved, median wall {wall:.2} ms, \
                 in callbacks {:.0} %, state calls {states:.0}, motion calls {motions:.0}, \
                 {per_call:.2} us per call",
                rows.len(),
                share * 100.0
            );
        }
    }
}
