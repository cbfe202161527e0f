//! The mobile manipulator: a mobile base (holonomic or differential drive) carrying a serial
//! arm, loaded from URDF.
//!
//! [`RobotModel`] is parsed with urdf-rs; its arm is also built as a Pinocchio model with
//! `ModelBuilder` from the parsed data (not with Pinocchio's own URDF parser), for Jacobians and
//! IK ([`crate::kinematics::ik`]). Forward kinematics of the whole robot is pure Rust
//! ([`RobotModel::link_poses`]); collision checking, against itself and the scene, is
//! [`RobotCollision`] (parry). The example robot of the paper ships with the crate:
//! [`RobotModel::kinova_gen3_mobile`] (`robots/kinova_gen3_mobile.urdf`).
//!
//! # Robot URDF conventions
//!
//! - **Base.** The root link is the mobile base, and its frame the base frame: origin on the
//!   floor, x forward, z up. Its planar motion `(x, y, yaw)` is implicit
//!   ([`RobotModel::world_from_base`]). A URDF that models that motion with a `planar` or
//!   `floating` joint from a `world`/`odom` root link is accepted: when the root link's only
//!   joint is of one of these types, the joint is skipped, its child is the base link, and the
//!   root link (with any collision elements) is ignored. So is a base modelled as joints, as
//!   several simulators do, recognised by its structure whatever the names: a chain from the
//!   root link of a `prismatic` joint along +x and one along +y (either order), then a
//!   `revolute` or `continuous` joint about +z, each the only joint of its parent link, with
//!   origins that are the identity or a pure z offset. The three joints are skipped (their
//!   limits too), the last one's child is the base link, lifted in the base frame by the sum of
//!   the z offsets, and the links before it are ignored. Any other axis, sign, order or origin
//!   leaves the joints as they are (arm or frozen joints).
//! - **Fixed merge.** A link attached by a `fixed` joint merges into its parent link, through
//!   chains of any length: its collision elements move into the owner's frame, composed with
//!   the fixed joints' origins, and a movable joint below it gets its origin composed the same
//!   way ([`ArmJoint::parent_from_joint`]). The links between the base link and the first arm
//!   joint merge into the base link; the arm root link's frame in the base frame is
//!   [`RobotModel::base_from_arm_root`].
//! - **Arm.** The arm is the chain of `revolute`, `continuous` and `prismatic` joints on the
//!   path from the base link to the tool link, root to tip ([`RobotModel::arm_joints`]), or
//!   from [`RobotImportOptions::arm_root`] when set; it must have at least one joint
//!   ([`RobotError::NoMovableJoint`]). [`RobotModel::links`] holds the base link and one link
//!   per arm joint (its child).
//! - **Frozen joints.** Every other movable joint — a head, wheels, a torso above the arm
//!   root, a second arm, a gripper's finger and `<mimic>` joints — is held at its value in
//!   [`RobotImportOptions::frozen`], or at 0 clamped into its limits
//!   ([`RobotModel::frozen_joints`]; its velocity limit is not checked): it is treated as
//!   fixed, and its links merge into the robot link it hangs from, so they stay in the
//!   collision model at that value. A `frozen` entry that names no such joint, or a value
//!   outside the joint's limits, is [`RobotError::InvalidFrozen`].
//! - **Tool.** The tool frame (TCP) is the frame of the link `tool_frame`, or of
//!   [`RobotImportOptions::tool_link`]; its +z axis is the approach direction. Its pose in the
//!   last arm link is [`RobotModel::last_from_tool`]; it must exist
//!   ([`RobotError::MissingToolLink`]).
//! - **Joints.** Axes must be finite and non-zero ([`RobotError::InvalidAxis`]) and are
//!   normalised. `revolute` and `prismatic` limits need `lower <= upper` (no NaN;
//!   [`RobotError::InvalidLimits`]); `continuous` joints have limits `±∞`
//!   ([`ArmJointKind::Continuous`]). Every arm joint needs a finite positive `velocity` limit
//!   ([`RobotError::NonPositiveLimit`]; a missing `<limit>` reads as velocity 0). URDF ≤ 1.1
//!   has no acceleration limits: arm joints get [`DEFAULT_REVOLUTE_ACCELERATION`] (2 rad/s²) or
//!   [`DEFAULT_PRISMATIC_ACCELERATION`] (1 m/s²) unless the `<limit>` carries a URDF 1.2
//!   `acceleration`; replace them with [`RobotModel::with_acceleration_limits`]. `planar` and
//!   `floating` joints elsewhere than from the root, and `spherical` joints, are
//!   [`RobotError::UnsupportedJointType`].
//! - **Frames.** `<origin xyz rpy>` is the child frame in the parent frame, with fixed-axis
//!   roll-pitch-yaw `R = Rz(yaw)·Ry(pitch)·Rx(roll)`; a link's frame is its joint's frame at
//!   value 0. Non-finite numbers are [`RobotError::NonFinite`].
//! - **Collision.** Primitives stay exact (`box`, `cylinder`, `sphere`, `capsule`; positive
//!   sizes, [`RobotError::InvalidShape`]). A `mesh` (STL, OBJ, COLLADA; `scale` applied)
//!   becomes one convex hull per sub-mesh, loaded as the scene importer loads meshes:
//!   `package://NAME/rest` through [`RobotImportOptions::package_paths`], relative paths
//!   against [`RobotImportOptions::base_dir`] (the file's directory for
//!   [`RobotModel::from_urdf_file_with`]); a mesh that cannot be loaded is
//!   [`RobotError::MeshCollision`] with the loader's reason. Visuals, inertials, effort limits, `<dynamics>`,
//!   `<safety_controller>` and anything urdf-rs skips are ignored.
//! - **Self-collision exemptions** ([`RobotModel::allowed_pairs`]). From an SRDF's
//!   `disable_collisions` ([`RobotModel::with_srdf`], which also takes its stowed
//!   `group_state` as the neutral configuration), or computed as setup tools compute them
//!   ([`RobotModel::with_sampled_pairs`]: adjacent links, pairs touching in nearly all random
//!   configurations or at the neutral one, and on request pairs touching in none) and saved with
//!   [`RobotModel::to_srdf`]. A robot loaded from a URDF alone has none, and its
//!   [`RobotCollision`] guesses them from a single pose (adjacent links and the pairs touching
//!   at the neutral configuration).
//! - **Base kind and limits.** URDF has no base description: the base is
//!   [`BaseKind::Holonomic`] with [`DEFAULT_BASE_VELOCITY`] (0.5 m/s in x and y, 1.0 rad/s in
//!   yaw) and [`DEFAULT_BASE_ACCELERATION`] (0.5 m/s², 1.0 rad/s²); its footprint radius is
//!   computed from the collision geometry at [`RobotModel::neutral`]. Replace them with
//!   [`RobotModel::with_base`], e.g. with [`BaseKind::DifferentialDrive`] for TIAGo, Fetch or
//!   Stretch ([`MobileBase::to_differential_drive`] keeps the x limits as the forward limits):
//!   its base paths then turn in place and drive straight, never sideways. A description's
//!   `[base]` sets them too.
//!
//! - **Description file.** A TOML file gathers what the URDF cannot say — the import options,
//!   the SRDF, the stow and the base — and loads the robot in one call:
//!   [`RobotDescription`], [`RobotModel::from_description_file`] (`robots/gen3.toml` is the
//!   shipped robot).
//!
//! No input makes the loader panic: every check above is a typed [`RobotError`].
//!
//! # Example
//! ```
//! use kinscene::kinematics::robot::{RobotConfig, RobotModel};
//! use nalgebra::DVector;
//!
//! let robot = RobotModel::kinova_gen3_mobile();
//! assert_eq!(robot.dof(), 7);
//! let config = RobotConfig { base: [1.0, 2.0, 0.5], arm: robot.neutral() };
//! let poses = robot.link_poses(&config)?;
//! assert_eq!(poses.len(), robot.links().len());
//! let tool = robot.world_from_tool(&config)?;
//! let expected = RobotModel::world_from_base(config.base) * robot.base_from_tool(&config.arm)?;
//! assert!((tool.translation.vector - expected.translation.vector).norm() < 1e-12);
//! # Ok::<(), kinscene::kinematics::robot::RobotError>(())
//! ```

mod collision;
mod description;
mod error;
mod model;
mod pairs;
mod pinocchio;
mod spheres;
mod srdf;
mod stow;
mod urdf;

pub use collision::{
    ContactWalk, Exempt, GROUND_TOP, RobotCollision, SceneAt, SpeedBound, WALK_CONTACT, WalkBase,
    WalkOutcome,
};
pub use description::{ArmDescription, BaseDescription, RobotDescription, ToolDescription};
pub use error::RobotError;
pub use model::{
    ArmJoint, ArmJointKind, BaseKind, DEFAULT_BASE_ACCELERATION, DEFAULT_BASE_VELOCITY,
    DEFAULT_PRISMATIC_ACCELERATION, DEFAULT_REVOLUTE_ACCELERATION, FrozenJoint, MobileBase,
    RobotConfig, RobotImportOptions, RobotLink, RobotModel,
};
pub use pairs::{AllowedPair, ExemptColliders, PairReason, PairSampling};
pub use pinocchio::TOOL_FRAME;
pub use spheres::{
    ArmCheck, ArmCheckData, CELL_SLACK, CONTACT_CLEARANCE, CONTINUOUS_BAND, EdgeScene,
    MAX_CONTINUOUS_STATES, RobotSpheres, SPHERE_SLACK, Sphere, SphereData, SphereObstacles,
    SphereSettings,
};
pub use srdf::{DisabledPair, GroupState, Srdf, SrdfGroup};
pub use stow::StowSearch;
