//! Settings of base placement and of the manipulation plan at a base pose.

use std::time::Duration;

use kinscene_casadi::NlpSettings;
use nalgebra::DVector;

use super::PlacementError;
use super::grasp::GraspRotation;
use crate::InvalidSetting;

/// How the base pose is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PlacementMethod {
    /// The paper's method: sample base poses around the part and keep the one from which the
    /// most waypoints are reached ([`SamplingSettings`]).
    #[default]
    Sampled,
    /// Sample first, then optimise the base pose and all arm configurations together as one
    /// CasADi/IPOPT problem initialised from the best sample ([`OptimisationSettings`]); the
    /// optimum is accepted only if an independent check reaches every waypoint, otherwise the
    /// sampled result is returned.
    Optimised,
}

/// Which base pose the sampler keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PlacementObjective {
    /// The paper's: the most waypoints reached, wherever they are along the motion.
    #[default]
    MostReached,
    /// The longest run of reached waypoints from the first (the pre-grasp): how far along the
    /// motion the robot gets from that base pose before it would have to let go. IK along a
    /// candidate stops at its first waypoint not reached (the rest count as
    /// [`Skipped`](super::WaypointFailure::Skipped)). The hierarchical planner uses it to
    /// choose where a segmented manipulation regrasps.
    LongestPrefix,
}

/// How samples that reach as many waypoints (by the [`PlacementObjective`]) are ranked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TieBreak {
    /// The lower estimated execution time wins: the base from where the robot stands to the
    /// sample, the arm from its stowed configuration to the first waypoint, along the
    /// waypoints and back, each timed as straight lines under the robot's velocity and
    /// acceleration limits (the slowest joint or base axis deciding). A base turned so that
    /// the arm's first joint has less far to swing, or a grasp closer to the stow, wins over
    /// a shorter arm path that needs a long swing first.
    #[default]
    ExecutionTime,
    /// The lower `path length (rad) + distance_weight · ‖base − robot_from‖ (m)` wins
    /// ([`SamplingSettings::distance_weight`]): the arm's joint-space path along the
    /// waypoints and the base's distance, as the crate ranked before execution times.
    PathLength,
}

/// Settings of the manipulation plan at one base pose (IK along the trajectory and its checks).
#[derive(Debug, Clone, PartialEq)]
pub struct ManipulationSettings {
    /// Largest change of any arm joint between consecutive waypoints (rad or m), > 0. A larger
    /// jump makes the later waypoint count as not reached unless the tool tracks the handle
    /// path along it ([`ManipulationSettings::tracking_tolerance`]). Default 0.35.
    pub max_joint_jump: f64,
    /// A larger joint change than `max_joint_jump` between consecutive waypoints is accepted
    /// when, with the arm interpolated linearly between them, the tool stays within this
    /// distance (m) of the straight line between the two grasp points and its approach axis
    /// within [`ManipulationSettings::tracking_angle`] of the interpolated approach, at 7
    /// points along the segment: a fast but continuous motion (a wrist swinging near a
    /// singularity), not a jump to another IK branch, which leaves the handle. > 0, default
    /// 0.01.
    pub tracking_tolerance: f64,
    /// The angle bound (rad) of that test, > 0, default 0.1.
    pub tracking_angle: f64,
    /// Spacing of the collision checks between consecutive waypoints: the straight joint-space
    /// segment (and the part's value, linearly) is checked at steps of at most this much in
    /// every joint (rad or m), > 0. Default 0.05.
    pub segment_resolution: f64,
    /// Clearance (m) the robot must keep from the scene, >= 0. Default 0.005.
    pub margin: f64,
    /// Clearance (m) the robot's checked link pairs must keep from each other at every
    /// waypoint and along the segments between them, >= 0; at most half the least clearance
    /// the arm's resting configuration has (the stow, else the seed), so that a robot whose
    /// links sit close together at rest keeps what it can. A real arm tracks its
    /// configurations with some error; with no clearance a planned posture may press one link
    /// against another. Default 0.005.
    pub self_margin: f64,
    /// Largest distance (m) of the tool origin from the grasp point for a waypoint to count as
    /// reached, > 0. Default 1e-5 (the IK's default tolerance).
    pub position_tolerance: f64,
    /// Largest angle (rad) between the tool's +z axis and the approach direction (and, for
    /// [`GraspRotation::Fixed`], of the full rotation error), > 0. Default 1e-4.
    pub rotation_tolerance: f64,
    /// Seeds tried for a full IK solve (at the first waypoint and after a missed one) whose
    /// solution fails a check: the seed with the last arm joint turned by `2π·i/roll_attempts`
    /// (another gripper roll, e.g. fingers clear of a neighbouring door), >= 1. Default 4.
    pub roll_attempts: usize,
    /// Gap (m) the fingertips keep from the grasped part's front, >= 0. The tool goes to the
    /// handle's grasp point unless the gripper's contact shapes reach farther past the tool
    /// origin than the handle stands off the front
    /// ([`handle_standoff`](crate::scene::collision::handle_standoff)) less this gap; then it
    /// stops that much short, out along the normal. Default 0.005.
    pub finger_clearance: f64,
    /// Approach tolerance (rad, in `[0, π/2]`): with [`GraspRotation::Free`], the tool's +z
    /// axis may lie anywhere within this angle of the approach direction (−normal), not only
    /// along it (IK target [`IkTarget::PositionCone`](crate::kinematics::ik::IkTarget)); the
    /// rotation and tracking checks allow the same tilt. Default 0 (exactly perpendicular to
    /// the handle's face). Ignored by [`GraspRotation::Fixed`].
    pub approach_cone: f64,
}

impl Default for ManipulationSettings {
    fn default() -> Self {
        ManipulationSettings {
            max_joint_jump: 0.35,
            tracking_tolerance: 0.01,
            tracking_angle: 0.1,
            segment_resolution: 0.05,
            margin: 0.005,
            self_margin: 0.005,
            position_tolerance: 1e-5,
            rotation_tolerance: 1e-4,
            roll_attempts: 4,
            finger_clearance: 0.005,
            approach_cone: 0.0,
        }
    }
}

/// Settings of the sampled base placement (the paper's method).
///
/// Base positions are drawn in an annular sector centred on the handle trajectory's
/// horizontal centroid `c`: distance `r ∈ distance` from `c` (uniform over the area), bearing
/// within `±bearing_spread` of the *front direction* (the mean of the waypoints' outward
/// normals, projected on the floor; if that is shorter than 0.1, the direction from `c` to the
/// robot's current position). The default spread, π, is the whole annulus "around the part":
/// beside a door's sweep is often the only place the base fits. The yaw faces `c` (base +x
/// towards it) plus a uniform jitter in `±yaw_jitter`. Poses outside the scene's navigation
/// grid ([`SceneModel::base_grid`](crate::scene::SceneModel::base_grid)), where no base path
/// can end, or whose base links touch the scene are drawn again, up to `max_draws` draws in
/// all. Draws are reproducible from `seed`.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplingSettings {
    /// Number of collision-free base poses to evaluate (IK along the trajectory), >= 1.
    /// Default 30.
    pub samples: usize,
    /// Largest number of base poses drawn (colliding ones included), >= `samples`.
    /// Default 600.
    pub max_draws: usize,
    /// Wall-clock budget of the sampling: no new base pose is evaluated once it is spent (the
    /// best so far is kept), > 0. Default 20 s. (A sample whose waypoints cannot be reached
    /// costs up to `K + 1` full IK solves, each bounded by the IK solver's own budget.)
    pub budget: Duration,
    /// Seed of the sampler (ChaCha8).
    pub seed: u64,
    /// Radial range `[min, max]` (m) of the base centre from the trajectory centroid, or `None`
    /// for the robot's default: `[footprint_radius + 0.05, footprint_radius + 0.05 + 0.6 ·
    /// arm reach]` where the arm reach is the length bound of
    /// [`arm_reach`](super::arm_reach).
    pub distance: Option<[f64; 2]>,
    /// Half-angle (rad) of the sector around the front direction, in `[0, π]`. Default π.
    pub bearing_spread: f64,
    /// Half-width (rad) of the uniform yaw jitter, in `[0, π]`. Default 0.6.
    pub yaw_jitter: f64,
    /// Clearance (m) the base links (and the stowed arm) must keep from the scene at the
    /// current state for a sample to be evaluated at all, >= 0. Default 0.02.
    pub base_margin: f64,
    /// How samples that reach as many waypoints are ranked. Default
    /// [`TieBreak::ExecutionTime`].
    pub tie_break: TieBreak,
    /// The base distance's weight in [`TieBreak::PathLength`]: the lower
    /// `path length (rad) + distance_weight · ‖base − robot_from‖ (m)` wins, >= 0. Default 0.5.
    pub distance_weight: f64,
    /// Evaluate the robot's current base pose (`robot_from`, its yaw included) before the
    /// drawn ones, as one more candidate under the same rules (it does not count towards
    /// `samples`). Where the arm can do the whole motion from where the robot stands, and no
    /// drawn pose is better by the tie-break, the base does not move. Default true.
    pub current_pose: bool,
    /// What makes one sample better than another before the tie-break: the most waypoints
    /// reached (the paper's, default) or the longest reached prefix.
    pub objective: PlacementObjective,
    /// How many of the best evaluated base poses' plans the outcome keeps
    /// ([`PlacementOutcome::ranked`](super::PlacementOutcome::ranked)), best first by the
    /// objective and the tie-break: the alternatives a whole-body plan may start from (with
    /// [`PlacementObjective::MostReached`] a plan that cannot beat the best is evaluated only
    /// until that shows, so the others rank by a lower bound). >= 1. Default 1.
    pub keep: usize,
}

impl Default for SamplingSettings {
    fn default() -> Self {
        SamplingSettings {
            samples: 30,
            max_draws: 600,
            budget: Duration::from_secs(20),
            seed: 0x6b69_6e73,
            distance: None,
            bearing_spread: std::f64::consts::PI,
            yaw_jitter: 0.6,
            base_margin: 0.02,
            tie_break: TieBreak::ExecutionTime,
            distance_weight: 0.5,
            current_pose: true,
            objective: PlacementObjective::MostReached,
            keep: 1,
        }
    }
}

/// Settings of the optimised base placement (CasADi/IPOPT). The problem is described in the
/// [module docs](super#the-placement-nlp).
#[derive(Debug, Clone, PartialEq)]
pub struct OptimisationSettings {
    /// IPOPT's settings. Default: `constraint_tolerance` 1e-8 (the waypoint equalities), a
    /// wall-time limit of 5 s, otherwise [`NlpSettings::default`].
    pub nlp: NlpSettings,
    /// How far the base may move from the best sample: `[metres, radians]`, both > 0.
    /// Default `[0.3, 0.6]`.
    pub trust_region: [f64; 2],
    /// Weights of the pull towards the sampled solution (`Σ‖q − q_sample‖² + ‖b − b_sample‖²`)
    /// relative to the smoothness term `Σ‖q_{k+1} − q_k‖²`, each >= 0 and finite, at least
    /// one: IPOPT is run with each in turn until its result passes the verification. Default
    /// `[1e-3, 1e-1, 10]`.
    pub pull_weights: Vec<f64>,
    /// Clearance (m) of the footprint disc from the obstacle boxes near the handle (the
    /// half-plane constraints), >= 0. Default 0.05.
    pub clearance: f64,
    /// Number of half-plane slots in the NLP (the nearest obstacle boxes are used), >= 1.
    /// Default 16.
    pub max_half_planes: usize,
    /// Obstacle boxes farther than this (m) from the sampled base centre are not turned into
    /// half-planes, > 0. Default 1.5.
    pub obstacle_radius: f64,
}

impl Default for OptimisationSettings {
    fn default() -> Self {
        OptimisationSettings {
            nlp: NlpSettings {
                constraint_tolerance: 1e-8,
                max_wall_time: 5.0,
                ..NlpSettings::default()
            },
            trust_region: [0.3, 0.6],
            pull_weights: vec![1e-3, 1e-1, 10.0],
            clearance: 0.05,
            max_half_planes: 16,
            obstacle_radius: 1.5,
        }
    }
}

/// Everything [`place_and_plan`](super::place_and_plan) needs besides the problem.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacementSettings {
    /// Sampled or optimised.
    pub method: PlacementMethod,
    /// Steps `K` of the handle trajectory (`K + 1` waypoints), in `1..=1000`. Default 10.
    pub steps: usize,
    /// How the rotation about the approach axis is chosen.
    pub grasp: GraspRotation,
    /// IK along the trajectory and its checks.
    pub manipulation: ManipulationSettings,
    /// The sampler (used by both methods).
    pub sampling: SamplingSettings,
    /// The optimiser (used by [`PlacementMethod::Optimised`]).
    pub optimisation: OptimisationSettings,
    /// Length (m) of the straight approach to the first grasp frame and of the straight
    /// retreat from the last, along the handle's normal (a turned grasp's direction, see
    /// `bar_turn`), >= 0 (default 0.05; 0: none). The
    /// base pose is chosen for the whole sequence: pre-grasp, approach, handle trajectory,
    /// retreat, post-grasp ([`JointMotion::with_approach`](super::JointMotion::with_approach)).
    pub approach_distance: f64,
    /// Waypoints of the straight approach and of the retreat each (default 3); 0 with a
    /// positive distance is rejected.
    pub approach_steps: usize,
    /// The arm configuration the robot arrives with and leaves with (its stow). With it, a
    /// base pose is drawn only if the whole robot in this configuration keeps
    /// [`ManipulationSettings::margin`] from the scene at the motion's start and end states,
    /// so the arm can go from the stow to the handle and back there; `None` (default): the
    /// base links alone. The hierarchical planner sets its stow.
    pub stow: Option<DVector<f64>>,
    /// Turned grasps of bar handles: the largest angle (rad, in `[0, π/2]`) by which the
    /// approach may be turned about the handle's bar axis
    /// ([`handle_bar_axis`](crate::scene::collision::handle_bar_axis)) away from the inward
    /// normal: a bar can be grasped from any direction perpendicular to it. Default
    /// [`DEFAULT_BAR_TURN`] (1.2 rad); 0: the grasp along the normal only. With a positive
    /// value and a bar handle, a placement whose
    /// grasp along the normal does not reach every waypoint is tried again with the approach
    /// turned by `±i/n` of this angle, `i = 1..=n` (`n` = `bar_turn_steps`), the smaller turns
    /// first, and the best by the sampler's objective is kept (an earlier one on a tie);
    /// [`JointMotion::grasp_angle`](super::JointMotion::grasp_angle) says which. The fingers
    /// of a turned grasp may touch the handle's own shape but not the part's front
    /// ([`JointMotion::turned_about_bar`](super::JointMotion::turned_about_bar)).
    pub bar_turn: f64,
    /// The turned grasps tried each way (`n` above), >= 1. Default 2.
    pub bar_turn_steps: usize,
}

impl Default for PlacementSettings {
    fn default() -> Self {
        PlacementSettings {
            method: PlacementMethod::default(),
            steps: 10,
            grasp: GraspRotation::default(),
            manipulation: ManipulationSettings::default(),
            sampling: SamplingSettings::default(),
            optimisation: OptimisationSettings::default(),
            approach_distance: 0.05,
            approach_steps: 3,
            stow: None,
            bar_turn: DEFAULT_BAR_TURN,
            bar_turn_steps: 2,
        }
    }
}

/// The default largest turn of a grasp about a bar handle ([`PlacementSettings::bar_turn`],
/// rad): turns of ±0.6 and ±1.2 rad are tried, in that order, only when the grasp along the
/// handle's normal does not cover the motion. Past about 0.8 rad of opening, a door next to
/// another run (a corner cabinet) has its handle facing that run, and a grasp across the bar
/// puts the wrist into it; turned by 1.2 rad (69°) the approach still comes from the handle's
/// side of the front, and the fingers keep the contact rule (they may touch the bar, not the
/// front). Measured with the shipped Gen3 on `examples/scenes/goals/` (`cargo bench --bench
/// plan -- 1` against `bar-turn=0`): `corner_order` is solved only with the turned grasps,
/// and no other goal's plan time changes.
pub const DEFAULT_BAR_TURN: f64 = 1.2;

/// Largest `K` accepted (the NLP has `7 · (K + 1)` arm variables for a 7-DoF arm).
pub const MAX_STEPS: usize = 1000;

fn positive(field: &str, value: f64) -> Result<(), InvalidSetting> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(InvalidSetting::new(field, value, "finite and > 0"))
    }
}

fn non_negative(field: &str, value: f64) -> Result<(), InvalidSetting> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(InvalidSetting::new(field, value, "finite and >= 0"))
    }
}

fn angle(field: &str, value: f64) -> Result<(), InvalidSetting> {
    if (0.0..=std::f64::consts::PI).contains(&value) {
        Ok(())
    } else {
        Err(InvalidSetting::new(field, value, "in [0, pi]"))
    }
}

impl ManipulationSettings {
    /// Checks every field's range.
    ///
    /// # Errors
    /// [`PlacementError::InvalidSetting`] naming the field.
    pub fn validate(&self) -> Result<(), PlacementError> {
        positive("manipulation.max_joint_jump", self.max_joint_jump)?;
        positive("manipulation.tracking_tolerance", self.tracking_tolerance)?;
        positive("manipulation.tracking_angle", self.tracking_angle)?;
        positive("manipulation.segment_resolution", self.segment_resolution)?;
        non_negative("manipulation.margin", self.margin)?;
        non_negative("manipulation.self_margin", self.self_margin)?;
        positive("manipulation.position_tolerance", self.position_tolerance)?;
        positive("manipulation.rotation_tolerance", self.rotation_tolerance)?;
        non_negative("manipulation.finger_clearance", self.finger_clearance)?;
        if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&self.approach_cone) {
            return Err(InvalidSetting::new(
                "manipulation.approach_cone",
                self.approach_cone,
                "in [0, pi/2]",
            )
            .into());
        }
        if self.roll_attempts == 0 {
            return Err(InvalidSetting::new("manipulation.roll_attempts", 0.0, ">= 1").into());
        }
        Ok(())
    }
}

impl SamplingSettings {
    /// Checks every field's range.
    ///
    /// # Errors
    /// [`PlacementError::InvalidSetting`] naming the field.
    pub fn validate(&self) -> Result<(), PlacementError> {
        if self.samples == 0 {
            return Err(InvalidSetting::new("sampling.samples", 0.0, ">= 1").into());
        }
        if self.keep == 0 {
            return Err(InvalidSetting::new("sampling.keep", 0.0, ">= 1").into());
        }
        if self.max_draws < self.samples {
            return Err(InvalidSetting::new(
                "sampling.max_draws",
                self.max_draws as f64,
                ">= sampling.samples",
            )
            .into());
        }
        if self.budget.is_zero() {
            return Err(InvalidSetting::new("sampling.budget", 0.0, "> 0").into());
        }
        if let Some([lo, hi]) = self.distance {
            non_negative("sampling.distance[0]", lo)?;
            positive("sampling.distance[1]", hi)?;
            if lo > hi {
                return Err(InvalidSetting::new(
                    "sampling.distance[0]",
                    lo,
                    "at most sampling.distance[1]",
                )
                .into());
            }
        }
        angle("sampling.bearing_spread", self.bearing_spread)?;
        angle("sampling.yaw_jitter", self.yaw_jitter)?;
        non_negative("sampling.base_margin", self.base_margin)?;
        non_negative("sampling.distance_weight", self.distance_weight)?;
        Ok(())
    }
}

impl OptimisationSettings {
    /// Checks every field's range (and IPOPT's settings).
    ///
    /// # Errors
    /// [`PlacementError::InvalidSetting`] naming the field; [`PlacementError::Casadi`] for
    /// invalid [`NlpSettings`].
    pub fn validate(&self) -> Result<(), PlacementError> {
        self.nlp.validate()?;
        positive("optimisation.trust_region[0]", self.trust_region[0])?;
        positive("optimisation.trust_region[1]", self.trust_region[1])?;
        if self.pull_weights.is_empty() {
            return Err(InvalidSetting::new(
                "optimisation.pull_weights",
                0.0,
                "a list of at least one weight",
            )
            .into());
        }
        for (i, &w) in self.pull_weights.iter().enumerate() {
            non_negative(&format!("optimisation.pull_weights[{i}]"), w)?;
        }
        non_negative("optimisation.clearance", self.clearance)?;
        if self.max_half_planes == 0 {
            return Err(InvalidSetting::new("optimisation.max_half_planes", 0.0, ">= 1").into());
        }
        positive("optimisation.obstacle_radius", self.obstacle_radius)?;
        Ok(())
    }
}

impl PlacementSettings {
    /// Checks every field's range.
    ///
    /// # Errors
    /// [`PlacementError::InvalidSetting`] naming the field; [`PlacementError::Casadi`] for
    /// invalid IPOPT settings.
    pub fn validate(&self) -> Result<(), PlacementError> {
        if self.steps == 0 || self.steps > MAX_STEPS {
            return Err(InvalidSetting::new(
                "steps",
                self.steps as f64,
                format!("between 1 and {MAX_STEPS}"),
            )
            .into());
        }
        non_negative("approach_distance", self.approach_distance)?;
        if self.approach_distance > 0.0 && self.approach_steps == 0 {
            return Err(InvalidSetting::new(
                "approach_steps",
                0.0,
                ">= 1 with a positive approach_distance",
            )
            .into());
        }
        if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&self.bar_turn) {
            return Err(InvalidSetting::new("bar_turn", self.bar_turn, "in [0, pi/2]").into());
        }
        if self.bar_turn_steps == 0 {
            return Err(InvalidSetting::new("bar_turn_steps", 0.0, ">= 1").into());
        }
        self.manipulation.validate()?;
        self.sampling.validate()?;
        self.optimisation.validate()
    }

    /// The grasp angles about a bar handle's axis tried after the grasp along the normal
    /// ([`PlacementSettings::bar_turn`]): `+a, −a` for `a = bar_turn · i / bar_turn_steps`,
    /// `i = 1..=bar_turn_steps`; empty when `bar_turn` is 0.
    pub fn bar_turns(&self) -> Vec<f64> {
        if self.bar_turn <= 0.0 {
            return Vec::new();
        }
        let n = self.bar_turn_steps.max(1);
        (1..=n)
            .flat_map(|i| {
                let a = self.bar_turn * i as f64 / n as f64;
                [a, -a]
            })
            .collect()
    }
}
