//! The pluggable interfaces of the discovery stage: perception ([`Perception`]) and the robot
//! ([`Hardware`]), with their data and failure types.
//!
//! Both traits are object-safe and use only nalgebra types and the types of this file, so a
//! ROS driver or a simulator implements them without knowing the planner. Frames: the map
//! (world) frame, z up (REP 103); the base frame has x forward, y left.

use nalgebra::{Isometry2, Isometry3, Point2, Point3, Unit, Vector3};
use serde::{Deserialize, Serialize};

pub use crate::articulation::PointCloud;

/// Which camera an observation comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Camera {
    /// The head (mast) camera: a wide view of the scene in front of the base.
    Head,
    /// The wrist camera: a close view of the surface around the end effector.
    Wrist,
}

/// One handle detection: the centre of the detected box in the map frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HandleDetection {
    /// Centre of the detected handle (m), map frame: the interaction hotspot.
    pub position: Point3<f64>,
    /// Half extents of the approximate, map-axis-aligned box around the handle (m).
    pub half_extents: Vector3<f64>,
    /// Detector confidence in [0, 1].
    pub confidence: f64,
    /// Acquisition time (s).
    pub stamp: f64,
}

/// Why a sensor produced no observation.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error)]
pub enum SensorFailure {
    /// The sensor returned nothing usable (no depth returns, a dropped frame).
    #[error("no data: {reason}")]
    NoData {
        /// Free-text cause, for logs.
        reason: String,
    },
    /// The sensor or its driver is not available.
    #[error("sensor unavailable: {reason}")]
    Unavailable {
        /// Free-text cause, for logs.
        reason: String,
    },
}

/// Perception: depth observations and handle detections, both in the map frame.
pub trait Perception {
    /// One depth observation from `camera` at the robot's current pose.
    ///
    /// # Errors
    /// A [`SensorFailure`] when no observation could be taken.
    fn observe(&mut self, camera: Camera) -> Result<PointCloud, SensorFailure>;

    /// The handles the detector sees from the robot's current pose (head camera).
    ///
    /// # Errors
    /// A [`SensorFailure`] when the detector could not run.
    fn detect_handles(&mut self) -> Result<Vec<HandleDetection>, SensorFailure>;
}

/// A failure signal of the robot. Outcomes, not errors: Algorithm 1 reacts to them
/// (reposition and retry) and logs them.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, thiserror::Error)]
pub enum HardwareFailure {
    /// The gripper lost (or never got) hold of the handle.
    #[error("grasp lost")]
    GraspLost,
    /// An arm joint reached its limit: the commanded motion cannot continue from this base pose.
    #[error("arm at a joint limit")]
    JointLimit,
    /// The commanded motion would make the robot collide with itself.
    #[error("self-collision")]
    SelfCollision,
    /// The target tracker lost the tracked point (local navigation, visual servoing).
    #[error("tracking lost")]
    TrackingLost,
    /// The target is outside the arm's workspace.
    #[error("unreachable")]
    Unreachable,
    /// The base could not reach the goal.
    #[error("navigation failed: {reason}")]
    NavigationFailed {
        /// Free-text cause, for logs.
        reason: String,
    },
    /// Anything else.
    #[error("{reason}")]
    Other {
        /// Free-text cause, for logs.
        reason: String,
    },
}

/// A local-navigation goal: a base pose expressed relative to a tracked target.
///
/// The hardware drives the base so that the tracked `target` (a handle, followed by a visual
/// tracker) appears at [`target_in_goal`](LocalGoal::target_in_goal) in its base frame with
/// the heading of `world_from_base`. It servoes on the relative position, so errors of the
/// global localisation do not enter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LocalGoal {
    /// The tracked point (m), map frame, as last detected.
    pub target: Point3<f64>,
    /// The goal base pose in the map frame (x, y in metres, yaw in radians).
    pub world_from_base: Isometry2<f64>,
}

impl LocalGoal {
    /// Where the target must appear in the goal base frame (x forward, y left; metres).
    pub fn target_in_goal(&self) -> Point2<f64> {
        self.world_from_base
            .inverse_transform_point(&Point2::new(self.target.x, self.target.y))
    }
}

/// The mobile manipulator: base navigation, grasping and compliant pulling.
///
/// Poses are in the map frame: `world_from_base` on the floor (x, y, yaw), `world_from_ee` in
/// 3D. Every motion call blocks until it has finished or failed.
pub trait Hardware {
    /// Global navigation to a base pose (map frame), using the robot's own planner and
    /// localisation.
    ///
    /// # Errors
    /// Usually [`HardwareFailure::NavigationFailed`].
    fn navigate_to(&mut self, world_from_base: &Isometry2<f64>) -> Result<(), HardwareFailure>;

    /// Local navigation relative to a tracked target (see [`LocalGoal`]).
    ///
    /// # Errors
    /// [`HardwareFailure::TrackingLost`] or [`HardwareFailure::NavigationFailed`].
    fn navigate_local(&mut self, goal: &LocalGoal) -> Result<(), HardwareFailure>;

    /// Closes the gripper on `point` (map frame), approaching along `approach` (the direction
    /// the gripper moves in, towards the surface). Returns `world_from_ee` once closed.
    ///
    /// # Errors
    /// [`HardwareFailure::Unreachable`], [`HardwareFailure::GraspLost`], ...
    fn grasp(
        &mut self,
        point: &Point3<f64>,
        approach: &Unit<Vector3<f64>>,
    ) -> Result<Isometry3<f64>, HardwareFailure>;

    /// One compliant pull step (the admittance-controlled action): moves the end effector by
    /// at most `step` metres along `direction` (map frame) while complying with the grasped
    /// mechanism, so the actual motion follows the mechanism's constraint. Returns
    /// `world_from_ee` after the step.
    ///
    /// # Errors
    /// [`HardwareFailure::GraspLost`], [`HardwareFailure::JointLimit`],
    /// [`HardwareFailure::SelfCollision`], ...
    fn pull_step(
        &mut self,
        direction: &Unit<Vector3<f64>>,
        step: f64,
    ) -> Result<Isometry3<f64>, HardwareFailure>;

    /// Opens the gripper and moves the arm to its stowed pose.
    ///
    /// # Errors
    /// Any [`HardwareFailure`].
    fn retract(&mut self) -> Result<(), HardwareFailure>;

    /// The current end-effector pose, `world_from_ee`.
    fn ee_pose(&self) -> Isometry3<f64>;

    /// The current base pose, `world_from_base`.
    fn base_pose(&self) -> Isometry2<f64>;

    /// The hardware clock (s), monotonic: stamps the end-effector poses recorded while pulling
    /// (a pose whose time does not advance past the previous one is not recorded).
    fn time(&self) -> f64;
}

/// Perception and hardware together: what [`discover`](super::discover) drives.
///
/// Implemented for every type that implements both traits (a simulator usually does: one
/// world renders the cameras and moves the robot). Two separate objects — a perception
/// pipeline and a robot driver — combine with [`Split`].
pub trait Robot: Perception + Hardware {}

impl<T: Perception + Hardware + ?Sized> Robot for T {}

/// A [`Robot`] from separate perception and hardware objects (owned, or `&mut` borrows).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Split<P, H> {
    /// The perception side.
    pub perception: P,
    /// The hardware side.
    pub hardware: H,
}

impl<P: Perception, H> Perception for Split<P, H> {
    fn observe(&mut self, camera: Camera) -> Result<PointCloud, SensorFailure> {
        self.perception.observe(camera)
    }
    fn detect_handles(&mut self) -> Result<Vec<HandleDetection>, SensorFailure> {
        self.perception.detect_handles()
    }
}

impl<P, H: Hardware> Hardware for Split<P, H> {
    fn navigate_to(&mut self, world_from_base: &Isometry2<f64>) -> Result<(), HardwareFailure> {
        self.hardware.navigate_to(world_from_base)
    }
    fn navigate_local(&mut self, goal: &LocalGoal) -> Result<(), HardwareFailure> {
        self.hardware.navigate_local(goal)
    }
    fn grasp(
        &mut self,
        point: &Point3<f64>,
        approach: &Unit<Vector3<f64>>,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        self.hardware.grasp(point, approach)
    }
    fn pull_step(
        &mut self,
        direction: &Unit<Vector3<f64>>,
        step: f64,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        self.hardware.pull_step(direction, step)
    }
    fn retract(&mut self) -> Result<(), HardwareFailure> {
        self.hardware.retract()
    }
    fn ee_pose(&self) -> Isometry3<f64> {
        self.hardware.ee_pose()
    }
    fn base_pose(&self) -> Isometry2<f64> {
        self.hardware.base_pose()
    }
    fn time(&self) -> f64 {
        self.hardware.time()
    }
}

impl<T: Perception + ?Sized> Perception for &mut T {
    fn observe(&mut self, camera: Camera) -> Result<PointCloud, SensorFailure> {
        (**self).observe(camera)
    }
    fn detect_handles(&mut self) -> Result<Vec<HandleDetection>, SensorFailure> {
        (**self).detect_handles()
    }
}

impl<T: Hardware + ?Sized> Hardware for &mut T {
    fn navigate_to(&mut self, world_from_base: &Isometry2<f64>) -> Result<(), HardwareFailure> {
        (**self).navigate_to(world_from_base)
    }
    fn navigate_local(&mut self, goal: &LocalGoal) -> Result<(), HardwareFailure> {
        (**self).navigate_local(goal)
    }
    fn grasp(
        &mut self,
        point: &Point3<f64>,
        approach: &Unit<Vector3<f64>>,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        (**self).grasp(point, approach)
    }
    fn pull_step(
        &mut self,
        direction: &Unit<Vector3<f64>>,
        step: f64,
    ) -> Result<Isometry3<f64>, HardwareFailure> {
        (**self).pull_step(direction, step)
    }
    fn retract(&mut self) -> Result<(), HardwareFailure> {
        (**self).retract()
    }
    fn ee_pose(&self) -> Isometry3<f64> {
        (**self).ee_pose()
    }
    fn base_pose(&self) -> Isometry2<f64> {
        (**self).base_pose()
    }
    fn time(&self) -> f64 {
        (**self).time()
    }
}
