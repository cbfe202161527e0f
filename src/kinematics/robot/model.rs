//! The immutable [`RobotModel`] and its plain-data pieces.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::{DVector, Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

use super::RobotError;
use super::urdf::{self, Parsed};
use crate::InvalidSetting;
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

/// Import options of [`RobotModel::from_urdf_str_with`].
#[derive(Debug, Clone, PartialEq)]
pub struct RobotImportOptions {
    /// Name of the link whose frame is the tool frame (TCP). Default `"tool_frame"`.
    pub tool_link: String,
    /// The URDF links whose collision elements are the gripper's contact geometry: the only
    /// shapes allowed to touch a grasped part, and only while grasping. Each must be rigidly
    /// attached below the last arm joint (it moves with the tool).
    ///
    /// `None` (the default) applies the naming convention: a collision element below the last
    /// arm joint is contact geometry when the name of its URDF link or of the `<collision>`
    /// element contains `finger` or `pad` (ASCII case-insensitive), as in the usual gripper
    /// descriptions (`panda_leftfinger`, `left_inner_finger_pad`, `gripper_finger_link`).
    /// `Some(vec![])` declares a robot without contact geometry: then no shape may touch a
    /// grasped part.
    pub contact_links: Option<Vec<String>>,
    /// Package roots for mesh URIs: `package://NAME/rest` resolves to
    /// `package_paths[NAME]/rest`. Default empty.
    pub package_paths: BTreeMap<String, PathBuf>,
    /// Directory that relative mesh paths resolve against. `None`: the current directory;
    /// [`RobotModel::from_urdf_file_with`] uses the file's directory when this is `None`.
    pub base_dir: Option<PathBuf>,
    /// The link the arm starts at. `None` (the default): the base link, so every movable joint
    /// on the path from the base to the tool link is an arm joint. With a link on that path,
    /// the movable joints above it (a torso lift, say) are frozen like the joints off the
    /// path ([`RobotImportOptions::frozen`]).
    pub arm_root: Option<String>,
    /// The approach direction in the tool link's frame, when it is not the link's +z (a hand
    /// whose fingers point along its x, say): the tool frame is then the tool link's frame
    /// turned so that its +z is this direction. Default `None`.
    pub tool_approach: Option<[f64; 3]>,
    /// Values (rad or m) of movable joints that are not arm joints: a head, wheels, a second
    /// arm, fingers, joints above [`RobotImportOptions::arm_root`]. Such a joint is frozen at
    /// its value here, or at 0 clamped into its limits, and its links stay in the collision
    /// model at that value. Default empty.
    pub frozen: BTreeMap<String, f64>,
}

impl Default for RobotImportOptions {
    fn default() -> Self {
        RobotImportOptions {
            tool_link: "tool_frame".to_owned(),
            contact_links: None,
            package_paths: BTreeMap::new(),
            base_dir: None,
            arm_root: None,
            tool_approach: None,
            frozen: BTreeMap::new(),
        }
    }
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

/// A mobile manipulator: a planar base carrying one serial arm with a tool frame. See the
/// [module docs](super) for the URDF conventions.
///
/// Immutable after construction (the `with_*` methods return a modified copy), `Send + Sync`,
/// cheap to clone (the Pinocchio model is shared).
#[derive(Debug, Clone)]
pub struct RobotModel {
    pub(super) name: String,
    pub(super) base: MobileBase,
    pub(super) joints: Vec<ArmJoint>,
    pub(super) links: Vec<RobotLink>,
    pub(super) base_from_arm_root: Isometry3<f64>,
    pub(super) last_from_tool: Isometry3<f64>,
    pub(super) neutral: DVector<f64>,
    pub(super) pinocchio: Arc<kinscene_pinocchio::Model>,
    pub(super) tool_frame: kinscene_pinocchio::FrameIndex,
    /// The self-collision exemptions, when given or computed (see
    /// [`RobotModel::allowed_pairs`]).
    pub(super) allowed_pairs: Option<Arc<[super::AllowedPair]>>,
    pub(super) frozen: Vec<FrozenJoint>,
}

/// The shipped robot's URDF (see `robots/kinova_gen3_mobile.urdf`).
const KINOVA_GEN3_MOBILE_URDF: &str = include_str!("../../../robots/kinova_gen3_mobile.urdf");

/// The shipped robot's SRDF: its arm group, stowed configuration and self-collision
/// exemptions (see `robots/kinova_gen3_mobile.srdf`).
const KINOVA_GEN3_MOBILE_SRDF: &str = include_str!("../../../robots/kinova_gen3_mobile.srdf");

impl RobotModel {
    /// Loads a robot from URDF text, with the tool frame at the link `tool_frame`.
    ///
    /// # Errors
    /// See [`RobotModel::from_urdf_str_with`].
    pub fn from_urdf_str(text: &str) -> Result<RobotModel, RobotError> {
        RobotModel::from_urdf_str_with(text, &RobotImportOptions::default())
    }

    /// Loads a robot from URDF text with the given options.
    ///
    /// # Errors
    /// A [`RobotError`] naming the element at fault: [`RobotError::Xml`] (not URDF),
    /// [`RobotError::DuplicateName`], [`RobotError::UnknownLink`], [`RobotError::NotATree`],
    /// [`RobotError::UnsupportedJointType`], [`RobotError::MissingToolLink`],
    /// [`RobotError::NoMovableJoint`], [`RobotError::InvalidArmRoot`], [`RobotError::InvalidFrozen`],
    /// [`RobotError::InvalidAxis`], [`RobotError::InvalidLimits`],
    /// [`RobotError::NonPositiveLimit`], [`RobotError::NonFinite`],
    /// [`RobotError::MeshCollision`] (a mesh that cannot be loaded), [`RobotError::InvalidShape`];
    /// [`RobotError::Pinocchio`]
    /// if the Pinocchio backend cannot be loaded.
    pub fn from_urdf_str_with(
        text: &str,
        options: &RobotImportOptions,
    ) -> Result<RobotModel, RobotError> {
        let parsed = urdf::parse(text, options)?;
        RobotModel::from_parsed(parsed)
    }

    /// Loads a robot from a URDF file (tool link `tool_frame`; relative mesh paths against the
    /// file's directory).
    ///
    /// # Errors
    /// [`RobotError::Io`] if the file cannot be read, otherwise as
    /// [`RobotModel::from_urdf_str_with`].
    pub fn from_urdf_file(path: &Path) -> Result<RobotModel, RobotError> {
        RobotModel::from_urdf_file_with(path, &RobotImportOptions::default())
    }

    /// Loads a robot from a URDF file with the given options; relative mesh paths resolve
    /// against the file's directory unless `options.base_dir` is set.
    ///
    /// # Errors
    /// [`RobotError::Io`] if the file cannot be read, otherwise as
    /// [`RobotModel::from_urdf_str_with`].
    pub fn from_urdf_file_with(
        path: &Path,
        options: &RobotImportOptions,
    ) -> Result<RobotModel, RobotError> {
        let text = std::fs::read_to_string(path).map_err(|e| RobotError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        let mut options = options.clone();
        if options.base_dir.is_none() {
            options.base_dir = path.parent().map(Path::to_path_buf);
        }
        RobotModel::from_urdf_str_with(&text, &options)
    }

    /// The shipped example robot: an omnidirectional base carrying a Kinova Gen3 7-DoF arm with
    /// a Robotiq 2F-140 gripper (`robots/kinova_gen3_mobile.urdf` and `.srdf`, compiled in),
    /// with the SRDF's stowed configuration as [`RobotModel::neutral`] and its exemptions as
    /// [`RobotModel::allowed_pairs`].
    ///
    /// # Panics
    /// Only if the Pinocchio backend cannot be loaded (the shipped URDF itself is checked by
    /// the tests); use [`RobotModel::try_kinova_gen3_mobile`] to get that as an error.
    pub fn kinova_gen3_mobile() -> RobotModel {
        match RobotModel::try_kinova_gen3_mobile() {
            Ok(robot) => robot,
            Err(e) => panic!("the shipped Kinova Gen3 mobile manipulator failed to load: {e}"),
        }
    }

    /// [`RobotModel::kinova_gen3_mobile`], with a failing Pinocchio backend as an error.
    ///
    /// # Errors
    /// [`RobotError::Pinocchio`] if the backend cannot be loaded.
    pub fn try_kinova_gen3_mobile() -> Result<RobotModel, RobotError> {
        RobotModel::from_urdf_str(KINOVA_GEN3_MOBILE_URDF)?
            .with_srdf(&super::Srdf::parse(KINOVA_GEN3_MOBILE_SRDF)?)
    }

    fn from_parsed(parsed: Parsed) -> Result<RobotModel, RobotError> {
        let neutral = default_neutral(&parsed.joints);
        let (pinocchio, tool_frame) = super::pinocchio::build(
            &parsed.joints,
            &parsed.base_from_arm_root,
            &parsed.last_from_tool,
        )?;
        let mut robot = RobotModel {
            name: parsed.name,
            base: MobileBase {
                kind: BaseKind::Holonomic,
                footprint_radius: 0.0,
                max_velocity: DEFAULT_BASE_VELOCITY,
                max_acceleration: DEFAULT_BASE_ACCELERATION,
            },
            joints: parsed.joints,
            links: parsed.links,
            base_from_arm_root: parsed.base_from_arm_root,
            last_from_tool: parsed.last_from_tool,
            neutral,
            pinocchio: Arc::new(pinocchio),
            tool_frame,
            allowed_pairs: None,
            frozen: parsed.frozen,
        };
        robot.base.footprint_radius = robot.footprint_at_neutral();
        Ok(robot)
    }

    /// The URDF robot name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The mobile base.
    pub fn base(&self) -> &MobileBase {
        &self.base
    }

    /// Number of arm joints (the length of [`RobotConfig::arm`]).
    pub fn dof(&self) -> usize {
        self.joints.len()
    }

    /// The arm joints, root to tip.
    pub fn arm_joints(&self) -> &[ArmJoint] {
        &self.joints
    }

    /// The movable URDF joints that are not arm joints and the values they are frozen at, in
    /// the order the URDF tree is walked.
    pub fn frozen_joints(&self) -> &[FrozenJoint] {
        &self.frozen
    }

    /// The links: `[0]` is the base link (it moves with the base), `[i + 1]` the child link of
    /// `arm_joints()[i]`.
    pub fn links(&self) -> &[RobotLink] {
        &self.links
    }

    /// The arm root link's frame (the parent link of the first arm joint) in the base frame:
    /// the composed origins of the fixed joints from the base link to it.
    pub fn base_from_arm_root(&self) -> &Isometry3<f64> {
        &self.base_from_arm_root
    }

    /// The tool frame (TCP) in the last arm link's frame. The tool's +z axis is the approach
    /// direction.
    pub fn last_from_tool(&self) -> &Isometry3<f64> {
        &self.last_from_tool
    }

    /// The "home" configuration: for the shipped robot a stowed, collision-free configuration;
    /// for a loaded URDF, 0 for every joint clamped into its limits (replace it with
    /// [`RobotModel::with_neutral`]).
    pub fn neutral(&self) -> DVector<f64> {
        self.neutral.clone()
    }

    /// Lower and upper position limits of the arm joints (`±∞` for continuous joints).
    pub fn arm_bounds(&self) -> (DVector<f64>, DVector<f64>) {
        (
            DVector::from_iterator(self.dof(), self.joints.iter().map(|j| j.lower)),
            DVector::from_iterator(self.dof(), self.joints.iter().map(|j| j.upper)),
        )
    }

    /// The arm as a Pinocchio model, built with `ModelBuilder` from the parsed robot: one
    /// revolute (also for continuous joints, so `nq = nv = dof` and q is the angle) or
    /// prismatic joint per arm joint, named as in the URDF, the first placed at
    /// `base_from_arm_root · parent_from_joint` under the universe, so the model's root frame is
    /// the robot's base frame; position and velocity limits as in [`ArmJoint`]; and the
    /// operational frame `"tool"` at [`RobotModel::last_from_tool`].
    pub fn pinocchio(&self) -> &kinscene_pinocchio::Model {
        &self.pinocchio
    }

    /// The operational frame `"tool"` in [`RobotModel::pinocchio`].
    pub fn tool_frame(&self) -> kinscene_pinocchio::FrameIndex {
        self.tool_frame
    }

    /// The base frame in the world for a planar base pose `(x, y, yaw)`: a rotation by `yaw`
    /// about world z, then a translation by `(x, y, 0)`.
    pub fn world_from_base(base: [f64; 3]) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(base[0], base[1], 0.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), base[2]),
        )
    }

    /// This robot with other arm acceleration limits (one per joint, rad/s² or m/s²).
    ///
    /// # Errors
    /// [`RobotError::DimensionMismatch`] unless `limits` has [`RobotModel::dof`] entries,
    /// [`RobotError::NonPositiveLimit`] for a limit that is not finite and positive.
    pub fn with_acceleration_limits(mut self, limits: &[f64]) -> Result<RobotModel, RobotError> {
        check_len("acceleration limits", self.dof(), limits.len())?;
        for (joint, &value) in self.joints.iter().zip(limits) {
            check_positive_limit(&joint.name, "acceleration", value)?;
        }
        for (joint, &value) in self.joints.iter_mut().zip(limits) {
            joint.max_acceleration = value;
        }
        Ok(self)
    }

    /// This robot with another mobile base description (kind, footprint and limits).
    ///
    /// # Errors
    /// [`RobotError::InvalidSetting`] for a footprint radius that is not finite and positive,
    /// [`RobotError::NonPositiveLimit`] for a velocity or acceleration limit that is not finite
    /// and positive.
    pub fn with_base(mut self, base: MobileBase) -> Result<RobotModel, RobotError> {
        if !(base.footprint_radius.is_finite() && base.footprint_radius > 0.0) {
            return Err(InvalidSetting::new(
                "footprint_radius",
                base.footprint_radius,
                "finite and > 0",
            )
            .into());
        }
        for (axis, (&v, &a)) in ["base x", "base y", "base yaw"]
            .iter()
            .zip(base.max_velocity.iter().zip(&base.max_acceleration))
        {
            check_positive_limit(axis, "velocity", v)?;
            check_positive_limit(axis, "acceleration", a)?;
        }
        self.base = base;
        Ok(self)
    }

    /// This robot with another [`RobotModel::neutral`] configuration. The footprint radius is
    /// recomputed for it (see [`MobileBase::footprint_radius`]).
    ///
    /// # Errors
    /// [`RobotError::DimensionMismatch`], [`RobotError::NonFiniteValue`],
    /// [`RobotError::OutOfLimits`].
    pub fn with_neutral(mut self, q: &DVector<f64>) -> Result<RobotModel, RobotError> {
        self.check_arm(q)?;
        for (joint, &value) in self.joints.iter().zip(q.iter()) {
            if !(joint.lower..=joint.upper).contains(&value) {
                return Err(RobotError::OutOfLimits {
                    joint: joint.name.clone(),
                    value,
                    lower: joint.lower,
                    upper: joint.upper,
                });
            }
        }
        self.neutral = q.clone();
        self.base.footprint_radius = self.footprint_at_neutral();
        Ok(self)
    }

    /// `world_from_link` for every link ([`RobotModel::links`] order) at `config`: pure-Rust
    /// forward kinematics, no allocation besides the result. Joint limits are not enforced.
    ///
    /// # Errors
    /// [`RobotError::DimensionMismatch`] unless `config.arm` has [`RobotModel::dof`] entries,
    /// [`RobotError::NonFiniteValue`] for a NaN or infinite entry.
    pub fn link_poses(&self, config: &RobotConfig) -> Result<Vec<Isometry3<f64>>, RobotError> {
        check_finite("base", &config.base)?;
        self.check_arm(&config.arm)?;
        let world_from_base = RobotModel::world_from_base(config.base);
        let mut poses = Vec::with_capacity(self.dof() + 1);
        poses.push(world_from_base);
        let mut pose = world_from_base * self.base_from_arm_root;
        for (joint, &q) in self.joints.iter().zip(config.arm.iter()) {
            pose *= joint.parent_from_child(q);
            poses.push(pose);
        }
        Ok(poses)
    }

    /// The tool frame in the world at `config`.
    ///
    /// # Errors
    /// As [`RobotModel::link_poses`].
    pub fn world_from_tool(&self, config: &RobotConfig) -> Result<Isometry3<f64>, RobotError> {
        check_finite("base", &config.base)?;
        Ok(RobotModel::world_from_base(config.base) * self.base_from_tool(&config.arm)?)
    }

    /// The tool frame in the base frame at arm configuration `arm` (the frame Pinocchio's
    /// [`RobotModel::tool_frame`] reports).
    ///
    /// # Errors
    /// [`RobotError::DimensionMismatch`], [`RobotError::NonFiniteValue`].
    pub fn base_from_tool(&self, arm: &DVector<f64>) -> Result<Isometry3<f64>, RobotError> {
        self.check_arm(arm)?;
        let mut pose = self.base_from_arm_root;
        for (joint, &q) in self.joints.iter().zip(arm.iter()) {
            pose *= joint.parent_from_child(q);
        }
        Ok(pose * self.last_from_tool)
    }

    fn check_arm(&self, arm: &DVector<f64>) -> Result<(), RobotError> {
        check_len("arm", self.dof(), arm.len())?;
        check_finite("arm", arm.as_slice())
    }

    /// The radius of the vertical cylinder about the base origin enclosing every collider at
    /// the neutral configuration (bounding spheres, so slightly conservative for boxes).
    fn footprint_at_neutral(&self) -> f64 {
        self.footprint_at(&self.neutral)
    }

    /// The largest horizontal distance of the base link's colliders from the base's vertical
    /// axis: the chassis alone, whatever the arm does.
    pub(super) fn base_radius(&self) -> f64 {
        self.links[0]
            .colliders
            .iter()
            .map(|c| horizontal_reach(c, &Isometry3::identity()))
            .fold(0.0, f64::max)
    }

    /// The footprint radius with the arm at `arm`: the largest horizontal distance of any
    /// collider from the base's vertical axis (0 for a configuration of the wrong size).
    pub(super) fn footprint_at(&self, arm: &DVector<f64>) -> f64 {
        let config = RobotConfig {
            base: [0.0; 3],
            arm: arm.clone(),
        };
        let Ok(poses) = self.link_poses(&config) else {
            return 0.0;
        };
        let mut radius: f64 = 0.0;
        for (link, pose) in self.links.iter().zip(&poses) {
            for collider in &link.colliders {
                radius = radius.max(horizontal_reach(collider, pose));
            }
        }
        radius
    }
}

/// The largest horizontal distance from the world z axis of a collider placed at
/// `world_from_link`: exact for boxes (their corners), bounding sphere otherwise.
fn horizontal_reach(collider: &Collider, world_from_link: &Isometry3<f64>) -> f64 {
    use crate::scene::Shape;
    let world_from_shape = world_from_link * collider.part_from_shape;
    match &collider.shape {
        Shape::Cuboid { half_extents } => {
            let mut reach: f64 = 0.0;
            for k in 0..8 {
                let sign = |bit: usize| if k & bit == 0 { -1.0 } else { 1.0 };
                let corner = nalgebra::Point3::new(
                    sign(1) * half_extents.x,
                    sign(2) * half_extents.y,
                    sign(4) * half_extents.z,
                );
                let p = world_from_shape * corner;
                reach = reach.max(p.x.hypot(p.y));
            }
            reach
        }
        shape => {
            let sphere = shape.bounding_sphere();
            let c = world_from_shape * sphere.center;
            c.x.hypot(c.y) + sphere.radius
        }
    }
}

/// The default neutral configuration: 0 clamped into each joint's limits.
fn default_neutral(joints: &[ArmJoint]) -> DVector<f64> {
    DVector::from_iterator(
        joints.len(),
        joints.iter().map(|j| 0.0_f64.clamp(j.lower, j.upper)),
    )
}

fn check_len(what: &'static str, expected: usize, got: usize) -> Result<(), RobotError> {
    if expected == got {
        Ok(())
    } else {
        Err(RobotError::DimensionMismatch {
            what,
            expected,
            got,
        })
    }
}

fn check_finite(what: &'static str, values: &[f64]) -> Result<(), RobotError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(RobotError::NonFiniteValue { what, index }),
        None => Ok(()),
    }
}

pub(super) fn check_positive_limit(
    joint: &str,
    what: &'static str,
    value: f64,
) -> Result<(), RobotError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(RobotError::NonPositiveLimit {
            joint: joint.to_owned(),
            what,
            value,
        })
    }
}
