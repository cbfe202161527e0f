//! Inverse kinematics on the shipped Kinova Gen3 (issue 5's measurement), against pink.
//!
//! 10 000 random arm configurations (ChaCha8, seed 5; uniform within the joint limits,
//! continuous joints uniform in [−π, π)) → forward kinematics (Pinocchio) → full-pose IK of the
//! tool frame from the robot's neutral configuration with the default [`IkSettings`]
//! (1e-5 m / 1e-4 rad, 50 restarts, 50 ms budget). Printed: success rate, median and p95
//! wall-clock µs per solve, QP steps, and the CPU time per solve (from the thread's schedstat;
//! unlike wall-clock time it does not grow when other processes share the cores). Then the same targets through pink (Python Pinocchio + QP IK, run by
//! `scripts/ik_pink.py` with the bench venv `.deps/bench-venv` that `setup.sh` creates; same
//! algorithm and settings, see the script) and the ratio. Finally criterion times `solve_with`
//! on a fixed subset of 200 of the targets (µs per solve).
//!
//! Run: `cargo bench --bench ik -- --warm-up-time 1 --measurement-time 2`. Set
//! `KINSCENE_IK_SAMPLES` to use fewer targets (both solvers), `KINSCENE_SKIP_PINK=1` to skip
//! pink.

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use criterion::{Criterion, criterion_group, criterion_main};
use kinscene::kinematics::ik::{IkData, IkOutcome, IkSettings, IkSolver, IkTarget};
use kinscene::kinematics::pinocchio as pin;
use kinscene::kinematics::robot::RobotModel;
use nalgebra::{DVector, Isometry3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The sample count.
const SAMPLES: usize = 10_000;
/// Targets timed by criterion (the first ones of the sample).
const CRITERION_SUBSET: usize = 200;
/// The shipped robot's URDF, for pink (the Rust side embeds the same file).
const URDF: &str = "robots/kinova_gen3_mobile.urdf";
/// The tool frame's link in that URDF (the Rust model calls the same frame `"tool"`).
const URDF_TOOL_LINK: &str = "tool_frame";

fn random_arm(lower: &DVector<f64>, upper: &DVector<f64>, rng: &mut ChaCha8Rng) -> DVector<f64> {
    DVector::from_fn(lower.len(), |i, _| {
        let (lo, hi) = (lower[i], upper[i]);
        if lo.is_finite() && hi.is_finite() {
            rng.random_range(lo..=hi)
        } else {
            rng.random_range(-std::f64::consts::PI..std::f64::consts::PI)
        }
    })
}

fn targets(robot: &RobotModel, samples: usize) -> Vec<Isometry3<f64>> {
    let model = robot.pinocchio();
    let mut data = pin::Data::new(model).expect("the Pinocchio shim loads");
    let (lower, upper) = robot.arm_bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    (0..samples)
        .map(|_| {
            let q = random_arm(&lower, &upper, &mut rng);
            pin::forward_kinematics(model, &mut data, &q).expect("fk");
            pin::frame_placement(model, &data, robot.tool_frame()).expect("placement")
        })
        .collect()
}

/// `sorted[p · (n − 1)]`, nearest rank.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

/// CPU time this thread has run (s): the first field of `/proc/thread-self/schedstat`
/// (nanoseconds on CPU). `None` where the kernel does not provide it.
fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// Success count, sorted wall-clock solve times (µs), QP steps and the CPU time of the whole
/// run (s), which unlike wall-clock time does not grow when other processes share the cores.
struct Summary {
    solved: usize,
    times_us: Vec<f64>,
    steps: usize,
    cpu_s: Option<f64>,
}

impl Summary {
    fn new(solved: usize, mut times_us: Vec<f64>, steps: usize, cpu_s: Option<f64>) -> Summary {
        times_us.sort_by(f64::total_cmp);
        Summary {
            solved,
            times_us,
            steps,
            cpu_s,
        }
    }

    /// Mean CPU time per solve (µs).
    fn cpu_per_solve(&self) -> Option<f64> {
        self.cpu_s.map(|s| s * 1e6 / self.times_us.len() as f64)
    }

    fn median(&self) -> f64 {
        percentile(&self.times_us, 0.5)
    }

    fn print(&self, who: &str) {
        let n = self.times_us.len();
        let total: f64 = self.times_us.iter().sum();
        let cpu = match self.cpu_per_solve() {
            Some(cpu) => format!(
                "; CPU {cpu:.0} µs per solve, {:.1} µs per step",
                cpu * n as f64 / self.steps.max(1) as f64
            ),
            None => String::new(),
        };
        println!(
            "ik/gen3 {who}: {}/{n} converged ({:.2} %); wall median {:.0} µs, p95 {:.0} µs, mean {:.0} µs per solve; {} QP steps{cpu}",
            self.solved,
            100.0 * self.solved as f64 / n as f64,
            self.median(),
            percentile(&self.times_us, 0.95),
            total / n as f64,
            self.steps,
        );
    }
}

fn ours(solver: &IkSolver, seed: &DVector<f64>, targets: &[Isometry3<f64>]) -> Summary {
    let mut data = IkData::new(solver).expect("scratch");
    let mut times = Vec::with_capacity(targets.len());
    let (mut solved, mut steps) = (0, 0);
    let cpu_start = thread_cpu_seconds();
    for target in targets {
        let start = Instant::now();
        let outcome = solver
            .solve_with(&mut data, &IkTarget::Pose(*target), seed)
            .expect("valid input");
        times.push(start.elapsed().as_secs_f64() * 1e6);
        match outcome {
            IkOutcome::Converged { iterations, .. } => {
                solved += 1;
                steps += iterations;
            }
            IkOutcome::NotConverged {
                position_error,
                rotation_error,
                reason,
                ..
            } => println!(
                "  not converged: {position_error:.2e} m, {rotation_error:.2e} rad ({reason})"
            ),
        }
    }
    let cpu = thread_cpu_seconds()
        .zip(cpu_start)
        .map(|(end, start)| end - start);
    // Steps of failed solves are not reported by the outcome; the per-step figure counts
    // converged solves' steps against all the time, so it is an upper bound.
    Summary::new(solved, times, steps, cpu)
}

/// Runs `scripts/ik_pink.py` on the targets; `Err` says why pink could not run.
fn pink(
    robot: &RobotModel,
    seed: &DVector<f64>,
    settings: &IkSettings,
    targets: &[Isometry3<f64>],
) -> Result<(Summary, String), String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let python = root.join(".deps/bench-venv/bin/python");
    if !python.exists() {
        return Err(format!(
            "{} not found: run `bash setup.sh` (it creates the bench venv from scripts/bench-requirements.txt)",
            python.display()
        ));
    }
    let xyzquat = |t: &Isometry3<f64>| {
        let (p, r) = (t.translation.vector, t.rotation.coords);
        [p.x, p.y, p.z, r.x, r.y, r.z, r.w]
    };
    let poses: Vec<[f64; 7]> = targets.iter().map(xyzquat).collect();
    // The tool pose at the seed, which the script checks against its own model of the URDF:
    // the same frames on both sides, or it stops.
    let seed_pose = robot
        .base_from_tool(seed)
        .map_err(|e| format!("forward kinematics at the seed: {e}"))?;
    let input = serde_json::json!({
        "urdf": root.join(URDF),
        "frame": URDF_TOOL_LINK,
        "joints": robot.arm_joints().iter().map(|j| j.name.clone()).collect::<Vec<_>>(),
        "seed": seed.as_slice(),
        "seed_pose": xyzquat(&seed_pose),
        "targets": poses,
        "settings": {
            "position_tolerance": settings.position_tolerance,
            "rotation_tolerance": settings.rotation_tolerance,
            "max_iterations": settings.max_iterations,
            "max_step": settings.max_step,
            "damping": settings.damping,
            "lm_damping": 0.1,
            "restarts": settings.restarts,
            "budget_s": settings.budget.as_secs_f64(),
            "seed": settings.seed,
        },
    });
    let dir = std::env::temp_dir();
    let stem = format!("kinscene-ik-bench-{}", std::process::id());
    let (in_path, out_path): (PathBuf, PathBuf) = (
        dir.join(format!("{stem}-in.json")),
        dir.join(format!("{stem}-out.json")),
    );
    std::fs::write(&in_path, input.to_string()).map_err(|e| format!("writing {in_path:?}: {e}"))?;
    // Small matrices: keep numpy's BLAS on one thread, like the Rust solver.
    let run = Command::new(&python)
        .env("OPENBLAS_NUM_THREADS", "1")
        .env("OMP_NUM_THREADS", "1")
        .arg(root.join("scripts/ik_pink.py"))
        .arg(&in_path)
        .arg(&out_path)
        .output()
        .map_err(|e| format!("running {}: {e}", python.display()));
    let _ = std::fs::remove_file(&in_path);
    let run = run?;
    if !run.status.success() {
        return Err(format!(
            "scripts/ik_pink.py failed ({}): {}",
            run.status,
            String::from_utf8_lossy(&run.stderr).trim()
        ));
    }
    let text =
        std::fs::read_to_string(&out_path).map_err(|e| format!("reading {out_path:?}: {e}"))?;
    let _ = std::fs::remove_file(&out_path);
    let output: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("pink output: {e}"))?;
    let solved = output["solved"]
        .as_array()
        .ok_or("pink output lacks `solved`")?
        .iter()
        .filter(|s| s.as_bool() == Some(true))
        .count();
    let times: Vec<f64> = output["times_us"]
        .as_array()
        .ok_or("pink output lacks `times_us`")?
        .iter()
        .filter_map(|t| t.as_f64())
        .collect();
    if times.len() != targets.len() {
        return Err(format!(
            "pink timed {} of {} targets",
            times.len(),
            targets.len()
        ));
    }
    let steps = output["steps"].as_u64().unwrap_or(0) as usize;
    let cpu = output["cpu_s"].as_f64();
    let versions = format!(
        "pink {}, pinocchio {}, qpsolvers {}, clarabel {}",
        output["pink"], output["pinocchio"], output["qpsolvers"], output["clarabel"]
    )
    .replace('"', "");
    Ok((Summary::new(solved, times, steps, cpu), versions))
}

fn benches(c: &mut Criterion) {
    let robot = RobotModel::kinova_gen3_mobile();
    let settings = IkSettings::default();
    let solver = IkSolver::for_robot(&robot, settings.clone()).expect("valid settings");
    let seed = robot.neutral();
    let samples = std::env::var("KINSCENE_IK_SAMPLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(SAMPLES);
    let targets = targets(&robot, samples);

    let rust = ours(&solver, &seed, &targets);
    rust.print("kinscene (Rust, Pinocchio + Clarabel.rs)");
    if std::env::var("KINSCENE_SKIP_PINK").is_ok_and(|v| v == "1") {
        println!("ik/gen3 pink: skipped (KINSCENE_SKIP_PINK=1)");
    } else {
        match pink(&robot, &seed, &settings, &targets) {
            Ok((py, versions)) => {
                py.print(&format!("pink ({versions})"));
                let cpu = match (py.cpu_per_solve(), rust.cpu_per_solve()) {
                    (Some(p), Some(r)) => format!(", CPU per solve {:.1}x", p / r),
                    _ => String::new(),
                };
                println!(
                    "ik/gen3 ratio pink / kinscene: wall median {:.1}x, wall mean {:.1}x{cpu}; success {:.2} % vs {:.2} %",
                    py.median() / rust.median(),
                    py.times_us.iter().sum::<f64>() / rust.times_us.iter().sum::<f64>(),
                    100.0 * py.solved as f64 / samples as f64,
                    100.0 * rust.solved as f64 / samples as f64,
                );
            }
            Err(why) => println!("ik/gen3 pink: not run: {why}"),
        }
    }

    let subset: Vec<IkTarget> = targets
        .iter()
        .take(CRITERION_SUBSET)
        .map(|t| IkTarget::Pose(*t))
        .collect();
    let mut data = IkData::new(&solver).expect("scratch");
    let mut next = 0;
    let mut group = c.benchmark_group("ik_gen3");
    group.bench_function("pose_from_neutral", |b| {
        b.iter(|| {
            let target = &subset[next % subset.len()];
            next += 1;
            black_box(
                solver
                    .solve_with(&mut data, black_box(target), &seed)
                    .expect("valid input"),
            )
        })
    });
    group.finish();
}

criterion_group!(ik, benches);
criterion_main!(ik);
