//! Settings of the hierarchical planner.

use std::time::Duration;

use nalgebra::DVector;

use super::PlannerError;
use crate::InvalidSetting;
use crate::kinematics::ik::IkSettings;
use crate::kinematics::robot::{RobotModel, SphereSettings};
use crate::motion::paths::{PathSettings, Simplifier};
use crate::motion::placement::{PlacementError, PlacementSettings, WholeBodySettings};
use crate::motion::timing::BlendSettings;
use crate::task::TaskSettings;

/// Settings of [`HierarchicalPlanner`](super::HierarchicalPlanner): one block per layer plus
/// the checks this layer adds.
#[derive(Debug, Clone)]
pub struct PlannerSettings {
    /// The task search (strategy, lattice, costs, manipulation regions).
    pub task: TaskSettings,
    /// Inverse kinematics. The planner's default keeps [`IkSettings::default`] but for 15
    /// restarts and a 1 s budget: the iteration counts (16 attempts of at most 100 steps, about
    /// 50 ms on the Gen3) then end a solve, not the wall clock, so a solve gives the same
    /// answer on a loaded machine; the budget is a safety net.
    pub ik: IkSettings,
    /// Base placement and the manipulation trajectory.
    pub placement: PlacementSettings,
    /// OMPL settings of the base and arm paths (the budget is per path, capped by what is
    /// left of the overall budget). The planner's default seeds OMPL (`seed: Some(1)`) and
    /// ends each path search after [`PLANNER_PATH_ITERATIONS`] iterations
    /// (`max_iterations`): with the IK's iteration limits and the placement's seeded sampling,
    /// the same input then gives the same plan whatever the machine's load, as long as no
    /// search reaches its wall-clock `budget` first (the safety net; on a heavily loaded
    /// machine raise it). Seeded path searches are serialised process-wide (OMPL has one
    /// generator).
    /// The planner's default simplifier is [`Simplifier::Full`] (the shortest, smoothest
    /// paths: its paths are executed, and re-checked densely), not the paths' own default.
    pub paths: PathSettings,
    /// Clearance (m) the robot keeps from the scene along base paths (arm paths keep the
    /// smaller of this and the placement's `manipulation.margin`, since they start or end at
    /// the placement's configurations), > 0
    /// recommended (default 0.02 m: the Gen3's points move at most about 1.6 cm per 0.01 rad
    /// of joint motion, so OMPL's and the re-check's discrete checks keep real clearance). Between
    /// the pre-grasp and the post-grasp configuration, the gripper's contact shapes alone may
    /// touch the grasped part (and its descendants); every other shape keeps the margin from it
    /// too. The free arm paths (to and from the stow) also keep the arm paths' clearance
    /// between the robot's own links, or half the least clearance their two end
    /// configurations have where that is less (a stow with links close together stays
    /// valid).
    pub margin: f64,
    /// Arm configuration for driving and between steps; `None`: [`RobotModel::neutral`].
    pub stow: Option<DVector<f64>>,
    /// Spacing of the independent dense re-check of every arm path and the manipulation
    /// trajectory (rad, largest joint change between checked configurations), default 0.01.
    pub arm_check_resolution: f64,
    /// Time shortcuts of the free arm paths (to and from the stow): OMPL shortens a path in
    /// joint-space length, but the arm's time on a leg is its slowest joint's `|Δq| / v_max`.
    /// Each segment of the checked path is divided into this many parts and, from each point
    /// in turn, the path goes straight to the farthest later point whose straight motion is
    /// quicker and passes the dense re-check (`arm_check_resolution`, the same check). 0: off.
    /// Default 4.
    pub arm_time_shortcuts: usize,
    /// Random time shortcuts of the free arm paths after the greedy ones: this many times,
    /// two points along the path are drawn (seeded by `paths.seed`, reproducible) and the
    /// path between them replaced by the straight motion when that is quicker and passes the
    /// same dense re-check. They cut corners the greedy pass's points miss, so the arm's path
    /// to and from the stow approaches the quickest one around the same obstacles. 0: off.
    /// Default 100.
    pub arm_random_shortcuts: usize,
    /// Spacing of the dense re-check of base paths (m, with yaw scaled by the footprint
    /// radius), default 0.02.
    pub base_check_resolution: f64,
    /// Time parameterisation without stops at the paths' corners: each corner cut by at most
    /// `max_deviation` (rad in joint space for the arm; m and rad for the base) and the
    /// blended trajectory timed time-optimally ([`time_optimal`]); it must pass the same
    /// checks as the path, sampled at the check resolution (where the fingers may touch the
    /// grasped part, also keeping them off its front), and a corner whose blend fails them
    /// becomes a stop at that corner alone. `None`: every phase stops at its corners.
    /// Default: 0.02.
    ///
    /// [`time_optimal`]: crate::motion::timing::time_optimal
    pub blend: Option<BlendSettings>,
    /// The largest corner cut (rad, joint space) of the manipulation, where the tool holds the
    /// handle: the smaller of this and `blend.max_deviation`, > 0. Default 0.002 (the Gen3's
    /// tool then leaves the handle path by at most about 2.5 mm, 0.002 times its 1.23 m
    /// reach).
    pub manipulation_blend: f64,
    /// The largest number of segments one step may be split into, >= 1. When no base pose
    /// covers a step's whole handle trajectory, the robot lets go, drives to another base pose
    /// and grasps again: the step is executed as consecutive segments of the joint's interval,
    /// each a full sequence of phases from a base pose of its own (see
    /// [`StepMotion`](super::StepMotion)). 1 keeps every step to one base pose (the paper's
    /// manipulation planner, which fails the step instead). Default 4.
    pub max_segments: usize,
    /// The sphere fast path of the arm's validity check during arm path searches: the robot
    /// covered by spheres ([`RobotSpheres`], built once per planner with these settings) and
    /// the scene as rounded boxes ([`SphereObstacles`], built once per scene state). A state
    /// whose spheres clear the scene skips the exact scene check; self-collision runs the
    /// exact test only on the link pairs whose spheres meet. Answers stay exact (the spheres
    /// are conservative); only the time changes. `None`: every state is checked exactly with
    /// parry. Default `Some(SphereSettings::default())`. With it, the search's motions are
    /// certified continuously by default ([`PlannerSettings::continuous_arm_motions`]).
    ///
    /// [`RobotSpheres`]: crate::kinematics::robot::RobotSpheres
    /// [`SphereObstacles`]: crate::kinematics::robot::SphereObstacles
    pub arm_spheres: Option<SphereSettings>,
    /// With `arm_spheres`, whether the arm path searches
    /// certify each motion over its whole length ([`ArmCheck::with_continuous`]: spans of
    /// exact distance bounds, so nothing is jumped between checked states) rather than at
    /// states `paths.resolution` apart. Default `true`; `false` gives the discrete check,
    /// whose every answer equals the exact check's at the same states.
    ///
    /// [`ArmCheck::with_continuous`]: crate::kinematics::robot::ArmCheck::with_continuous
    pub continuous_arm_motions: bool,
    /// Whole-body manipulation: when no single base pose covers a step, the base also moves
    /// during the manipulation, along with the arm ([`plan_whole_body`] with these settings,
    /// from the base pose where the fixed-base arm follows the handle furthest). When the
    /// step can also be executed in segments, the alternative with the shorter execution time
    /// is kept ([`StepMotion::mode`](super::StepMotion::mode) says which; see the
    /// [planner's docs](super#whole-body-manipulation)). Default
    /// `Some(WholeBodySettings::default())`: a consumer that executes a plan must then follow
    /// the base during a manipulation whose
    /// [`StepMotion::manipulation_base`](super::StepMotion::manipulation_base) is `Some`.
    /// `None`: every manipulation keeps its base still, the paper's manipulation planner (with
    /// segments up to `max_segments`).
    /// With it, the task level's manipulation regions admit a base cell that covers a prefix
    /// of the handle trajectory with the rest covered from other cells, up to one per grasp
    /// point (`task.manipulation.segments`), so that it does not rule out what the moving base
    /// can do.
    ///
    /// [`plan_whole_body`]: crate::motion::placement::plan_whole_body
    pub whole_body: Option<WholeBodySettings>,
}

/// The planner's default iteration budget per OMPL path search
/// ([`PathSettings::max_iterations`]): a seeded search ends on this count, at the same point
/// whatever the machine's load, with the wall-clock `paths.budget` as the safety net.
pub const PLANNER_PATH_ITERATIONS: u64 = 50_000;

impl Default for PlannerSettings {
    fn default() -> Self {
        PlannerSettings {
            task: TaskSettings::default(),
            ik: IkSettings {
                restarts: 15,
                budget: Duration::from_secs(1),
                ..IkSettings::default()
            },
            placement: PlacementSettings::default(),
            paths: PathSettings {
                seed: Some(1),
                simplifier: Simplifier::Full,
                max_iterations: Some(PLANNER_PATH_ITERATIONS),
                ..PathSettings::default()
            },
            margin: 0.02,
            stow: None,
            arm_check_resolution: 0.01,
            arm_time_shortcuts: 4,
            arm_random_shortcuts: 100,
            base_check_resolution: 0.02,
            blend: Some(BlendSettings::default()),
            manipulation_blend: 0.002,
            max_segments: 4,
            arm_spheres: Some(SphereSettings::default()),
            continuous_arm_motions: true,
            whole_body: Some(WholeBodySettings::default()),
        }
    }
}

impl PlannerSettings {
    /// These settings with every random choice of the motion layer drawn from `seed`: OMPL's
    /// generator for each path search (`paths.seed`; OMPL cannot take 0, which becomes 1),
    /// the IK restarts (`ik.seed`) and the placement's base-pose sampler
    /// (`placement.sampling.seed`). Equal seeds give equal plans (see `paths`).
    pub fn seeded(mut self, seed: u64) -> Self {
        self.paths.seed = Some(seed);
        self.ik.seed = seed;
        self.placement.sampling.seed = seed;
        self
    }

    /// Checks the settings against `robot`.
    ///
    /// # Errors
    /// [`PlannerError::InvalidSetting`] naming the setting (`stow[i]` for a stowed value
    /// outside its joint's limits); the layers' own errors for their blocks.
    pub fn validate(&self, robot: &RobotModel) -> Result<(), PlannerError> {
        self.task.validate()?;
        self.ik.validate()?;
        self.placement.validate()?;
        self.paths.validate()?;
        let positive = |field: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(InvalidSetting::new(field, v, "finite and > 0"))
            }
        };
        positive("arm_check_resolution", self.arm_check_resolution)?;
        positive("base_check_resolution", self.base_check_resolution)?;
        positive("manipulation_blend", self.manipulation_blend)?;
        if let Some(blend) = &self.blend {
            blend.validate()?;
        }
        if let Some(spheres) = &self.arm_spheres {
            spheres.validate().map_err(|e| InvalidSetting {
                field: format!("arm_spheres.{}", e.field),
                ..e
            })?;
        }
        if let Some(whole_body) = &self.whole_body {
            whole_body.validate().map_err(|e| match e {
                PlacementError::InvalidSetting(e) => PlannerError::InvalidSetting(InvalidSetting {
                    field: format!("whole_body.{}", e.field),
                    ..e
                }),
                other => other.into(),
            })?;
        }
        if self.max_segments == 0 {
            return Err(InvalidSetting::new("max_segments", 0.0, ">= 1").into());
        }
        if !(self.margin.is_finite() && self.margin >= 0.0) {
            return Err(InvalidSetting::new("margin", self.margin, "finite and >= 0").into());
        }
        if let Some(stow) = &self.stow {
            let (lower, upper) = robot.arm_bounds();
            if stow.len() != robot.dof() {
                return Err(InvalidSetting::new(
                    "stow",
                    stow.len() as f64,
                    format!("{} values long, one per arm joint", robot.dof()),
                )
                .into());
            }
            for (i, v) in stow.iter().enumerate() {
                if !(v.is_finite() && *v >= lower[i] && *v <= upper[i]) {
                    return Err(InvalidSetting::new(
                        format!("stow[{i}]"),
                        *v,
                        format!(
                            "within joint {:?}'s limits [{}, {}]",
                            robot.arm_joints()[i].name,
                            lower[i],
                            upper[i]
                        ),
                    )
                    .into());
                }
            }
        }
        Ok(())
    }
}
