//! Inverse kinematics: the TRAC-IK protocol on the shipped Kinova Gen3 and on the Panda,
//! kinscene's fast path against its QP step paths, a plain Pinocchio damped-least-squares
//! loop, TRAC-IK and pink; then the Gen3 from its neutral configuration against pink with the
//! default settings.
//!
//! **TRAC-IK protocol** (per robot): 10 000 random arm configurations (ChaCha8, seed 5; uniform
//! within the joint limits, continuous joints uniform in [−π, π)) → forward kinematics
//! (Pinocchio) → full-pose IK of the tool frame, seeded from the middle of the limits (0 for
//! continuous joints), 1e-5 m and 1e-5 rad (norms of the position and rotation errors), a
//! 5 ms wall-clock budget. kinscene runs [`protocol_settings`]: random restarts until
//! [`PROTOCOL_STEPS`] steps (the iteration budget, which ends a solve before the wall clock on
//! an idle machine, so the figures do not depend on the load) or 5 ms. Solvers, all in the
//! same process (or called from it) on the same targets:
//! - **new**: [`StepSolver::DampedLeastSquares`] (the default: the DLS step, the QP only when
//!   a bound cuts it);
//! - **dense QP step** and **Clarabel QP step**: the same settings with [`StepSolver::Dense`]
//!   (the solver before the fast path) and [`StepSolver::Clarabel`] (before the dense path);
//! - **Pinocchio DLS loop**: [`pinocchio_dls`], the plain damped-least-squares loop with
//!   clamping and random restarts, written here in Rust over the same Pinocchio calls;
//! - **TRAC-IK**: pytracik (TRAC-IK 1.x: KDL Newton and NLopt SQP in two threads, "Speed"
//!   mode, 5 ms, ε = 1e-5 on each twist component), called on the same targets from the bench
//!   venv (see [`TRACIK_SCRIPT`]); its answers are re-checked with our tolerances by its own
//!   FK;
//! - **pink**: `scripts/ik_pink.py` (Python Pinocchio + pink's QP IK, the same algorithm as
//!   the Clarabel step path) with the protocol's tolerances and 5 ms; it has no iteration
//!   budget.
//!
//! Printed per solver: success rate, median / p95 / mean wall-clock µs per solve, steps, CPU
//! time per solve (the thread's schedstat, or the process's for the Python baselines: unlike
//! wall-clock time it does not grow when other processes share the cores), and the ratios
//! solver / new of the median, p95, mean and CPU per solve.
//!
//! The Panda is Pinocchio's parse of `panda.urdf` of the PyPI package `example-robot-data`
//! (tool frame `panda_hand`, the 7 arm joints; the finger joints keep their seed value); the
//! bench looks for it in the bench venv and skips the Panda when it is absent (or set
//! `KINSCENE_PANDA_URDF`).
//!
//! **pink, default settings**: the Gen3 targets solved from the robot's neutral configuration
//! with the default [`IkSettings`] (1e-5 m / 1e-4 rad, 50 restarts, 50 ms), by kinscene and
//! by pink. Finally criterion times `solve_with` on 200 of the Gen3 targets (default settings,
//! from neutral) and one step's Pinocchio calls.
//!
//! Run: `bash setup.sh --bench` once (the bench venv `.deps/bench-venv`, from
//! `scripts/bench-requirements.txt`; or set `KINSCENE_BENCH_VENV` to a venv with those
//! packages), then `cargo bench --bench ik -- --warm-up-time 1 --measurement-time 2`. Set
//! `KINSCENE_IK_SAMPLES` to use fewer targets (every solver), `KINSCENE_SKIP_PINK=1` to skip
//! pink, `KINSCENE_SKIP_TRACIK=1` to skip TRAC-IK, `KINSCENE_SKIP_OLD=1` to skip kinscene's QP
//! step paths, `KINSCENE_IK_VERBOSE=1` to list kinscene's failures.

use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use kinscene::kinematics::ik::{IkData, IkOutcome, IkSettings, IkSolver, IkTarget, StepSolver};
use kinscene::kinematics::pinocchio::{self as pin, FrameIndex, JointKind, Model};
use kinscene::kinematics::robot::RobotModel;
use nalgebra::{DVector, Isometry3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Targets of the TRAC-IK protocol (its published sample count).
const SAMPLES: usize = 10_000;
/// Targets timed by criterion (the first ones of the sample).
const CRITERION_SUBSET: usize = 200;
/// The shipped robot's URDF, for pink and TRAC-IK (the Rust side embeds the same file).
const GEN3_URDF: &str = "robots/kinova_gen3_mobile.urdf";
/// The Panda's URDF inside the bench venv's `example-robot-data`.
const PANDA_URDF: &str = "lib/python3.11/site-packages/cmeel.prefix/share/example-robot-data/robots/panda_description/urdf/panda.urdf";

/// The bench venv: `KINSCENE_BENCH_VENV`, else `.deps/bench-venv` of the crate.
fn bench_venv() -> PathBuf {
    std::env::var_os("KINSCENE_BENCH_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join(".deps/bench-venv"))
}
/// The protocol's wall-clock budget and tolerance.
const PROTOCOL_BUDGET: Duration = Duration::from_millis(5);
const PROTOCOL_TOLERANCE: f64 = 1e-5;
/// The protocol's iteration budget: about 1.5 µs per step on these arms in a release build
/// (Pinocchio's FK and Jacobian through the shim dominate), so 2 000 steps take ~3 ms, within
/// the 5 ms wall-clock budget on an idle machine.
const PROTOCOL_STEPS: usize = 2_000;

/// kinscene's settings for the TRAC-IK protocol.
fn protocol_settings(step_solver: StepSolver) -> IkSettings {
    IkSettings {
        position_tolerance: PROTOCOL_TOLERANCE,
        rotation_tolerance: PROTOCOL_TOLERANCE,
        restarts: usize::MAX,
        max_total_iterations: PROTOCOL_STEPS,
        budget: PROTOCOL_BUDGET,
        step_solver,
        ..IkSettings::default()
    }
}

/// A robot under test: its Pinocchio model, the tool frame, and what the Python baselines need
/// to build the same chain from the URDF.
struct Arm {
    name: &'static str,
    model: Model,
    frame: FrameIndex,
    urdf: PathBuf,
    base_link: String,
    tip_link: String,
    /// The chain's joints, root to tip (the q layout of the baselines).
    joints: Vec<String>,
}

impl Arm {
    fn gen3(robot: &RobotModel) -> Arm {
        Arm {
            name: "gen3",
            model: robot
                .pinocchio()
                .to_builder()
                .build()
                .expect("a copy of the model"),
            frame: robot.tool_frame(),
            urdf: Path::new(env!("CARGO_MANIFEST_DIR")).join(GEN3_URDF),
            base_link: "base_link".into(),
            tip_link: "tool_frame".into(),
            joints: robot.arm_joints().iter().map(|j| j.name.clone()).collect(),
        }
    }

    /// The Panda, if its URDF is on this machine; `Err` says why not.
    fn panda() -> Result<Arm, String> {
        let urdf = std::env::var_os("KINSCENE_PANDA_URDF")
            .map(PathBuf::from)
            .unwrap_or_else(|| bench_venv().join(PANDA_URDF));
        let xml = std::fs::read_to_string(&urdf).map_err(|e| {
            format!(
                "{}: {e} (pip install example-robot-data into .deps/bench-venv, or set KINSCENE_PANDA_URDF)",
                urdf.display()
            )
        })?;
        let model = Model::from_urdf_str(&xml).map_err(|e| format!("parsing the Panda: {e}"))?;
        let frame = model
            .link_frame("panda_hand")
            .ok_or("no panda_hand link in the Panda URDF")?;
        let joints = (1..=7).map(|i| format!("panda_joint{i}")).collect();
        Ok(Arm {
            name: "panda",
            model,
            frame,
            urdf,
            base_link: "panda_link0".into(),
            tip_link: "panda_hand".into(),
            joints,
        })
    }

    /// `q[idx_q]` of each chain joint, in chain order.
    fn chain_q(&self) -> Vec<usize> {
        self.joints
            .iter()
            .map(|name| {
                let j = self
                    .model
                    .joint_index(name)
                    .expect("chain joint in the model");
                self.model.joint(j).expect("valid index").idx_q
            })
            .collect()
    }

    /// The middle of every joint's limits (0 where a limit is infinite).
    fn middle(&self) -> DVector<f64> {
        let mut q = self.model.neutral();
        for joint in self.model.joints() {
            if let (JointKind::Revolute { .. } | JointKind::Prismatic { .. }, Some((lo, hi))) =
                (joint.kind, joint.limits.position)
            {
                q[joint.idx_q] = if lo.is_finite() && hi.is_finite() {
                    0.5 * (lo + hi)
                } else {
                    0.0
                };
            }
        }
        q
    }

    /// `samples` tool poses of random configurations (uniform within the limits, unlimited
    /// angles in [−π, π)).
    fn targets(&self, samples: usize) -> Vec<Isometry3<f64>> {
        let mut data = pin::Data::new(&self.model).expect("the Pinocchio shim loads");
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        (0..samples)
            .map(|_| {
                let q = self.random(&mut rng);
                pin::forward_kinematics(&self.model, &mut data, &q).expect("fk");
                pin::frame_placement(&self.model, &data, self.frame).expect("placement")
            })
            .collect()
    }

    fn random(&self, rng: &mut ChaCha8Rng) -> DVector<f64> {
        let mut q = self.model.neutral();
        for joint in self.model.joints() {
            let (lo, hi) = joint
                .limits
                .position
                .unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
            let angle = |rng: &mut ChaCha8Rng| {
                rng.random_range(-std::f64::consts::PI..std::f64::consts::PI)
            };
            match joint.kind {
                JointKind::Revolute { .. } | JointKind::Prismatic { .. } => {
                    q[joint.idx_q] = if lo.is_finite() && hi.is_finite() {
                        rng.random_range(lo..=hi)
                    } else {
                        angle(rng)
                    };
                }
                JointKind::RevoluteUnbounded { .. } => {
                    let (sin, cos) = angle(rng).sin_cos();
                    q[joint.idx_q] = cos;
                    q[joint.idx_q + 1] = sin;
                }
                JointKind::Planar => {}
            }
        }
        q
    }

    fn pose(&self, q: &DVector<f64>) -> Isometry3<f64> {
        let mut data = pin::Data::new(&self.model).expect("the Pinocchio shim loads");
        pin::forward_kinematics(&self.model, &mut data, q).expect("fk");
        pin::frame_placement(&self.model, &data, self.frame).expect("placement")
    }
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

/// Success count, sorted wall-clock solve times (µs), steps and the CPU time of the whole run
/// (s), which unlike wall-clock time does not grow when other processes share the cores.
struct Summary {
    solved: usize,
    times_us: Vec<f64>,
    steps: usize,
    cpu_s: Option<f64>,
    /// Extra figures for the printed line.
    note: String,
}

impl Summary {
    fn new(solved: usize, mut times_us: Vec<f64>, steps: usize, cpu_s: Option<f64>) -> Summary {
        times_us.sort_by(f64::total_cmp);
        Summary {
            solved,
            times_us,
            steps,
            cpu_s,
            note: String::new(),
        }
    }

    /// Mean CPU time per solve (µs).
    fn cpu_per_solve(&self) -> Option<f64> {
        self.cpu_s.map(|s| s * 1e6 / self.times_us.len() as f64)
    }

    fn median(&self) -> f64 {
        percentile(&self.times_us, 0.5)
    }

    fn p95(&self) -> f64 {
        percentile(&self.times_us, 0.95)
    }

    fn mean(&self) -> f64 {
        self.times_us.iter().sum::<f64>() / self.times_us.len() as f64
    }

    fn rate(&self) -> f64 {
        100.0 * self.solved as f64 / self.times_us.len() as f64
    }

    fn print(&self, what: &str) {
        let n = self.times_us.len();
        let steps = if self.steps > 0 {
            format!("; {} steps", self.steps)
        } else {
            String::new()
        };
        let cpu = match self.cpu_per_solve() {
            Some(cpu) if self.steps > 0 => format!(
                "; CPU {cpu:.1} µs per solve, {:.2} µs per step",
                cpu * n as f64 / self.steps as f64
            ),
            Some(cpu) => format!("; CPU {cpu:.1} µs per solve"),
            None => String::new(),
        };
        println!(
            "{what}: {}/{n} converged ({:.2} %); wall median {:.1} µs, p95 {:.1} µs, mean {:.1} µs per solve{steps}{cpu}{}",
            self.solved,
            self.rate(),
            self.median(),
            self.p95(),
            self.mean(),
            self.note,
        );
    }

    /// `other / self` for the median, p95, mean and CPU per solve.
    fn ratios(&self, other: &Summary) -> String {
        let cpu = match (other.cpu_per_solve(), self.cpu_per_solve()) {
            (Some(o), Some(s)) => format!(", CPU per solve {:.1}x", o / s),
            _ => String::new(),
        };
        format!(
            "median {:.1}x, p95 {:.1}x, mean {:.1}x{cpu}; success {:.2} % vs {:.2} %",
            other.median() / self.median(),
            other.p95() / self.p95(),
            other.mean() / self.mean(),
            other.rate(),
            self.rate(),
        )
    }
}

/// kinscene on every target from `seed`; failures are listed when `verbose`.
fn ours(
    solver: &IkSolver,
    seed: &DVector<f64>,
    targets: &[Isometry3<f64>],
    verbose: bool,
) -> Summary {
    let mut data = IkData::new(solver).expect("scratch");
    let mut times = Vec::with_capacity(targets.len());
    let (mut solved, mut steps, mut clarabel_steps, mut attempts) = (0, 0, 0, 0);
    let mut qp_steps = 0;
    let mut budget_ends = 0;
    let cpu_start = thread_cpu_seconds();
    for target in targets {
        let start = Instant::now();
        let outcome = solver
            .solve_with(&mut data, &IkTarget::Pose(*target), seed)
            .expect("valid input");
        times.push(start.elapsed().as_secs_f64() * 1e6);
        let stats = data.last_solve();
        steps += stats.steps;
        clarabel_steps += stats.clarabel_steps;
        qp_steps += stats.qp_steps;
        attempts += stats.attempts;
        match outcome {
            IkOutcome::Solved(_) => solved += 1,
            other => {
                if matches!(other, IkOutcome::Timeout(_)) {
                    budget_ends += 1;
                }
                if verbose {
                    println!("  not converged: {other}");
                }
            }
        }
    }
    let cpu = thread_cpu_seconds()
        .zip(cpu_start)
        .map(|(end, start)| end - start);
    let mut summary = Summary::new(solved, times, steps, cpu);
    summary.note = format!(
        "; {qp_steps} steps solved the QP, {clarabel_steps} by Clarabel, {:.2} attempts per solve, {budget_ends} ended by the wall clock",
        attempts as f64 / targets.len() as f64
    );
    summary
}

/// `x y z qx qy qz qw` of a pose.
fn xyzquat(t: &Isometry3<f64>) -> [f64; 7] {
    let (p, r) = (t.translation.vector, t.rotation.coords);
    [p.x, p.y, p.z, r.x, r.y, r.z, r.w]
}

/// Runs `script` (a path, or `None` for the embedded `source`) with the bench venv's python
/// on `input`; returns the JSON it wrote. `Err` says why it could not run.
fn run_python(
    script: Option<&Path>,
    source: &str,
    tag: &str,
    input: &serde_json::Value,
) -> Result<serde_json::Value, String> {
    let python = bench_venv().join("bin/python");
    if !python.exists() {
        return Err(format!(
            "{} not found: run `bash setup.sh --bench` (it creates the bench venv from scripts/bench-requirements.txt) or set KINSCENE_BENCH_VENV",
            python.display()
        ));
    }
    let dir = std::env::temp_dir();
    let stem = format!("kinscene-ik-bench-{}-{tag}", std::process::id());
    let in_path = dir.join(format!("{stem}-in.json"));
    let out_path = dir.join(format!("{stem}-out.json"));
    let embedded = script.is_none();
    let script = match script {
        Some(path) => path.to_path_buf(),
        None => {
            let path = dir.join(format!("{stem}.py"));
            std::fs::write(&path, source).map_err(|e| format!("writing {path:?}: {e}"))?;
            path
        }
    };
    std::fs::write(&in_path, input.to_string()).map_err(|e| format!("writing {in_path:?}: {e}"))?;
    // Small matrices: keep numpy's BLAS on one thread, like the Rust solver.
    let run = Command::new(&python)
        .env("OPENBLAS_NUM_THREADS", "1")
        .env("OMP_NUM_THREADS", "1")
        .arg(&script)
        .arg(&in_path)
        .arg(&out_path)
        .output()
        .map_err(|e| format!("running {}: {e}", python.display()));
    let _ = std::fs::remove_file(&in_path);
    if embedded {
        let _ = std::fs::remove_file(&script);
    }
    let run = run?;
    if !run.status.success() {
        return Err(format!(
            "{} failed ({}): {}",
            script.display(),
            run.status,
            String::from_utf8_lossy(&run.stderr).trim()
        ));
    }
    let text =
        std::fs::read_to_string(&out_path).map_err(|e| format!("reading {out_path:?}: {e}"))?;
    let _ = std::fs::remove_file(&out_path);
    serde_json::from_str(&text).map_err(|e| format!("{tag} output: {e}"))
}

/// Per-target `solved` flags and `times_us` of a Python baseline's output.
fn python_summary(
    output: &serde_json::Value,
    key: &str,
    targets: usize,
) -> Result<Summary, String> {
    let solved = output[key]
        .as_array()
        .ok_or(format!("output lacks `{key}`"))?
        .iter()
        .filter(|s| s.as_bool() == Some(true))
        .count();
    let times: Vec<f64> = output["times_us"]
        .as_array()
        .ok_or("output lacks `times_us`")?
        .iter()
        .filter_map(|t| t.as_f64())
        .collect();
    if times.len() != targets {
        return Err(format!("timed {} of {targets} targets", times.len()));
    }
    let steps = output["steps"].as_u64().unwrap_or(0) as usize;
    Ok(Summary::new(solved, times, steps, output["cpu_s"].as_f64()))
}

/// TRAC-IK (pytracik) on the arm's targets: the chain `base_link → tip_link` of the URDF, the
/// protocol's 5 ms and ε, "Speed" mode, seeded with `seed` (the chain joints' values, root to
/// tip) and given the Rust model's joint limits (see the script). The tool pose at the seed
/// is checked against the Rust model's, so both use the same frames. Each call is timed around `pytracik.ik` alone (no Python-side conversions). A
/// solution counts as TRAC-IK reports it (`solved`: its ε on each twist component) and, as
/// `within`, when its own FK puts the tool within our tolerances (norms, 1e-5 m and 1e-5 rad).
const TRACIK_SCRIPT: &str = r#"
import json, sys, time
from importlib.metadata import version
import numpy as np
import pytracik

spec = json.load(open(sys.argv[1]))
solver = pytracik.TRAC_IK(spec["base"], spec["tip"], open(spec["urdf"]).read(),
                          spec["timeout_s"], spec["epsilon"], pytracik.SolveType.Speed)
if pytracik.get_num_joints(solver) != len(spec["seed"]):
    raise SystemExit(f"TRAC-IK chain has {pytracik.get_num_joints(solver)} joints, expected {len(spec['seed'])}")
seed = np.array(spec["seed"], dtype=float)
# pytracik's URDF reader takes the <safety_controller> soft limits as 0 (the Panda's file has
# them, equal to the hard limits), which would pin every joint near 0: set the limits of the
# Rust model (the same URDF's <limit> values) where they are finite.
lower = list(pytracik.get_joint_lower_bounds(solver))
upper = list(pytracik.get_joint_upper_bounds(solver))
for i, (lo, hi) in enumerate(zip(spec["lower"], spec["upper"])):
    if lo is not None and hi is not None:
        lower[i], upper[i] = lo, hi
pytracik.set_joint_limits(solver, lower, upper)

def rotation(qx, qy, qz, qw):
    return np.array([
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]])

def errors(q, pose):
    x, y, z, qx, qy, qz, qw = pose
    m = np.asarray(pytracik.fk(solver, np.asarray(q, dtype=float)))
    dp = np.linalg.norm(m[:3, 3] - [x, y, z])
    r = rotation(qx, qy, qz, qw) @ m[:3, :3].T
    s = 0.5 * np.linalg.norm([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    c = 0.5 * (np.trace(r) - 1.0)
    return dp, np.arctan2(s, c)

dp, dr = errors(seed, spec["seed_pose"])
if dp > 1e-9 or dr > 1e-9:
    raise SystemExit(f"TRAC-IK's tool pose at the seed differs from the Rust model's by {dp} m, {dr} rad")

solved, within, times_us = [], [], []
# TRAC-IK solves in two threads of its own: count the process's CPU time, not this thread's.
cpu_start = time.process_time()
for x, y, z, qx, qy, qz, qw in spec["targets"]:
    start = time.perf_counter()
    r = pytracik.ik(solver, seed, x, y, z, qx, qy, qz, qw)
    times_us.append((time.perf_counter() - start) * 1e6)
    ok = r[0] >= 0
    solved.append(bool(ok))
    if ok:
        dp, dr = errors(r[1:], (x, y, z, qx, qy, qz, qw))
        within.append(bool(dp <= spec["tolerance"] and dr <= spec["tolerance"]))
    else:
        within.append(False)
cpu_s = time.process_time() - cpu_start
json.dump({"solved": solved, "within": within, "times_us": times_us, "cpu_s": cpu_s,
           "pytracik": version("pytracik")}, open(sys.argv[2], "w"))
"#;

/// TRAC-IK's summary (success as it reports it) and how many of its answers meet our
/// tolerances.
fn tracik(
    arm: &Arm,
    seed: &DVector<f64>,
    targets: &[Isometry3<f64>],
) -> Result<(Summary, usize, String), String> {
    let chain = arm.chain_q();
    let (lower, upper) = arm.model.position_bounds();
    let finite = |x: f64| x.is_finite().then_some(x);
    let input = serde_json::json!({
        "urdf": arm.urdf,
        "base": arm.base_link,
        "tip": arm.tip_link,
        "seed": chain.iter().map(|&i| seed[i]).collect::<Vec<_>>(),
        "lower": chain.iter().map(|&i| finite(lower[i])).collect::<Vec<_>>(),
        "upper": chain.iter().map(|&i| finite(upper[i])).collect::<Vec<_>>(),
        "seed_pose": xyzquat(&arm.pose(seed)),
        "targets": targets.iter().map(xyzquat).collect::<Vec<_>>(),
        "timeout_s": PROTOCOL_BUDGET.as_secs_f64(),
        "epsilon": PROTOCOL_TOLERANCE,
        "tolerance": PROTOCOL_TOLERANCE,
    });
    let output = run_python(None, TRACIK_SCRIPT, "tracik", &input)?;
    let summary = python_summary(&output, "solved", targets.len())?;
    let within = output["within"]
        .as_array()
        .ok_or("output lacks `within`")?
        .iter()
        .filter(|s| s.as_bool() == Some(true))
        .count();
    let version = format!("pytracik {}", output["pytracik"]).replace('"', "");
    Ok((summary, within, version))
}

/// Damping λ of the plain damped-least-squares loop ([`pinocchio_dls`]), added to JJᵀ.
const DLS_DAMPING: f64 = 1e-6;
/// Steps of one attempt of [`pinocchio_dls`] before it restarts from a random configuration.
const DLS_ATTEMPT_STEPS: usize = 50;

/// The plain damped-least-squares IK loop on Pinocchio, written here in Rust over the same
/// Pinocchio calls the solver makes (the frame placement and `LOCAL_WORLD_ALIGNED` Jacobian in
/// one pass, `integrate`): the issue's "40-line C++ Pinocchio DLS loop" without a C++ bench
/// entry in the shim. Per step: `e = [p* − p; log(R* Rᵀ)]`, stop when ‖e_p‖ and ‖e_R‖ are
/// within the tolerance, `dq = Jᵀ (JJᵀ + λI)⁻¹ e` (λ = [`DLS_DAMPING`], a full step),
/// `q ← integrate(q, dq)` clamped into the limits; after [`DLS_ATTEMPT_STEPS`] steps a restart
/// from a configuration uniform within the limits (ChaCha8, seed 0 for every target), until
/// the protocol's 5 ms run out. No trust region, no line search, no stall test.
fn pinocchio_dls(arm: &Arm, seed: &DVector<f64>, targets: &[Isometry3<f64>]) -> Summary {
    let model = &arm.model;
    let mut data = pin::Data::new(model).expect("the Pinocchio shim loads");
    let mut jacobian = nalgebra::DMatrix::zeros(6, model.nv());
    let limited: Vec<(usize, f64, f64)> = model
        .joints()
        .iter()
        .filter_map(|joint| match (joint.kind, joint.limits.position) {
            (JointKind::Revolute { .. } | JointKind::Prismatic { .. }, Some((lo, hi))) => {
                Some((joint.idx_q, lo, hi))
            }
            _ => None,
        })
        .collect();
    let mut times = Vec::with_capacity(targets.len());
    let (mut solved, mut steps) = (0, 0);
    let cpu_start = thread_cpu_seconds();
    for target in targets {
        let start = Instant::now();
        let deadline = start + PROTOCOL_BUDGET;
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let mut q = seed.clone();
        let converged = 'solve: loop {
            for _ in 0..DLS_ATTEMPT_STEPS {
                let pose = pin::frame_placement_and_jacobian(
                    model,
                    &mut data,
                    &q,
                    arm.frame,
                    &mut jacobian,
                )
                .expect("valid q");
                let dp = target.translation.vector - pose.translation.vector;
                let dr = (target.rotation * pose.rotation.inverse()).scaled_axis();
                if dp.norm() <= PROTOCOL_TOLERANCE && dr.norm() <= PROTOCOL_TOLERANCE {
                    break 'solve true;
                }
                if Instant::now() >= deadline {
                    break 'solve false;
                }
                let e = nalgebra::Vector6::new(dp.x, dp.y, dp.z, dr.x, dr.y, dr.z);
                let mut jjt = nalgebra::Matrix6::<f64>::zeros();
                for c in 0..jacobian.ncols() {
                    let column = jacobian.fixed_view::<6, 1>(0, c);
                    jjt += column * column.transpose();
                }
                for i in 0..6 {
                    jjt[(i, i)] += DLS_DAMPING;
                }
                let Some(y) = jjt.cholesky().map(|c| c.solve(&e)) else {
                    break;
                };
                let dq = jacobian.transpose() * y;
                q = pin::integrate(model, &q, &dq).expect("valid q");
                for &(i, lo, hi) in &limited {
                    q[i] = q[i].clamp(lo, hi);
                }
                steps += 1;
            }
            q = arm.random(&mut rng);
        };
        times.push(start.elapsed().as_secs_f64() * 1e6);
        solved += usize::from(converged);
    }
    let cpu = thread_cpu_seconds()
        .zip(cpu_start)
        .map(|(end, start)| end - start);
    Summary::new(solved, times, steps, cpu)
}

/// `KINSCENE_<NAME>=1` is set.
fn skip(name: &str) -> bool {
    std::env::var(format!("KINSCENE_{name}")).is_ok_and(|v| v == "1")
}

/// The TRAC-IK protocol on one arm: kinscene's fast path (new), its QP step paths, the plain
/// Pinocchio DLS loop, TRAC-IK and pink; printed with ratios to the new path.
fn protocol(arm: &Arm, samples: usize) {
    let targets = arm.targets(samples);
    let seed = arm.middle();
    let name = arm.name;
    println!(
        "ik/{name} TRAC-IK protocol: {samples} targets, seed = middle of the limits, 1e-5 m / 1e-5 rad, 5 ms, kinscene at most {PROTOCOL_STEPS} steps per solve"
    );
    let solver = |step_solver| {
        IkSolver::new(&arm.model, arm.frame, protocol_settings(step_solver))
            .expect("valid settings")
    };
    let new = solver(StepSolver::DampedLeastSquares);
    let verbose = skip("IK_VERBOSE");
    // Warm-up: the shim's first load and the caches, outside the figures.
    let _ = ours(&new, &seed, &targets[..targets.len().min(100)], false);
    let new_summary = ours(&new, &seed, &targets, verbose);
    new_summary.print(&format!("ik/{name} kinscene DLS step (new)"));
    let compare = |label: &str, summary: &Summary| {
        summary.print(&format!("ik/{name} {label}"));
        println!(
            "ik/{name} ratio {label} / new: {}",
            new_summary.ratios(summary)
        );
    };
    let dls = pinocchio_dls(arm, &seed, &targets);
    compare("Pinocchio DLS loop", &dls);
    if skip("SKIP_OLD") {
        println!("ik/{name} kinscene QP steps (dense, Clarabel): skipped (KINSCENE_SKIP_OLD=1)");
    } else {
        compare(
            "kinscene dense QP step",
            &ours(&solver(StepSolver::Dense), &seed, &targets, false),
        );
        compare(
            "kinscene Clarabel QP step",
            &ours(&solver(StepSolver::Clarabel), &seed, &targets, false),
        );
    }
    if skip("SKIP_TRACIK") {
        println!("ik/{name} TRAC-IK: skipped (KINSCENE_SKIP_TRACIK=1)");
    } else {
        match tracik(arm, &seed, &targets) {
            Ok((summary, within, version)) => {
                compare(&format!("TRAC-IK ({version}, its own ε test)"), &summary);
                println!(
                    "ik/{name} TRAC-IK answers within 1e-5 m and 1e-5 rad (norms): {within}/{} ({:.2} %)",
                    targets.len(),
                    100.0 * within as f64 / targets.len() as f64
                );
            }
            Err(why) => println!("ik/{name} TRAC-IK: not run: {why}"),
        }
    }
    if skip("SKIP_PINK") {
        println!("ik/{name} pink: skipped (KINSCENE_SKIP_PINK=1)");
    } else {
        match pink(arm, &seed, new.settings(), &targets) {
            Ok((summary, versions)) => compare(&format!("pink ({versions})"), &summary),
            Err(why) => println!("ik/{name} pink: not run: {why}"),
        }
    }
}

/// Runs `scripts/ik_pink.py` on the Gen3 targets with `settings`; `Err` says why pink could
/// not run.
fn pink(
    arm: &Arm,
    seed: &DVector<f64>,
    settings: &IkSettings,
    targets: &[Isometry3<f64>],
) -> Result<(Summary, String), String> {
    // The tool pose at the seed, which the script checks against its own model of the URDF:
    // the same frames on both sides, or it stops.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let input = serde_json::json!({
        "urdf": arm.urdf,
        "frame": arm.tip_link,
        "joints": arm.joints,
        "seed": arm.chain_q().iter().map(|&i| seed[i]).collect::<Vec<_>>(),
        "seed_pose": xyzquat(&arm.pose(seed)),
        "targets": targets.iter().map(xyzquat).collect::<Vec<_>>(),
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
    let output = run_python(Some(&root.join("scripts/ik_pink.py")), "", "pink", &input)?;
    let summary = python_summary(&output, "solved", targets.len())?;
    let versions = format!(
        "pink {}, pinocchio {}, qpsolvers {}, clarabel {}",
        output["pink"], output["pinocchio"], output["qpsolvers"], output["clarabel"]
    )
    .replace('"', "");
    Ok((summary, versions))
}

/// The pink comparison: the Gen3 from neutral with the default settings, kinscene vs pink.
fn pink_comparison(robot: &RobotModel, samples: usize) {
    let settings = IkSettings::default();
    let solver = IkSolver::for_robot(robot, settings.clone()).expect("valid settings");
    let seed = robot.neutral();
    let targets = Arm::gen3(robot).targets(samples);
    let rust = ours(&solver, &seed, &targets, true);
    rust.print("ik/gen3 default settings from neutral: kinscene");
    if skip("SKIP_PINK") {
        println!("ik/gen3 pink: skipped (KINSCENE_SKIP_PINK=1)");
        return;
    }
    match pink(&Arm::gen3(robot), &seed, &settings, &targets) {
        Ok((py, versions)) => {
            py.print(&format!(
                "ik/gen3 default settings from neutral: pink ({versions})"
            ));
            println!("ik/gen3 ratio pink / kinscene: {}", rust.ratios(&py));
        }
        Err(why) => println!("ik/gen3 pink: not run: {why}"),
    }
}

fn benches(c: &mut Criterion) {
    let robot = RobotModel::kinova_gen3_mobile();
    let samples = std::env::var("KINSCENE_IK_SAMPLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(SAMPLES);

    protocol(&Arm::gen3(&robot), samples);
    match Arm::panda() {
        Ok(panda) => protocol(&panda, samples),
        Err(why) => println!("ik/panda: skipped: {why}"),
    }
    pink_comparison(&robot, samples);

    let solver = IkSolver::for_robot(&robot, IkSettings::default()).expect("valid settings");
    let seed = robot.neutral();
    let subset: Vec<IkTarget> = Arm::gen3(&robot)
        .targets(CRITERION_SUBSET)
        .into_iter()
        .map(IkTarget::Pose)
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
    // The floor of one step: what each step asks of Pinocchio through the shim (forward
    // kinematics, the tool placement, the frame Jacobian), without the step's own arithmetic.
    let model = robot.pinocchio();
    let mut pin_data = pin::Data::new(model).expect("the Pinocchio shim loads");
    let configurations: Vec<DVector<f64>> = {
        let arm = Arm::gen3(&robot);
        let mut rng = ChaCha8Rng::seed_from_u64(6);
        (0..64).map(|_| arm.random(&mut rng)).collect()
    };
    let mut k = 0;
    group.bench_function("pinocchio_fk_placement_jacobian", |b| {
        b.iter(|| {
            let q = &configurations[k % configurations.len()];
            k += 1;
            pin::forward_kinematics(model, &mut pin_data, q).expect("fk");
            let pose = pin::frame_placement(model, &pin_data, robot.tool_frame()).expect("pose");
            let jacobian = pin::frame_jacobian(
                model,
                &mut pin_data,
                q,
                robot.tool_frame(),
                pin::ReferenceFrame::LocalWorldAligned,
            )
            .expect("jacobian");
            black_box((pose, jacobian))
        })
    });
    group.finish();
}

criterion_group!(ik, benches);
criterion_main!(ik);
