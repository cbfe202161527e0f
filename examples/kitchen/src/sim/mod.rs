//! The simulated kitchen world: rapier3d physics of the parts and the robot, implementing the
//! discovery stage's `Perception` and `Hardware` traits and executing motion plans.
//!
//! - [`physics`]: the rapier world (parts on exact multibody joints with friction and damping,
//!   real part–part and part–kitchen contacts, the robot's links as kinematic bodies, the
//!   compliant grasp spring);
//! - [`robot`]: the robot's configuration, IK, collision checks and arm timing;
//! - [`navigation`]: the base's own A* navigation on the true scene's grid;
//! - [`hardware`]: the `Hardware` actions (navigation, grasp, compliant pull steps, retract);
//! - [`execute`]: execution of a planner's `StepMotion`s with the part dragged under physics;
//! - [`sensors`]: depth cameras and the handle detector (ray casting on [`SimWorld::placed`]).
//!
//! Everything random (sensor noise, faults) comes from one ChaCha8 generator seeded with
//! [`SimSettings::seed`], and every duration is simulated time, so the same seed and the same
//! calls give the same results.

mod execute;
mod hardware;
mod navigation;
mod physics;
mod robot;
pub mod sensors;

use kinscene::discovery::{
    Camera, HandleDetection, Hardware, HardwareFailure, LocalGoal, Perception, PointCloud,
    SensorFailure,
};
use kinscene::kinematics::robot::RobotModel;
use kinscene::planner::{MotionPlan, StepMotion};
use kinscene::scene::collision::Body;
use kinscene::scene::{
    PartId, SceneData, SceneModel, State, forward_kinematics, world_from_handle,
};
use nalgebra::{Isometry2, Isometry3, Point3, Unit, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use sensors::{CameraSettings, DetectorSettings, Placed, TrueHandle};

/// Injectable faults, each drawn from the world's seeded generator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Faults {
    /// Probability that a grasp slips off the handle: per grasp, and per pull step or per
    /// second of manipulation.
    pub grasp_slip: f64,
    /// Probability per pull step that the arm reports a joint limit early.
    pub joint_limit: f64,
    /// Probability per local navigation that the tracker loses the target.
    pub tracker_loss: f64,
    /// Standard deviation (m) of the base's final position error after local navigation
    /// (drift), per axis.
    pub nav_drift: f64,
}

/// The soft fingers' compliance under a pull: each pull step leaves the tool off the point it
/// grasped on the handle by a Gaussian deflection (independent per step), and its approach
/// axis tilted off the one it grasped with, while the roll about the approach axis is the
/// arm's to choose (the fingers hold a handle, not an orientation). Drawn from a generator of its own (stream 1 of the
/// world's seed), so that the other draws do not depend on it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GraspCompliance {
    /// Standard deviation (m) of the tool's offset from the grasp point, per axis.
    pub deflection: f64,
    /// Standard deviation (rad) of the approach axis's tilt, per perpendicular axis.
    pub tilt: f64,
}

impl Default for GraspCompliance {
    /// 1 mm and 1° from one pull step to the next. Soft printed fingers (the paper's Robotiq
    /// F-140 with 3D-printed soft fingers) give by several millimetres under a pull, but a
    /// steady admittance pull bends them by about the same amount at every step, and a
    /// constant offset is only another grasp point on the same rigid part; what the
    /// estimators see is the step-to-step variation drawn here.
    fn default() -> Self {
        GraspCompliance {
            deflection: 0.001,
            tilt: 1f64.to_radians(),
        }
    }
}

impl GraspCompliance {
    /// None: the tool stays on the grasp point with the grasp's approach axis.
    pub fn none() -> GraspCompliance {
        GraspCompliance {
            deflection: 0.0,
            tilt: 0.0,
        }
    }

    /// Checks that both deviations are finite and non-negative.
    ///
    /// # Errors
    /// [`SimError::Setup`] naming the bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        for (name, v) in [("deflection", self.deflection), ("tilt", self.tilt)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SimError::Setup(format!(
                    "grasp compliance {name} = {v} must be finite and >= 0"
                )));
            }
        }
        Ok(())
    }
}

/// Drift (m, standard deviation per axis) of local navigation at fault rate 1.
const FULL_DRIFT: f64 = 0.05;

impl Faults {
    /// No faults at all.
    pub fn none() -> Faults {
        Faults {
            grasp_slip: 0.0,
            joint_limit: 0.0,
            tracker_loss: 0.0,
            nav_drift: 0.0,
        }
    }

    /// Every fault probability `p` (clamped into [0, 1]; NaN counts as 0) and a local
    /// navigation drift of `0.05 · p` m per axis.
    pub fn with_rate(p: f64) -> Faults {
        let p = if p.is_nan() { 0.0 } else { p.clamp(0.0, 1.0) };
        Faults {
            grasp_slip: p,
            joint_limit: p,
            tracker_loss: p,
            nav_drift: FULL_DRIFT * p,
        }
    }

    /// Checks that the probabilities are in [0, 1] and the drift is finite and non-negative.
    ///
    /// # Errors
    /// [`SimError::Setup`] naming the first bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        for (name, p) in [
            ("grasp_slip", self.grasp_slip),
            ("joint_limit", self.joint_limit),
            ("tracker_loss", self.tracker_loss),
        ] {
            if !(0.0..=1.0).contains(&p) {
                return Err(SimError::Setup(format!(
                    "fault probability {name} = {p} is outside [0, 1]"
                )));
            }
        }
        if !(self.nav_drift.is_finite() && self.nav_drift >= 0.0) {
            return Err(SimError::Setup(format!(
                "nav_drift = {} must be finite and >= 0",
                self.nav_drift
            )));
        }
        Ok(())
    }
}

impl Default for Faults {
    /// No faults.
    fn default() -> Self {
        Faults::none()
    }
}

/// Knobs of the simulated world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimSettings {
    /// Seed of every random draw (noise, faults).
    pub seed: u64,
    /// Depth cameras.
    pub camera: CameraSettings,
    /// Handle detector.
    pub detector: DetectorSettings,
    /// Fault injection.
    pub faults: Faults,
    /// The gripper's compliance while pulling.
    pub grasp: GraspCompliance,
}

impl Default for SimSettings {
    /// Seed 0, the sensors' realistic defaults (depth σ 5 mm, 2 % dropout; detector 1 cm,
    /// 10 % misses, 0.2 false positives per call), the grasp's (1 mm, 1°), no faults.
    fn default() -> Self {
        SimSettings {
            seed: 0,
            camera: CameraSettings::default(),
            detector: DetectorSettings::default(),
            faults: Faults::none(),
            grasp: GraspCompliance::default(),
        }
    }
}

/// Why an executed step failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum FailureCategory {
    /// The moving part hit another part (or the static kitchen) in the simulator.
    PartCollision,
    /// The robot's base path was blocked by a part (or the base could not follow it).
    PathBlocked,
    /// The gripper missed the handle or slipped off it.
    GraspLost,
    /// Anything else (arm collision, planner failure, timeout).
    Other,
}

/// One failure of execution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExecFailure {
    /// The category (the paper's Fig. 5 failure classes).
    pub category: FailureCategory,
    /// What happened, in one line.
    pub reason: String,
}

impl ExecFailure {
    fn new(category: FailureCategory, reason: impl Into<String>) -> ExecFailure {
        ExecFailure {
            category,
            reason: reason.into(),
        }
    }
}

/// Simulated execution time accumulated so far (s), per kind of motion (paper Table I).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Clock {
    /// Driving the base (global and local navigation, repositioning, plan base paths).
    pub base: f64,
    /// Moving the arm (grasping, pulling, retracting, plan arm paths).
    pub arm: f64,
}

/// The result of executing one planned step in the simulator.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepExecution {
    /// The joint the plan moved (the planning model's name).
    pub joint: String,
    /// Simulated time of the base path (s).
    pub base_time: f64,
    /// Simulated time of the approach, manipulation and retreat (s).
    pub arm_time: f64,
    /// `None` when the step was executed as planned.
    pub failure: Option<ExecFailure>,
}

/// The result of executing a motion plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Execution {
    /// The executed steps, in order; execution stops after the first failed one.
    pub steps: Vec<StepExecution>,
    /// The first failure, if any.
    pub failure: Option<ExecFailure>,
}

/// A contract violation or bad input of the simulator (not an execution outcome).
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// Building the physics world or a robot computation failed.
    #[error("simulator: {0}")]
    Setup(String),
}

/// Time (s) one camera frame or detector call takes (30 Hz); counted in [`Hardware::time`],
/// not in the motion [`Clock`].
const FRAME_TIME: f64 = 1.0 / 30.0;

/// The simulated kitchen: ground truth, physics, the robot and its sensors.
///
/// The true joint values live in the physics bodies ([`SimWorld::true_state`]); the robot is a
/// kinematic mechanism driven by [`Hardware`] calls and [`SimWorld::execute_step`]. A closed
/// gripper holds a part through a spring (1.5 kN/m per axis, rotation free): pulling moves
/// the part along its true joint only as far as the spring drags it, and the grasp slips when
/// the spring stretches beyond 4.5 cm.
pub struct SimWorld {
    truth: SceneModel,
    settings: SimSettings,
    physics: physics::Physics,
    robot: robot::Robot,
    clock: Clock,
    /// Time spent taking camera frames and detections (s).
    sensing: f64,
    trace: Vec<Isometry2<f64>>,
    rng: ChaCha8Rng,
    /// The grasp compliance's own generator.
    compliance_rng: ChaCha8Rng,
    watch: Option<Watch>,
}

/// A joint watched for the paper's Table I threshold: when its true value first differs from
/// `from` by `threshold`, the clock then is recorded (see [`SimWorld::watch`]).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Watch {
    part: usize,
    from: f64,
    threshold: f64,
    reached: Option<Clock>,
}

impl SimWorld {
    /// A world with the parts of `truth` at its zero state and the robot at `start`, arm stowed.
    ///
    /// # Errors
    /// [`SimError::Setup`] for invalid settings, a non-finite start pose, or a shape the
    /// physics cannot build.
    pub fn new(
        truth: &SceneModel,
        robot: &RobotModel,
        start: Isometry2<f64>,
        settings: SimSettings,
    ) -> Result<SimWorld, SimError> {
        settings.faults.validate()?;
        settings.grasp.validate()?;
        settings
            .camera
            .validate()
            .map_err(|e| SimError::Setup(e.to_string()))?;
        settings
            .detector
            .validate()
            .map_err(|e| SimError::Setup(e.to_string()))?;
        let base = robot::base_of(&start);
        if !base.iter().all(|v| v.is_finite()) {
            return Err(SimError::Setup(format!(
                "start pose {base:?} is not finite"
            )));
        }
        let links: Vec<_> = robot.links().iter().map(|l| l.colliders.clone()).collect();
        let physics = physics::Physics::new(truth, &links)?;
        let robot = robot::Robot::new(robot, base)?;
        let mut world = SimWorld {
            truth: truth.clone(),
            rng: ChaCha8Rng::seed_from_u64(settings.seed),
            compliance_rng: {
                let mut r = ChaCha8Rng::seed_from_u64(settings.seed);
                r.set_stream(1);
                r
            },
            settings,
            physics,
            robot,
            clock: Clock::default(),
            watch: None,
            sensing: 0.0,
            trace: vec![start],
        };
        world.sync_robot()?;
        Ok(world)
    }

    /// The ground-truth model.
    pub fn truth(&self) -> &SceneModel {
        &self.truth
    }

    /// The true joint values, read from the physics bodies (the multibody coordinates,
    /// clamped into the limits: a joint limit in the physics is soft by a fraction of a
    /// millimetre).
    pub fn true_state(&self) -> State {
        let mut state = self.truth.zero_state();
        for (part, q) in self.truth.parts().iter().zip(self.physics.values()) {
            // A NaN (a body the physics quarantined) leaves the zero value.
            let _ = state.set_clamped(&self.truth, part.joint(), q);
        }
        state
    }

    /// Teleports the parts to `state` (at rest) and the robot to `base` (arm stowed, gripper
    /// open), for the next run of an experiment. The clock and the fault generator carry on.
    ///
    /// # Errors
    /// [`SimError::Setup`] if `state` does not fit the true model or `base` is not finite.
    pub fn reset(&mut self, state: &State, base: Isometry2<f64>) -> Result<(), SimError> {
        state
            .validate(&self.truth)
            .map_err(|e| SimError::Setup(format!("reset state: {e}")))?;
        let b = robot::base_of(&base);
        if !b.iter().all(|v| v.is_finite()) {
            return Err(SimError::Setup(format!("reset pose {b:?} is not finite")));
        }
        self.physics.detach();
        self.physics.set_values(state.as_slice());
        // A watch starts over from the reset state.
        if let Some(w) = self.watch.as_mut() {
            w.from = state.as_slice()[w.part];
            w.reached = None;
        }
        self.robot.base = b;
        self.robot.arm = self.robot.stow.clone();
        self.sync_robot()?;
        self.trace = vec![base];
        Ok(())
    }

    /// The largest distance (m) between where the physics engine holds a part collider and
    /// where its body puts it (0 when the colliders follow their bodies; tests).
    #[cfg(test)]
    pub fn collider_lag(&self) -> f64 {
        self.physics.collider_lag()
    }

    /// Simulated execution time so far.
    pub fn clock(&self) -> Clock {
        self.clock
    }

    /// Watches `joint` (a true joint): the simulated clock at the physics step where its true
    /// value first differs from its value now by at least `threshold` (rad or m) is kept for
    /// [`threshold_reached`](Self::threshold_reached) (the paper's Table I times the actions
    /// up to 30° / 5 cm). Pulls (exploration) and planned manipulations are watched, at the
    /// physics step (1/120 s); replaces an earlier watch, and a [`reset`](Self::reset) starts
    /// it over from the reset state.
    ///
    /// # Errors
    /// [`SimError::Setup`] for an unknown joint or a threshold that is not finite and positive.
    pub fn watch(&mut self, joint: &str, threshold: f64) -> Result<(), SimError> {
        let id = self
            .truth
            .joint_id(joint)
            .map_err(|e| SimError::Setup(format!("watch: {e}")))?;
        if !(threshold.is_finite() && threshold > 0.0) {
            return Err(SimError::Setup(format!(
                "watch threshold {threshold} is not finite and positive"
            )));
        }
        let from = self.physics.value(id.index());
        self.watch = Some(Watch {
            part: id.index(),
            from,
            threshold,
            reached: None,
        });
        Ok(())
    }

    /// The clock when the watched joint reached its threshold, if it did.
    pub fn threshold_reached(&self) -> Option<Clock> {
        self.watch.and_then(|w| w.reached)
    }

    /// Records the watched joint's threshold crossing at the clock plus `extra` (the time of
    /// the current action not yet added to the clock).
    fn check_watch(&mut self, extra: Clock) {
        let Some(w) = self.watch.as_mut() else {
            return;
        };
        if w.reached.is_some() {
            return;
        }
        let v = self.physics.value(w.part);
        if (v - w.from).abs() >= w.threshold {
            w.reached = Some(Clock {
                base: self.clock.base + extra.base,
                arm: self.clock.arm + extra.arm,
            });
        }
    }

    /// The base poses the robot drove through since the last `reset` (for the top view).
    pub fn base_trace(&self) -> &[Isometry2<f64>] {
        &self.trace
    }

    /// Every collider in the world now (kitchen, parts, robot).
    pub fn placed(&self) -> Vec<Placed> {
        self.physics.placed()
    }

    /// Executes one planned step: drives the base along its path, the arm along approach,
    /// closes the gripper on the handle under the tool (if any), follows the manipulation
    /// trajectory with the part moving under physics, releases and retreats. A whole-body
    /// manipulation ([`StepMotion::manipulation_base`]) moves the base along its timed poses
    /// with the arm; the retreat then runs at the last of them ([`StepMotion::end_base`]).
    ///
    /// The handle is whichever true handle is within 3.5 cm of the tool at the end of the
    /// approach (the plan's joint and handle names may be an estimated model's). Failures:
    /// the chassis or stowed arm touching a part or the kitchen on the base path is
    /// [`FailureCategory::PathBlocked`]; no handle under the tool, a grasp spring stretched
    /// beyond 4.5 cm (the part does not follow the planned handle trajectory) or a slip fault
    /// is [`FailureCategory::GraspLost`]; the moving part (or a part it carries) pressing on
    /// another part or the kitchen is [`FailureCategory::PartCollision`]; the arm touching
    /// the scene or itself, or a malformed step, is [`FailureCategory::Other`].
    pub fn execute_step(&mut self, step: &StepMotion) -> StepExecution {
        self.run_step(step)
    }

    /// Executes every step of `plan` in order, stopping at the first failure.
    pub fn execute(&mut self, plan: &MotionPlan) -> Execution {
        let mut steps = Vec::with_capacity(plan.steps.len());
        let mut failure = None;
        for step in &plan.steps {
            let done = self.execute_step(step);
            failure = done.failure.clone();
            steps.push(done);
            if failure.is_some() {
                break;
            }
        }
        Execution { steps, failure }
    }

    /// Places the robot's link bodies at the current configuration.
    fn sync_robot(&mut self) -> Result<(), SimError> {
        let poses = self.robot.link_poses()?;
        self.physics.place_links(&poses);
        Ok(())
    }

    /// The true state and its forward kinematics.
    fn true_data(&self) -> (State, SceneData) {
        let state = self.true_state();
        let mut data = SceneData::new(&self.truth);
        // The state has the model's length and finite values by construction.
        let _ = forward_kinematics(&self.truth, &mut data, &state);
        (state, data)
    }

    /// Every true handle now: (part index, position, outward normal).
    fn true_handles(&self) -> Vec<(usize, TrueHandle)> {
        let (_, data) = self.true_data();
        self.truth
            .handles()
            .filter_map(|(id, _)| {
                let h = world_from_handle(&self.truth, &data, id).ok()?;
                Some((
                    id.part().index(),
                    TrueHandle {
                        position: h.position,
                        normal: h.normal.into_inner(),
                    },
                ))
            })
            .collect()
    }

    /// The true handle nearest to `point`: (part index, handle, distance).
    fn nearest_handle(&self, point: &Point3<f64>) -> Option<(usize, TrueHandle, f64)> {
        self.true_handles()
            .into_iter()
            .map(|(k, h)| (k, h, (h.position - point).norm()))
            .min_by(|a, b| a.2.total_cmp(&b.2))
    }

    /// Part `k` and its descendants (indices).
    fn subtree(&self, k: usize) -> Vec<usize> {
        self.truth
            .parts()
            .get(k)
            .map(|p| p.subtree().map(PartId::index).collect())
            .unwrap_or_default()
    }

    /// Part ids of part `k`'s subtree.
    fn subtree_ids(&self, k: usize) -> Vec<PartId> {
        self.truth
            .parts()
            .get(k)
            .map(|p| p.subtree().collect())
            .unwrap_or_default()
    }

    /// A readable name of a scene body.
    fn body_name(&self, body: Body) -> String {
        match body {
            Body::Part(p) => self
                .truth
                .parts()
                .get(p.index())
                .map(|p| format!("part {}", p.name()))
                .unwrap_or_else(|| "a part".into()),
            Body::Base(s) => self
                .truth
                .base()
                .shapes
                .get(s.index())
                .map(|s| format!("the kitchen ({})", s.name))
                .unwrap_or_else(|| "the kitchen".into()),
        }
    }

    /// A readable name of a robot link.
    fn link_name(&self, link: usize) -> String {
        self.robot
            .model
            .links()
            .get(link)
            .map(|l| l.name.clone())
            .unwrap_or_else(|| format!("link {link}"))
    }

    /// Steps the physics for `seconds` with the robot still.
    fn settle(&mut self, seconds: f64) {
        let n = (seconds / physics::DT).ceil() as usize;
        for _ in 0..n {
            self.physics.step();
        }
    }

    /// True with probability `p` (no draw when `p <= 0`, so fault-free runs draw nothing).
    fn roll(&mut self, p: f64) -> bool {
        p > 0.0 && self.rng.random::<f64>() < p
    }

    /// A standard normal draw (Box–Muller).
    fn gaussian(&mut self) -> f64 {
        standard_normal(&mut self.rng)
    }
}

impl Perception for SimWorld {
    fn observe(&mut self, camera: Camera) -> Result<PointCloud, SensorFailure> {
        let scene = self.placed();
        let (origin, dirs) = match camera {
            Camera::Head => {
                sensors::head_rays(&self.robot.world_from_base(), &self.settings.camera)
            }
            Camera::Wrist => sensors::wrist_rays(&self.ee_pose(), &self.settings.camera),
        };
        self.sensing += FRAME_TIME;
        let stamp = self.time();
        let cloud = sensors::render(
            &scene,
            &origin,
            &dirs,
            &self.settings.camera,
            stamp,
            &mut self.rng,
        );
        if cloud.points.is_empty() {
            return Err(SensorFailure::NoData {
                reason: format!("no depth returns from the {camera:?} camera"),
            });
        }
        Ok(cloud)
    }

    fn detect_handles(&mut self) -> Result<Vec<HandleDetection>, SensorFailure> {
        let scene = self.placed();
        let handles: Vec<TrueHandle> = self.true_handles().into_iter().map(|(_, h)| h).collect();
        let base = self.robot.world_from_base();
        let (origin, _) = sensors::head_rays(&base, &self.settings.camera);
        self.sensing += FRAME_TIME;
        let stamp = self.time();
        Ok(sensors::detect(
            &scene,
            &handles,
            &origin,
            base.rotation.angle(),
            &self.settings.detector,
            stamp,
            &mut self.rng,
        ))
    }
}

impl Hardware for SimWorld {
    /// A* on the true scene's occupancy grid inflated by the footprint radius (open parts
    /// occupy space); the goal is checked against the robot's exact geometry (stowed arm).
    /// Time: route length at the base's linear speed plus the turn at its yaw rate.
    fn navigate_to(&mut self, world_from_base: &Isometry2<f64>) -> Result<(), HardwareFailure> {
        self.navigate(world_from_base)
    }

    /// As [`Hardware::navigate_to`], with the tracker-loss fault (the robot stays) and a
    /// Gaussian drift of the final position.
    fn navigate_local(&mut self, goal: &LocalGoal) -> Result<(), HardwareFailure> {
        self.navigate_tracked(goal)
    }

    /// IK (with restarts) for the tool at `point`, tool z along `approach`: `Unreachable` if
    /// it fails, `SelfCollision` or `Other` if the arm would touch itself or the scene; then
    /// the gripper closes on the true handle within 3.5 cm of the tool (`GraspLost` if none,
    /// or on a slip fault).
    fn grasp(
        &mut self,
        point: &Point3<f64>,
        approach: &Unit<Vector3<f64>>,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        self.close_on(point, approach)
    }

    /// The admittance step: the gripper moves `step` along `direction` in 0.2 s and holds
    /// 0.1 s while the physics runs (the part follows its true joint as far as the spring
    /// drags it); then the compliant arm follows the grasp point (IK near the current arm:
    /// failure is `JointLimit`, a self-collision `SelfCollision`). A stretch beyond the slip
    /// distance, or a slip fault, is `GraspLost`.
    fn pull_step(
        &mut self,
        direction: &Unit<Vector3<f64>>,
        step: f64,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        self.pull(direction, step)
    }

    fn retract(&mut self) -> Result<(), HardwareFailure> {
        self.open_and_stow()
    }

    fn ee_pose(&self) -> Isometry3<f64> {
        // Forward kinematics of a finite configuration cannot fail.
        self.robot
            .world_from_tool()
            .unwrap_or_else(|_| Isometry3::identity())
    }

    fn base_pose(&self) -> Isometry2<f64> {
        self.robot.world_from_base()
    }

    fn time(&self) -> f64 {
        self.clock.base + self.clock.arm + self.sensing
    }
}

/// A standard normal draw from `rng` (Box–Muller).
fn standard_normal(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}
