//! One pipeline session: the state shared by the runs (models, planner, report, output files)
//! and one run of the three stages with the experiments that use them.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::time::Instant;

use kinscene::discovery::{Discovery, DiscoverySettings, MappedHandle, discover};
use kinscene::kinematics::robot::RobotModel;
use kinscene::planner::PlannerResult;
use kinscene::scene::{BaseMap, SceneModel, urdf};

use super::config::{Config, EstimatorChoice, Experiment, ExploreScope, Method};
use super::manipulation::{Planning, TrueGoal, translate};
use super::matching::{self, MATCH_RADIUS, Match, PartAxis, nearest_part};
use super::output::Outputs;
use super::progress::Progress;
use super::sequences::{START_BASE, Sequence};
use super::sim::{self, SimSettings, SimWorld};
use super::stages::{self, pose};
use super::summary::{DiscoveryRun, Report, RunReport, Table2Row, TwinSummary};
use super::{PipelineError, experiments, fig5};

/// The simulator's settings for run seed `seed`.
pub fn sim_settings(config: &Config, seed: u64) -> SimSettings {
    let mut s = SimSettings {
        seed,
        faults: sim::Faults::with_rate(config.fault_rate),
        ..SimSettings::default()
    };
    s.camera.depth_noise = config.depth_noise;
    s.detector.position_noise = config.detector_noise;
    s.grasp = sim::GraspCompliance {
        deflection: config.grasp_deflection,
        tilt: config.grasp_tilt,
    };
    s.camera.head_rays = match (config.head_rays, config.quick) {
        (Some(r), _) => r,
        (None, true) => (160, 120),
        (None, false) => (320, 240),
    };
    s
}

/// One discovery run: Algorithm 1 over `handles` from the world's current pose, and its
/// summary with the estimated parts matched to `truth`.
///
/// # Errors
/// Discovery contract violations and invalid estimated models.
pub fn discovery_run(
    world: &mut SimWorld,
    base: &BaseMap,
    handles: &[MappedHandle],
    estimator: EstimatorChoice,
    settings: &DiscoverySettings,
    truth: &[PartAxis],
) -> Result<(Discovery, DiscoveryRun), PipelineError> {
    let c0 = world.clock();
    let est = estimator.estimator();
    let d = discover(world, base, handles, est.as_ref(), settings)?;
    let c1 = world.clock();
    let est_parts = matching::part_axes(&d.model)?;
    let mut matches = matching::match_parts(truth, &est_parts);
    matching::estimator_errors(&mut matches, truth, &d);
    let row = DiscoveryRun {
        estimator: estimator.name().to_string(),
        handles: experiments::handle_rows(truth, handles, &d),
        registered: d.model.parts().len(),
        matches,
        base_time: c1.base - c0.base,
        arm_time: c1.arm - c0.arm,
    };
    Ok((d, row))
}

/// Writes `model` as URDF and reads it back (meshes resolve against `mesh_base`).
pub fn twin(model: &SceneModel, mesh_base: &Path) -> (String, Result<usize, String>) {
    match urdf::write_string(model, &urdf::ExportOptions::default()) {
        Ok(xml) => {
            let options = urdf::ImportOptions {
                base_dir: Some(mesh_base.to_path_buf()),
                ..urdf::ImportOptions::default()
            };
            let back = urdf::read_str(&xml, &options)
                .map(|m| m.nq())
                .map_err(|e| e.to_string());
            (xml, back)
        }
        Err(e) => (String::new(), Err(e.to_string())),
    }
}

/// What the runs share and accumulate.
pub struct Session<'a> {
    /// The configuration.
    pub config: &'a Config,
    /// The true kitchen.
    pub truth: &'a SceneModel,
    /// Its parts' handles and axes.
    pub truth_parts: &'a [PartAxis],
    /// The robot.
    pub robot: &'a RobotModel,
    /// The planner and its budget.
    pub planning: Planning<'a>,
    /// The Fig. 5 sequences.
    pub sequences: Vec<Sequence>,
    /// The Table I parts and targets.
    pub table1: Vec<(String, f64)>,
    /// The Fig. 5 methods, in report order.
    pub methods: Vec<Method>,
    /// True joints the sequences and Table I name.
    pub needed: BTreeSet<String>,
    /// The scene's folder (meshes, goals).
    pub scene_dir: PathBuf,
    /// The mapping viewpoints: x (m), y (m), yaw (rad), in order.
    pub viewpoints: Vec<[f64; 3]>,
    /// Progress output.
    pub ui: Progress,
    /// The report being filled.
    pub report: Report,
    /// The files being collected.
    pub outputs: Outputs,
    /// The Oracle's plans (the true model does not change between runs).
    pub oracle_cache: BTreeMap<String, PlannerResult>,
    /// Wall-clock seconds per phase.
    pub wall: BTreeMap<String, f64>,
}

impl Session<'_> {
    /// Adds the wall-clock time since `t0` to phase `name`.
    pub fn tick(&mut self, name: &str, t0: Instant) {
        *self.wall.entry(name.to_string()).or_insert(0.0) += t0.elapsed().as_secs_f64();
    }

    /// Run `r`: mapping, discovery (both estimators for Table II), Fig. 6, Fig. 5, Table I.
    ///
    /// # Errors
    /// Contract violations of the simulator, the discovery stage or the planner.
    pub fn one_run(&mut self, r: usize) -> Result<(), PipelineError> {
        let config = self.config;
        let truth = self.truth;
        let seed = config.seed.wrapping_add(r as u64);
        self.ui.say(format!("run {r} (seed {seed})"));
        let mut world = SimWorld::new(
            truth,
            self.robot,
            pose(START_BASE),
            sim_settings(config, seed),
        )?;

        // Stage 1: mapping.
        self.ui.doing(format!("run {r}: mapping"));
        let t0 = Instant::now();
        let (mut handles, mapping) =
            stages::map(&mut world, truth.base(), &self.viewpoints, self.truth_parts)?;
        stages::selection_order(&mut handles, START_BASE);
        if config.explore == ExploreScope::Needed {
            let (parts, needed) = (self.truth_parts, &self.needed);
            handles.retain(|h| {
                nearest_part(parts, &h.position, MATCH_RADIUS)
                    .is_some_and(|i| needed.contains(&parts[i].joint))
            });
        }
        self.tick("mapping", t0);
        self.ui.say(format!(
            "  mapping: {} detections, {} handles registered ({} of {} true handles), {} to explore",
            mapping.detections,
            mapping.registered,
            mapping.true_mapped.len(),
            self.truth_parts.len(),
            handles.len()
        ));
        self.ui.done();

        // Stage 2: discovery.
        let (discovery, main) = self.discover(r, &mut world, &handles, config.estimator)?;
        let est = discovery.model.clone();
        for c in &discovery.reconciliation.unresolved {
            self.report.notes.push(format!(
                "run {r}: in the estimated model {} and {} still collide where the robot saw \
                 none ({}) even with the boxes cut back",
                c.a,
                c.b,
                if c.observation == 0 {
                    "the closed scene".to_string()
                } else {
                    format!("opening number {}", c.observation)
                }
            ));
        }
        let matches = main.matches.clone();
        if r == 0 {
            let (xml, back) = twin(&est, &self.scene_dir);
            self.report.twin = Some(TwinSummary {
                run: r,
                joints: est.nq(),
                loaded_back: back,
            });
            if !xml.is_empty() {
                self.outputs.add("twin.urdf", xml);
            }
        }
        if config.runs_experiment(Experiment::Fig6) {
            let considered: Vec<&PartAxis> = self
                .truth_parts
                .iter()
                .filter(|t| config.explore == ExploreScope::All || self.needed.contains(&t.joint))
                .collect();
            self.report.fig6.push(experiments::fig6_row(
                r,
                &considered,
                self.truth_parts,
                &handles,
                &discovery,
                &matches,
            ));
        }
        let mut discoveries = vec![(discovery, main)];
        if config.runs_experiment(Experiment::Table2) {
            // The other estimator on the same handles, in a fresh world with the same seed.
            let mut second = SimWorld::new(
                truth,
                self.robot,
                pose(START_BASE),
                sim_settings(config, seed),
            )?;
            let other = self.discover(r, &mut second, &handles, config.estimator.other())?;
            discoveries.push(other);
            for (d, row) in &discoveries {
                self.report.type_checks.extend(experiments::type_checks(
                    r,
                    &row.estimator,
                    self.truth_parts,
                    &handles,
                    d,
                ));
                self.report
                    .table2
                    .extend(row.matches.iter().map(|m| Table2Row {
                        run: r,
                        estimator: row.estimator.clone(),
                        m: m.clone(),
                    }));
            }
        }

        // Stage 3: scene-level manipulation (Fig. 5), then Table I.
        for k in 0..self.sequences.len() {
            let q = self.sequences[k].clone();
            let goal = TrueGoal {
                goal: q.goal.iter().map(|(j, v)| (j.to_string(), *v)).collect(),
                start: q.start.iter().map(|(j, v)| (j.to_string(), *v)).collect(),
                base: START_BASE,
            };
            let translated = translate(self.truth, &est, &matches, &goal);
            let random_seed = seed.wrapping_mul(16).wrapping_add(k as u64);
            fig5::attempts(self, &mut world, r, &q, &goal, &translated, random_seed)?;
        }
        self.table1(r, &mut world, &handles, &est, &matches)?;
        self.report.runs.push(RunReport {
            run: r,
            seed,
            mapping,
            discovery: discoveries.into_iter().map(|(_, row)| row).collect(),
        });
        Ok(())
    }

    /// Stage 2 with `estimator`, with progress and the log file.
    fn discover(
        &mut self,
        r: usize,
        world: &mut SimWorld,
        handles: &[MappedHandle],
        estimator: EstimatorChoice,
    ) -> Result<(Discovery, DiscoveryRun), PipelineError> {
        self.ui.doing(format!(
            "run {r}: discovery of {} handles ({})",
            handles.len(),
            estimator.name()
        ));
        let t0 = Instant::now();
        let (d, row) = discovery_run(
            world,
            self.truth.base(),
            handles,
            estimator,
            &self.config.discovery,
            self.truth_parts,
        )?;
        self.tick("discovery", t0);
        self.ui.say(format!(
            "  discovery ({}): {} parts registered, {} matched to true parts",
            row.estimator,
            row.registered,
            row.matches.len()
        ));
        self.ui.done();
        if let Ok(json) = serde_json::to_string_pretty(&d.log) {
            self.outputs
                .add(format!("discovery/run{r}-{}.json", row.estimator), json);
        }
        Ok((d, row))
    }

    /// Table I on every selected part.
    fn table1(
        &mut self,
        r: usize,
        world: &mut SimWorld,
        handles: &[MappedHandle],
        est: &SceneModel,
        matches: &[Match],
    ) -> Result<(), PipelineError> {
        if self.table1.is_empty() {
            return Ok(());
        }
        let estimator = self.config.estimator.estimator();
        for k in 0..self.table1.len() {
            let (joint, target) = self.table1[k].clone();
            self.ui.doing(format!("run {r}: table1 {joint}"));
            let t0 = Instant::now();
            let ctx = experiments::Table1Context {
                planning: &self.planning,
                base: self.truth.base(),
                estimator: estimator.as_ref(),
                settings: &self.config.discovery,
                truth: self.truth_parts,
                handles,
                estimated: (est, matches),
            };
            let (rows, attempts) = experiments::table1_part(&ctx, world, r, &joint, target)?;
            self.tick("table1", t0);
            for (method, a) in &attempts {
                self.outputs.add_attempt(
                    &format!("run{r}-table1-{joint}-{}", method.to_lowercase()),
                    a,
                );
            }
            for row in &rows {
                self.ui.say(format!(
                    "  table1 {joint} / {}: reached {}, base {} s, arm {} s",
                    row.method,
                    row.reached.map_or("–".into(), |v| format!("{v:.3}")),
                    row.base_time.map_or("–".into(), |v| format!("{v:.1}")),
                    row.arm_time.map_or("–".into(), |v| format!("{v:.1}")),
                ));
                self.ui.done();
            }
            self.report.table1.extend(rows);
        }
        Ok(())
    }
}
