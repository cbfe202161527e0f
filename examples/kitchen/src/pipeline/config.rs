//! The knobs of one pipeline run ([`Config`]) and their choices.

use std::path::PathBuf;

use kinscene::articulation::{ArticulationEstimator, Fused, Proprioceptive, TwoView};
use kinscene::discovery::DiscoverySettings;
use serde::{Deserialize, Serialize};

use super::{PipelineError, sim};

/// One experiment of the paper (or the task-level section kept from the old example).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Experiment {
    /// Task level only, on the authored model: every goal file of `examples/scenes/goals`
    /// with the lattice search, the validator and the paper's two baselines.
    Task,
    /// Scene-level manipulation (paper Fig. 5): goal sequences, Ours vs Random vs Oracle.
    Fig5,
    /// Single-object manipulation (paper Table I): Exploration-only vs Ours vs Oracle.
    Table1,
    /// Articulation estimation accuracy (paper Table II), both estimators.
    Table2,
    /// Discovery error analysis (paper Fig. 6).
    Fig6,
}

impl Experiment {
    /// Every experiment, in report order.
    pub const ALL: [Experiment; 5] = [
        Experiment::Task,
        Experiment::Fig5,
        Experiment::Table1,
        Experiment::Table2,
        Experiment::Fig6,
    ];

    /// The name used on the command line and in the report.
    pub fn name(self) -> &'static str {
        match self {
            Experiment::Task => "task",
            Experiment::Fig5 => "fig5",
            Experiment::Table1 => "table1",
            Experiment::Table2 => "table2",
            Experiment::Fig6 => "fig6",
        }
    }

    /// Parses a comma-separated list (`fig5,table1`; `all` for every experiment).
    ///
    /// # Errors
    /// [`PipelineError::Config`] for an unknown name or an empty list.
    pub fn parse_list(text: &str) -> Result<Vec<Experiment>, PipelineError> {
        let mut out = Vec::new();
        for name in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            if name == "all" {
                out.extend(Experiment::ALL);
                continue;
            }
            let e = Experiment::ALL
                .into_iter()
                .find(|e| e.name() == name)
                .ok_or_else(|| {
                    PipelineError::Config(format!(
                        "unknown experiment {name:?} (expected task, fig5, table1, table2, fig6 or all)"
                    ))
                })?;
            out.push(e);
        }
        out.sort();
        out.dedup();
        if out.is_empty() {
            return Err(PipelineError::Config("no experiment given".into()));
        }
        Ok(out)
    }
}

/// The articulation estimator of the discovery stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum EstimatorChoice {
    /// Two point clouds, before and after the interaction (ICP + screw decomposition): the
    /// paper's DiTH role.
    TwoView,
    /// The end-effector poses recorded while pulling (the paper's Proprioception baseline).
    Proprioceptive,
    /// Both sources in one joint fit ([`Fused`]). Not the default, so that Table II keeps
    /// the paper's two estimators; measured with `--experiments table2 --estimator fused`
    /// (5 runs): 0.30° / 1.05° / 1.2 cm, types 39 of 39.
    Fused,
}

impl EstimatorChoice {
    /// The name on the command line and in the report.
    pub fn name(self) -> &'static str {
        match self {
            EstimatorChoice::TwoView => "two-view",
            EstimatorChoice::Proprioceptive => "proprioceptive",
            EstimatorChoice::Fused => "fused",
        }
    }

    /// Parses `two-view`, `proprioceptive` or `fused`.
    ///
    /// # Errors
    /// [`PipelineError::Config`] for any other name.
    pub fn parse(text: &str) -> Result<Self, PipelineError> {
        match text.trim() {
            "two-view" | "twoview" | "two_view" => Ok(EstimatorChoice::TwoView),
            "proprioceptive" => Ok(EstimatorChoice::Proprioceptive),
            "fused" => Ok(EstimatorChoice::Fused),
            other => Err(PipelineError::Config(format!(
                "unknown estimator {other:?} (expected two-view, proprioceptive or fused)"
            ))),
        }
    }

    /// The other estimator (Table II runs both; the fused one is compared with the
    /// two-view one).
    pub fn other(self) -> Self {
        match self {
            EstimatorChoice::TwoView => EstimatorChoice::Proprioceptive,
            EstimatorChoice::Proprioceptive | EstimatorChoice::Fused => EstimatorChoice::TwoView,
        }
    }

    /// The estimator with its default settings.
    pub fn estimator(self) -> Box<dyn ArticulationEstimator> {
        match self {
            EstimatorChoice::TwoView => Box::new(TwoView::default()),
            EstimatorChoice::Proprioceptive => Box::new(Proprioceptive::default()),
            EstimatorChoice::Fused => Box::new(Fused::default()),
        }
    }
}

/// Which mapped handles the discovery stage explores.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ExploreScope {
    /// Every mapped handle (the paper's pipeline).
    All,
    /// Only the mapped handles nearest to the true handles of the joints the selected goal
    /// sequences name (goal and start joints). An experiment shortcut for small runs (tests):
    /// it uses the ground truth to choose, which a real robot could not.
    Needed,
}

/// Where the mapping stage's viewpoints come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum ViewpointChoice {
    /// The kitchen's hand-placed list ([`VIEWPOINTS`](super::stages::VIEWPOINTS)).
    #[default]
    Kitchen,
    /// Computed from the base map ([`viewpoints`](super::viewpoints::viewpoints)).
    Computed,
}

/// A method of the manipulation experiments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Method {
    /// The hierarchical planner (lattice search + motion) on the estimated model.
    Ours,
    /// The paper's Random baseline: a random order of the goal joints on the estimated model.
    Random,
    /// The hierarchical planner on the true model.
    Oracle,
}

impl Method {
    /// Every method, in report order.
    pub const ALL: [Method; 3] = [Method::Ours, Method::Random, Method::Oracle];

    /// The name in the report.
    pub fn name(self) -> &'static str {
        match self {
            Method::Ours => "Ours",
            Method::Random => "Random",
            Method::Oracle => "Oracle",
        }
    }
}

/// Everything one run of the pipeline depends on. The same configuration gives the same report
/// (wall-clock figures aside, see [`Config::wall_clock`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Config {
    /// The true kitchen (the simulator's ground truth): a scene URDF.
    pub scene: PathBuf,
    /// Seed of everything random: run `r` uses `seed + r` for the simulator (noise, faults)
    /// and the Random baseline.
    pub seed: u64,
    /// Independent runs of the whole pipeline (mapping, discovery, manipulation), >= 1.
    pub runs: usize,
    /// Depth noise of both cameras (m, standard deviation along each ray), in [0, 0.1].
    pub depth_noise: f64,
    /// Position noise of the handle detector (m, standard deviation per axis), in [0, 0.1].
    pub detector_noise: f64,
    /// The soft fingers' deflection under a pull (m, standard deviation per axis of the tool's
    /// offset from the grasp point), in [0, 0.05].
    #[serde(default = "default_grasp_deflection")]
    pub grasp_deflection: f64,
    /// The soft fingers' tilt of the approach axis under a pull (rad, standard deviation), in
    /// [0, 0.2].
    #[serde(default = "default_grasp_tilt")]
    pub grasp_tilt: f64,
    /// Probability of each injected fault (grasp slip, early joint limit, tracker loss; local
    /// navigation drift 5 cm · rate), in [0, 1].
    pub fault_rate: f64,
    /// The experiments, sorted, no duplicates, at least one.
    pub experiments: Vec<Experiment>,
    /// The estimator of the pipeline (Table II runs both).
    pub estimator: EstimatorChoice,
    /// Small sizes: fewer camera rays, fewer sequences and parts (see [`Config::quick`]).
    pub quick: bool,
    /// Budget of each planner call (s), > 0. A timeout is a failure of category "other".
    pub planner_budget: f64,
    /// Put wall-clock times into the markdown report (they differ between runs of the same
    /// configuration; without them the report is reproducible).
    pub wall_clock: bool,
    /// The Fig. 5 goal sequences by name; `None`: all of them (the first two in quick mode).
    pub sequences: Option<Vec<String>>,
    /// Which handles the discovery stage explores.
    pub explore: ExploreScope,
    /// The methods of the Fig. 5 experiment.
    pub methods: Vec<Method>,
    /// The Table I parts by true joint name; `None`: the default four (two in quick mode).
    pub table1_parts: Option<Vec<String>>,
    /// Head camera rays, columns × rows; `None`: 320 × 240 (a 640 × 480 depth image
    /// subsampled by 2; 160 × 120 in quick mode). At 160 × 120 the two-view estimator takes
    /// a third of the drawers for doors.
    pub head_rays: Option<(usize, usize)>,
    /// Settings of Algorithm 1 (see [`Config::default`] for the kitchen's values).
    pub discovery: DiscoverySettings,
    /// The mapping viewpoints of the experiments' runs (a run on another scene always computes
    /// them).
    #[serde(default)]
    pub viewpoints: ViewpointChoice,
    /// Whole-body manipulation in the planner (`PlannerSettings::whole_body` with its
    /// defaults, for Ours, Oracle and Random's refinement alike): a step that no single base
    /// pose covers may be executed with the base moving along with the arm. On by default, as
    /// in the library; off (`--fixed-base`) is the paper's fixed-base manipulation.
    #[serde(default = "default_whole_body")]
    pub whole_body: bool,
    /// Grasps turned about a bar handle (`PlacementSettings::bar_turn`, rad, in [0, π/2]; 0:
    /// the fingers across the bar only). Default: the library's,
    /// [`DEFAULT_BAR_TURN`](kinscene::motion::placement::DEFAULT_BAR_TURN).
    #[serde(default = "default_bar_turn")]
    pub bar_turn: f64,
}

fn default_whole_body() -> bool {
    true
}

fn default_bar_turn() -> f64 {
    kinscene::motion::placement::DEFAULT_BAR_TURN
}

/// Algorithm 1's settings for the kitchen and the simulated Gen3: the library defaults except
/// - `interaction_distance` 0.85 m, `approach_distance` 1.0 m: the Gen3 on its base reaches a
///   handle at the height of the top drawers (0.74 m) with a horizontal grasp only from
///   0.70 m or farther when facing it (the simulator's IK); at the default 0.6 m every such
///   grasp is `Unreachable`;
/// - `base_search_radius` 1.0 m (default 0.4): the passage between the back run and the
///   island leaves the base centre a band 0.45 .. 0.5 m from the fronts; PlanBase keeps the
///   nominal distance to the handle first and turns to the side (up to 60°), and a 60° turn at
///   0.85–1.0 m lies 0.85–1.0 m from the nominal pose;
/// - `nest_margin` 0.03 m (default 0.05): neighbouring fronts' handles stand 4.3 cm from the
///   edge of the next front (corner door A's handle next to the top drawer), so 5 cm carried
///   them along with a neighbour explored before them;
/// - `max_extra_pulls` 0 (default 3): the paper's Algorithm 1, without the keep-pulling loop,
///   so that Table II and Fig. 5 stay the measured ones until they are re-measured with it
///   (a further pull opens a front wider, which changes what later handles' paths meet).
///
/// Measured (`--quick --experiments fig5,fig6`, seed 1): 7 of the 10 mapped handles
/// registered, the sink door among them; with PlanBase's earlier rule (the free pose nearest
/// the nominal one) and a 0.5 m radius, 3–4 per run over seeds 1–3 and never the sink door.
pub fn kitchen_discovery_settings() -> DiscoverySettings {
    DiscoverySettings {
        interaction_distance: 0.85,
        approach_distance: 1.0,
        base_search_radius: 1.0,
        nest_margin: 0.03,
        max_extra_pulls: 0,
        ..DiscoverySettings::default()
    }
}

fn default_grasp_deflection() -> f64 {
    sim::GraspCompliance::default().deflection
}

fn default_grasp_tilt() -> f64 {
    sim::GraspCompliance::default().tilt
}

impl Default for Config {
    /// The full run: 5 runs of every experiment, σ = 5 mm depth and 1 cm detector noise, the
    /// simulator's grasp compliance (1 mm, 1°), no injected faults, the two-view estimator, 60 s
    /// per planner call.
    fn default() -> Self {
        Config {
            scene: crate::repository().join("examples/scenes/kitchen.urdf"),
            seed: 1,
            runs: 5,
            depth_noise: 0.005,
            detector_noise: 0.01,
            grasp_deflection: default_grasp_deflection(),
            grasp_tilt: default_grasp_tilt(),
            fault_rate: 0.0,
            experiments: Experiment::ALL.to_vec(),
            estimator: EstimatorChoice::TwoView,
            quick: false,
            planner_budget: 60.0,
            wall_clock: false,
            sequences: None,
            explore: ExploreScope::All,
            methods: Method::ALL.to_vec(),
            table1_parts: None,
            head_rays: None,
            discovery: kitchen_discovery_settings(),
            whole_body: default_whole_body(),
            bar_turn: default_bar_turn(),
            viewpoints: ViewpointChoice::Kitchen,
        }
    }
}

impl Config {
    /// The `--quick` run: one run, two goal sequences, two Table I parts, a coarser head
    /// camera.
    pub fn quick() -> Self {
        Config {
            runs: 1,
            quick: true,
            ..Config::default()
        }
    }

    /// Whether `e` is selected.
    pub fn runs_experiment(&self, e: Experiment) -> bool {
        self.experiments.contains(&e)
    }

    /// Checks every field.
    ///
    /// # Errors
    /// [`PipelineError::Config`] naming the first bad field.
    pub fn validate(&self) -> Result<(), PipelineError> {
        let bad = |m: String| Err(PipelineError::Config(m));
        if self.runs == 0 {
            return bad("runs must be at least 1".into());
        }
        for (name, v, hi) in [
            ("depth noise", self.depth_noise, 0.1),
            ("detector noise", self.detector_noise, 0.1),
            ("grasp deflection", self.grasp_deflection, 0.05),
            ("grasp tilt", self.grasp_tilt, 0.2),
            ("fault rate", self.fault_rate, 1.0),
        ] {
            if !(v.is_finite() && (0.0..=hi).contains(&v)) {
                return bad(format!("{name} {v} is outside [0, {hi}]"));
            }
        }
        if !(self.bar_turn.is_finite()
            && (0.0..=std::f64::consts::FRAC_PI_2).contains(&self.bar_turn))
        {
            return bad(format!(
                "bar turn {} rad is outside [0, π/2]",
                self.bar_turn
            ));
        }
        if !(self.planner_budget.is_finite() && self.planner_budget > 0.0) {
            return bad(format!(
                "planner budget {} s must be finite and > 0",
                self.planner_budget
            ));
        }
        if self.experiments.is_empty() {
            return bad("no experiment selected".into());
        }
        if self.methods.is_empty() {
            return bad("no method selected".into());
        }
        self.discovery
            .validate()
            .map_err(|e| PipelineError::Config(format!("discovery settings: {e}")))?;
        if let Some((c, r)) = self.head_rays {
            if c == 0 || r == 0 || c * r > 1_000_000 {
                return bad(format!("head camera rays {c} × {r} must be in 1 .. 10^6"));
            }
        }
        Ok(())
    }
}
