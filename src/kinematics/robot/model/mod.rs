//! The immutable [`RobotModel`] and its plain-data pieces.

mod checks;
mod construct;
mod footprint;
mod options;
mod parts;

use std::sync::Arc;

use nalgebra::{DVector, Isometry3, Translation3, UnitQuaternion, Vector3};

use super::RobotError;
pub(super) use checks::check_positive_limit;
use checks::{check_finite, check_len};
pub use options::RobotImportOptions;
pub use parts::{
    ArmJoint, ArmJointKind, BaseKind, DEFAULT_BASE_ACCELERATION, DEFAULT_BASE_VELOCITY,
    DEFAULT_PRISMATIC_ACCELERATION, DEFAULT_REVOLUTE_ACCELERATION, FrozenJoint, MobileBase,
    RobotConfig, RobotLink,
};

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
    /// Checked link pairs of which only some collider pairs are exempt (see
    /// [`RobotModel::exempt_colliders`]).
    pub(super) exempt_colliders: Arc<[super::ExemptColliders]>,
    pub(super) frozen: Vec<FrozenJoint>,
}

impl RobotModel {
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

    pub(super) fn check_arm(&self, arm: &DVector<f64>) -> Result<(), RobotError> {
        check_len("arm", self.dof(), arm.len())?;
        check_finite("arm", arm.as_slice())
    }
}
