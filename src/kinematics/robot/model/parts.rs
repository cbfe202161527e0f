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
/// The robot model and its kinematics are the same for every kind — the base pose is
/// `(x, y, yaw)` and [`RobotModel::world_from_base`] places it — only the motion layer
/// differs:
/// - [`BaseKind::Holonomic`]: base paths are planned in SE(2) with a straight-line local
///   planner (yaw wrapping) and timed per axis under [`MobileBase::max_velocity`] /
///   [`MobileBase::max_acceleration`] (`[x, y, yaw]`).
/// - [`BaseKind::DifferentialDrive`]: base paths are planned in SE(2) as well, then turned into
///   turn-in-place and drive-straight (forward or backward) pieces that never move sideways,
///   and the whole robot is collision-checked along those pieces (see
///   [`motion::paths::differential_drive`](crate::motion::paths::differential_drive)). They are
///   timed along the path under the forward speed and the yaw rate (see
///   [`motion::timing::time_differential_drive`](crate::motion::timing::time_differential_drive)).
///
/// Base placement is the same for every kind: it only chooses the final pose. A car-like base
/// (`Ackermann { wheelbase, min_turning_radius }`, planned in OMPL's Dubins or Reeds–Shepp
/// spaces) would be another variant; code that matches on `BaseKind` (it is
/// `#[non_exhaustive]`) must reject kinds it cannot plan for.
#[non_exhaustive]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BaseKind {
    /// Omnidirectional: x, y and yaw independently controllable.
    #[default]
    Holonomic,
    /// Two driven wheels on one axle (TIAGo, Fetch, Stretch): the base moves along its own x
    /// axis (forward or backward) and turns about its origin, never sideways (velocity in the
    /// base frame `(v, 0, ω)`). [`MobileBase::max_velocity`] and
    /// [`MobileBase::max_acceleration`] then hold `[forward, 0, yaw]`: the forward speed
    /// (m/s) and acceleration (m/s²) along the base's x axis, a lateral entry that must be 0,
    /// and the yaw rate (rad/s) and acceleration (rad/s²). The base origin is taken to be the
    /// midpoint of the wheel axle (REP 120's `base_footprint`), so turning in place keeps it
    /// fixed.
    DifferentialDrive,
}

/// The mobile base: its kind, footprint and planar limits.
#[derive(Debug, Clone, PartialEq)]
pub struct MobileBase {
    /// How the base moves.
    pub kind: BaseKind,
    /// Radius (m) of the vertical cylinder about the base origin that encloses the base and
    /// the arm at [`RobotModel::neutral`] (the footprint the navigation grid uses).
    pub footprint_radius: f64,
    /// Velocity limits in the base frame. Holonomic: x (m/s), y (m/s), yaw (rad/s).
    /// Differential drive: forward speed (m/s), 0 (no sideways motion), yaw rate (rad/s).
    pub max_velocity: [f64; 3],
    /// Acceleration limits. Holonomic: x (m/s²), y (m/s²), yaw (rad/s²). Differential drive:
    /// forward (m/s²), 0, yaw (rad/s²).
    pub max_acceleration: [f64; 3],
}

impl MobileBase {
    /// This base as a differential-drive base with the same footprint: the x limits become the
    /// forward limits, the yaw limits stay, the lateral entries become 0.
    pub fn to_differential_drive(&self) -> MobileBase {
        let [vx, _, vyaw] = self.max_velocity;
        let [ax, _, ayaw] = self.max_acceleration;
        MobileBase {
            kind: BaseKind::DifferentialDrive,
            footprint_radius: self.footprint_radius,
            max_velocity: [vx, 0.0, vyaw],
            max_acceleration: [ax, 0.0, ayaw],
        }
    }
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
    /// One index into [`RobotLink::merged`] per collider: the URDF link it comes from (an SRDF
    /// exempts pairs of URDF links). Empty: every collider comes from the first.
    pub sources: Vec<usize>,
}

impl RobotLink {
    /// The URDF link (name) collider `k` comes from; `None` for a link that carries no
    /// URDF link's collision elements.
    pub fn source(&self, k: usize) -> Option<&str> {
        let m = self.sources.get(k).copied().unwrap_or(0);
        self.merged.get(m).map(String::as_str)
    }

    /// The link's name for a contact of `collider`: its own, or `link/urdf_link` when the
    /// collider comes from another URDF link merged into it (`base_footprint/head_2_link`).
    pub fn contact_name(&self, collider: Option<usize>) -> String {
        match collider.and_then(|c| self.source(c)) {
            Some(source) if source != self.name => format!("{}/{source}", self.name),
            _ => self.name.clone(),
        }
    }

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
