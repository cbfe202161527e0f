//! The report: every figure of a pipeline run ([`Report`], serialisable) and its markdown.

use std::collections::BTreeMap;

use kinscene::scene::JointKind;
use serde::Serialize;

use super::config::{Config, Method};
use super::manipulation::{Category, Verdict};
use super::matching::Match;
use super::stages::MappingSummary;

/// The scene the run used.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneSummary {
    /// The URDF file, as configured.
    pub file: String,
    /// Articulated parts.
    pub parts: usize,
    /// Handles.
    pub handles: usize,
    /// Base-map shapes.
    pub base_shapes: usize,
    /// Joint names (parts with a handle), in part order.
    pub joints: Vec<String>,
}

/// A Fig. 5 sequence checked on the true model at the task level before the runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SequenceCheck {
    /// The sequence's name.
    pub name: String,
    /// Why the order matters.
    pub about: String,
    /// Goal, readable.
    pub goal: String,
    /// Start, readable (empty: all closed).
    pub start: String,
    /// The lattice search's verdict on the true model (task level).
    pub search: String,
    /// Its order, `joint from → to`.
    pub order: Vec<String>,
    /// Random orders (seeds 0 .. tried) the task layer rejects on the true model, per category.
    pub random_rejected: BTreeMap<String, usize>,
    /// Random orders tried.
    pub random_tried: usize,
}

/// What happened to one mapped handle in the discovery stage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HandleRow {
    /// Position in the exploration order.
    pub index: usize,
    /// The mapped position (m).
    pub mapped: [f64; 3],
    /// The true joint whose handle is within the match radius, if any.
    pub true_joint: Option<String>,
    /// `registered <joint>` or `failed at <stage>: <reason>`.
    pub outcome: String,
    /// Attempts (grasp + pull).
    pub attempts: usize,
    /// How far the handle was pulled (m).
    pub pull: f64,
    /// The estimate's joint type, if the estimator ran.
    pub estimate: Option<String>,
}

/// One discovery run (one estimator).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiscoveryRun {
    /// The estimator.
    pub estimator: String,
    /// Per explored handle, in exploration order.
    pub handles: Vec<HandleRow>,
    /// Registered parts.
    pub registered: usize,
    /// Registered parts matched to true parts.
    pub matches: Vec<Match>,
    /// Simulated base time of the stage (s).
    pub base_time: f64,
    /// Simulated arm time of the stage (s).
    pub arm_time: f64,
}

/// One run of the pipeline: mapping and discovery.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunReport {
    /// Run index.
    pub run: usize,
    /// The simulator's seed.
    pub seed: u64,
    /// Stage 1.
    pub mapping: MappingSummary,
    /// Stage 2, the configured estimator first.
    pub discovery: Vec<DiscoveryRun>,
}

/// One Fig. 5 attempt.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttemptRow {
    /// Run index.
    pub run: usize,
    /// Sequence name.
    pub sequence: String,
    /// Method.
    pub method: Method,
    /// The verdict.
    pub verdict: Verdict,
}

/// One Table I measurement.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table1Row {
    /// Run index.
    pub run: usize,
    /// True joint.
    pub joint: String,
    /// Its type.
    pub kind: JointKind,
    /// `Exploration-only`, `Ours` or `Oracle`.
    pub method: String,
    /// The opening Ours and Oracle are asked for (rad or m).
    pub target: f64,
    /// The true opening reached (rad or m); `None` if nothing was executed.
    pub reached: Option<f64>,
    /// Simulated base time (s): repositioning after the global navigation for
    /// Exploration-only, the base path for Ours and Oracle.
    pub base_time: Option<f64>,
    /// Simulated arm time (s).
    pub arm_time: Option<f64>,
    /// Exploration-only: simulated time of its global navigation from the start pose to the
    /// approach pose (s), not counted in `base_time`.
    pub global_time: Option<f64>,
    /// The paper's execution time: simulated base and arm time (s) from the start of the
    /// action (as `base_time`, `arm_time`) until the true joint first moved
    /// [`THRESHOLD_REVOLUTE`] / [`THRESHOLD_PRISMATIC`]; `None` if it never did.
    pub to_threshold: Option<(f64, f64)>,
    /// Why nothing or less was reached (empty when the target was reached).
    pub note: String,
}

/// A type check of one estimate against the true joint (Table II's type accuracy).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TypeCheck {
    /// Run index.
    pub run: usize,
    /// Estimator.
    pub estimator: String,
    /// True joint.
    pub joint: String,
    /// The estimate's type (`revolute`, `prismatic`, `unknown`).
    pub estimated: String,
    /// Whether it is the true type.
    pub correct: bool,
}

/// One Table II row: a registered part matched to a true one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table2Row {
    /// Run index.
    pub run: usize,
    /// Estimator.
    pub estimator: String,
    /// The match and its errors.
    pub m: Match,
}

/// One run of the Fig. 6 error analysis: how many true handles passed each stage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fig6Row {
    /// Run index.
    pub run: usize,
    /// True handles considered.
    pub handles: usize,
    /// Passed mapping (mapped and re-detected).
    pub mapping: usize,
    /// Passed navigation.
    pub navigation: usize,
    /// Passed exploration.
    pub exploration: usize,
    /// Passed estimation: registered, matched to the true part, with the right type.
    pub estimation: usize,
    /// Mapped handles near no true handle (false positives), and how many became parts.
    pub false_positives: (usize, usize),
}

/// One goal file at the task level on the authored model (the old example's table).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TaskLevelRow {
    /// Goal file stem.
    pub goal: String,
    /// The search's verdict.
    pub search: String,
    /// Steps of the plan (`–` if none).
    pub steps: String,
    /// The validator's verdict on the plan.
    pub valid: String,
    /// The Random baseline (seed 1).
    pub random: String,
    /// The Paper baseline (seed 1).
    pub paper: String,
    /// Wall-clock search time (ms).
    pub wall_ms: f64,
}

/// The digital twin.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TwinSummary {
    /// From which run.
    pub run: usize,
    /// Joints of the estimated model.
    pub joints: usize,
    /// Joints after writing the URDF and reading it back.
    pub loaded_back: Result<usize, String>,
}

/// Every figure of a pipeline run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// The configuration.
    pub config: Config,
    /// The scene.
    pub scene: SceneSummary,
    /// The Fig. 5 sequences and their task-level check.
    pub sequences: Vec<SequenceCheck>,
    /// Mapping and discovery per run.
    pub runs: Vec<RunReport>,
    /// Fig. 5 attempts.
    pub fig5: Vec<AttemptRow>,
    /// Table I measurements.
    pub table1: Vec<Table1Row>,
    /// Table II rows (every estimator, every run).
    pub table2: Vec<Table2Row>,
    /// Type checks of every estimate (Table II's type accuracy).
    pub type_checks: Vec<TypeCheck>,
    /// Fig. 6 rows.
    pub fig6: Vec<Fig6Row>,
    /// The task-level section.
    pub task_level: Vec<TaskLevelRow>,
    /// The digital twin.
    pub twin: Option<TwinSummary>,
    /// Files written (relative to the output folder).
    pub files: Vec<String>,
    /// Remarks collected during the run (pictures that could not be drawn, ...).
    pub notes: Vec<String>,
    /// Wall-clock seconds per phase (shown only with `Config::wall_clock`).
    pub wall: Vec<(String, f64)>,
}

/// The mean of `v`, if any.
pub fn mean(v: impl IntoIterator<Item = f64>) -> Option<f64> {
    let (s, n) = v
        .into_iter()
        .filter(|x| x.is_finite())
        .fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    (n > 0).then(|| s / n as f64)
}

/// Per-method Fig. 5 tallies: attempts and count per category.
pub fn fig5_tally(rows: &[AttemptRow]) -> Vec<(Method, usize, BTreeMap<Category, usize>)> {
    Method::ALL
        .into_iter()
        .filter_map(|m| {
            let mine: Vec<&AttemptRow> = rows.iter().filter(|r| r.method == m).collect();
            if mine.is_empty() {
                return None;
            }
            let mut counts = BTreeMap::new();
            for c in Category::ALL {
                counts.insert(c, mine.iter().filter(|r| r.verdict.category == c).count());
            }
            Some((m, mine.len(), counts))
        })
        .collect()
}

/// The paper's Table I threshold of a revolute joint: 30°.
pub const THRESHOLD_REVOLUTE: f64 = std::f64::consts::PI / 6.0;
/// The paper's Table I threshold of a prismatic joint: 5 cm.
pub const THRESHOLD_PRISMATIC: f64 = 0.05;

/// Table I summary per method: base, arm (rev), arm (pris) until the threshold (the paper's
/// execution time), the same until the end of the action, opening ratio (rev), (pris), rows.
pub struct Table1Summary {
    /// Method name.
    pub method: String,
    /// Mean base time until the threshold (s), over the measurements that reached it.
    pub base: Option<f64>,
    /// Mean arm time until the threshold, revolute (s).
    pub arm_rev: Option<f64>,
    /// Mean arm time until the threshold, prismatic (s).
    pub arm_pris: Option<f64>,
    /// Measurements that reached the threshold.
    pub reached: usize,
    /// Mean base time of the whole action (s).
    pub total_base: Option<f64>,
    /// Mean arm time of the whole action, revolute (s).
    pub total_arm_rev: Option<f64>,
    /// Mean arm time of the whole action, prismatic (s).
    pub total_arm_pris: Option<f64>,
    /// Mean opening / target, revolute.
    pub open_rev: Option<f64>,
    /// Mean opening / target, prismatic.
    pub open_pris: Option<f64>,
    /// Measurements.
    pub n: usize,
}

/// The Table I summary rows, Exploration-only, Ours, Oracle.
pub fn table1_summary(rows: &[Table1Row]) -> Vec<Table1Summary> {
    ["Exploration-only", "Ours", "Oracle"]
        .into_iter()
        .filter_map(|m| {
            let mine: Vec<&Table1Row> = rows.iter().filter(|r| r.method == m).collect();
            if mine.is_empty() {
                return None;
            }
            let of = |k: JointKind| mine.iter().filter(move |r| r.kind == k);
            let open = |k| mean(of(k).map(|r| r.reached.unwrap_or(0.0) / r.target));
            Some(Table1Summary {
                method: m.to_string(),
                base: mean(mine.iter().filter_map(|r| r.to_threshold.map(|t| t.0))),
                arm_rev: mean(of(JointKind::Revolute).filter_map(|r| r.to_threshold.map(|t| t.1))),
                arm_pris: mean(
                    of(JointKind::Prismatic).filter_map(|r| r.to_threshold.map(|t| t.1)),
                ),
                reached: mine.iter().filter(|r| r.to_threshold.is_some()).count(),
                total_base: mean(mine.iter().filter_map(|r| r.base_time)),
                total_arm_rev: mean(of(JointKind::Revolute).filter_map(|r| r.arm_time)),
                total_arm_pris: mean(of(JointKind::Prismatic).filter_map(|r| r.arm_time)),
                open_rev: open(JointKind::Revolute),
                open_pris: open(JointKind::Prismatic),
                n: mine.len(),
            })
        })
        .collect()
}

/// Table II summary per estimator: prismatic angle (°), revolute angle (°), revolute position
/// (m), type accuracy, matched parts of the right type.
pub struct Table2Summary {
    /// Estimator.
    pub estimator: String,
    /// Mean axis angle error of prismatic joints (degrees).
    pub pris_angle: Option<f64>,
    /// Mean axis angle error of revolute joints (degrees).
    pub rev_angle: Option<f64>,
    /// Mean axis position error of revolute joints (m).
    pub rev_position: Option<f64>,
    /// Right types / estimates.
    pub types: (usize, usize),
    /// Prismatic and revolute parts of the right type.
    pub counts: (usize, usize),
}

/// The Table II summary rows, one per estimator in order of appearance.
pub fn table2_summary(rows: &[Table2Row], types: &[TypeCheck]) -> Vec<Table2Summary> {
    let mut names: Vec<String> = Vec::new();
    for n in rows
        .iter()
        .map(|r| &r.estimator)
        .chain(types.iter().map(|t| &t.estimator))
    {
        if !names.contains(n) {
            names.push(n.clone());
        }
    }
    names
        .into_iter()
        .map(|e| {
            let right: Vec<&Table2Row> = rows.iter().filter(|r| r.estimator == e).collect();
            let of = |k: JointKind| {
                right.iter().copied().filter(move |r| {
                    r.m.true_kind == k && r.m.est_kind == k && r.m.estimator_kind == k
                })
            };
            let t: Vec<&TypeCheck> = types.iter().filter(|t| t.estimator == e).collect();
            Table2Summary {
                pris_angle: mean(of(JointKind::Prismatic).map(|r| r.m.angle_error)),
                rev_angle: mean(of(JointKind::Revolute).map(|r| r.m.angle_error)),
                rev_position: mean(of(JointKind::Revolute).filter_map(|r| r.m.position_error)),
                types: (t.iter().filter(|t| t.correct).count(), t.len()),
                counts: (
                    of(JointKind::Prismatic).count(),
                    of(JointKind::Revolute).count(),
                ),
                estimator: e,
            }
        })
        .collect()
}

impl Report {
    /// Success rate of `method` in Fig. 5, if it ran.
    pub fn success_rate(&self, method: Method) -> Option<f64> {
        let mine: Vec<&AttemptRow> = self.fig5.iter().filter(|r| r.method == method).collect();
        (!mine.is_empty()).then(|| {
            mine.iter()
                .filter(|r| r.verdict.category == Category::Success)
                .count() as f64
                / mine.len() as f64
        })
    }

    /// Ratio of Exploration-only's mean base time to Ours' until the threshold (Table I, the
    /// paper's execution time), if both ran and reached it.
    pub fn base_ratio(&self) -> Option<f64> {
        self.ratio(|r| r.base)
    }

    /// The same ratio over the whole actions.
    pub fn total_base_ratio(&self) -> Option<f64> {
        self.ratio(|r| r.total_base)
    }

    fn ratio(&self, f: impl Fn(&Table1Summary) -> Option<f64>) -> Option<f64> {
        let s = table1_summary(&self.table1);
        let get = |m: &str| s.iter().find(|r| r.method == m).and_then(&f);
        match (get("Exploration-only"), get("Ours")) {
            (Some(e), Some(o)) if o > 0.0 => Some(e / o),
            _ => None,
        }
    }
}
