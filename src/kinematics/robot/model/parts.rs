//! The robot's plain-data pieces: the mobile base, arm joints, links, configurations and
//! frozen joints, with the default limits.

use nalgebra::{DVector, Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

#[cfg(doc)]
use super::{RobotImportOptions, RobotModel};
use crate::scene::Collider;

/// Default acceleration limit of revolute and continuous arm joints (rad/s²), used when the URDF
/// gives none (URDF ≤ 1.1 has no acceleration limits).
pub const DEFAULT_REVOLUTE_ACCELERATION: f64 = 2.0;
/// Default acceleration limit of prismatic arm joints (m/s²), used when the URDF gives none.
pub const DEFAULT_PRISMATIC_ACCELERATION: f64 = 1.0;
/// Default base velocity limits: x, y (m/s), yaw (rad/s).
pub const DEFAULT_BASE_VELOCITY: [f64; 3] = [0.5, 0.5, 1.0];
/// Default base acceleration limits: x, y (m/s²), yaw (rad/s²).
pub const DEFAULT_BASE_ACCELERATION: [f64; 3] = [0.5, 0.5, 1.0];

/// How the mobile base moves in the plane.
///
/// Only [`BaseKind::Holonomic`] exists today: the base follows any planar path in SE(2), so
/// base paths are planned in SE(2) with a straight-line local planner (yaw wrapping) and timed
/// per axis under [`MobileBase::max_velocity`] / [`MobileBase::max_acceleration`].
///
/// A non-holonomic base (differential drive, car-like) would be a new variant carrying its
/// constraint (e.g. `DifferentialDrive { track_width }` or `Ackermann { wheelbase,
/// min_turning_radius }`). Nothing in the robot model or its kinematics changes — the base pose
/// is still `(x, y, yaw)` and [`RobotModel::world_from_base`] is the same — but the motion
/// layer must then plan base paths with a state space that respects the constraint (OMPL's
/// Dubins or Reeds–Shepp spaces, or a kinodynamic planner over the wheel controls), and time
/// them along the path (forward speed and yaw rate) instead of per axis. Base placement is
/// unaffected, since it only chooses the final pose. Code that matches on `BaseKind` (it is
/// `#[non_exhaustive]`) must reject kinds it cannot plan for.
#[non_exhaustive]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BaseKind {
    /// Omnidirectional: x, y and yaw independently controllable.
    Holonomic,
}

/// The mobile base: its kind, footprint and planar limits.
#[derive(Debug, Clone, PartialEq)]
pub struct MobileBase {
    /// How the base moves.
    pub kind: BaseKind,
    /// Radius (m) of the vertical cylinder about the base origin that encloses the base and
    /// the arm at [`RobotModel::neutral`] (the footprint the navigation grid uses).
    pub footprint_radius: f64,
    /// Velocity limits: x (m/s), y (m/s), yaw (rad/s), in the base frame.
    pub max_velocity: [f64; 3],
    /// Acceleration limits: x (m/s²), y (m/s²), yaw (rad/s²).
    pub max_acceleration: [f64; 3],
}

/// The kind of an arm joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArmJointKind {
    /// Rotation about the axis, with finite position limits (rad).
    Revolute,
    /// Rotation about the axis without position limits (URDF `continuous`): `lower = -∞`,
    /// `upper = +∞`. The angle is not wrapped: q and q + 2π are different configurations with
    /// the same pose.
    Continuous,
    /// Translation along the axis (m).
    Prismatic,
}

/// One actuated arm joint.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmJoint {
    /// The URDF joint name.
    pub name: String,
    /// Kind.
    pub kind: ArmJointKind,
    /// Joint frame in the parent link's frame (the URDF `<origin>`, composed with the origins
    /// of any fixed joints between the previous arm link and this joint). For the first arm
    /// joint the parent link is the arm root link, placed on the base by
    /// [`RobotModel::base_from_arm_root`].
    pub parent_from_joint: Isometry3<f64>,
    /// Unit axis in the joint frame.
    pub axis: Unit<Vector3<f64>>,
    /// Lower position limit (rad or m; `-∞` for continuous joints).
    pub lower: f64,
    /// Upper position limit (rad or m; `+∞` for continuous joints).
    pub upper: f64,
    /// Velocity limit (rad/s or m/s), > 0.
    pub max_velocity: f64,
    /// Acceleration limit (rad/s² or m/s²), > 0.
    pub max_acceleration: f64,
}

impl ArmJoint {
    /// The child link's frame in the joint's parent link frame at joint value `q`:
    /// `parent_from_joint · motion(q)`.
    pub fn parent_from_child(&self, q: f64) -> Isometry3<f64> {
        self.parent_from_joint * self.motion(q)
    }

    /// The joint's motion at value `q` in the joint frame: a rotation by `q` about the axis
    /// (revolute, continuous) or a translation by `q` along it (prismatic).
    pub fn motion(&self, q: f64) -> Isometry3<f64> {
        match self.kind {
            ArmJointKind::Revolute | ArmJointKind::Continuous => Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_axis_angle(&self.axis, q),
            ),
            ArmJointKind::Prismatic => Isometry3::from_parts(
                Translation3::from(self.axis.into_inner() * q),
                UnitQuaternion::identity(),
            ),
        }
    }
}

/// A rigid link of the robot and its collision geometry (in the link frame). Links attached
/// by fixed joints are merged into their parent's [`RobotLink`].
#[derive(Debug, Clone, PartialEq)]
pub struct RobotLink {
    /// The URDF link name (the one that owns the merged fixed links).
    pub name: String,
    /// Collision shapes in the link frame (primitives, and convex hulls of meshes).
    pub colliders: Vec<Collider>,
    /// One flag per collider: `true` for the gripper's contact geometry (fingers, pads), the
    /// only shapes allowed to touch a grasped part (see [`RobotImportOptions::contact_links`]).
    pub contact: Vec<bool>,
    /// The URDF links whose collision elements this link carries (itself and the links merged
    /// into it through fixed or frozen joints), in the order they were merged.
    pub merged: Vec<String>,
}

impl RobotLink {
    /// The link's colliders with their contact flags.
    pub fn colliders_with_contact(&self) -> impl Iterator<Item = (&Collider, bool)> {
        self.colliders
            .iter()
            .zip(self.contact.iter().copied().chain(std::iter::repeat(false)))
    }
}

/// A configuration of the whole robot.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotConfig {
    /// Base pose in the world: x (m), y (m), yaw (rad).
    pub base: [f64; 3],
    /// Arm joint values, [`RobotModel::dof`] entries (rad or m).
    pub arm: DVector<f64>,
}

/// A movable URDF joint that is not an arm joint, held at one value
/// ([`RobotImportOptions::frozen`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FrozenJoint {
    /// The URDF joint name.
    pub name: String,
    /// Its value (rad or m).
    pub value: f64,
}
