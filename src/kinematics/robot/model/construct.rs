//! Building a [`RobotModel`]: from URDF text or a file, the shipped robot, and the `with_*`
//! copies with other limits, base or neutral configuration.

use std::path::Path;
use std::sync::Arc;

use nalgebra::DVector;

use super::checks::{check_len, check_positive_limit};
use super::{
    ArmJoint, BaseKind, DEFAULT_BASE_ACCELERATION, DEFAULT_BASE_VELOCITY, MobileBase,
    RobotImportOptions, RobotModel,
};
use crate::InvalidSetting;
use crate::kinematics::robot::urdf::{self, Parsed};
use crate::kinematics::robot::{RobotError, Srdf};

/// The shipped robot's URDF (see `robots/kinova_gen3_mobile.urdf`).
const KINOVA_GEN3_MOBILE_URDF: &str = include_str!("../../../../robots/kinova_gen3_mobile.urdf");

/// The shipped robot's SRDF: its arm group, stowed configuration and self-collision
/// exemptions (see `robots/kinova_gen3_mobile.srdf`).
const KINOVA_GEN3_MOBILE_SRDF: &str = include_str!("../../../../robots/kinova_gen3_mobile.srdf");

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
            .with_srdf(&Srdf::parse(KINOVA_GEN3_MOBILE_SRDF)?)
    }

    fn from_parsed(parsed: Parsed) -> Result<RobotModel, RobotError> {
        let neutral = default_neutral(&parsed.joints);
        let (pinocchio, tool_frame) = crate::kinematics::robot::pinocchio::build(
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
            exempt_colliders: Arc::from(Vec::new()),
            frozen: parsed.frozen,
        };
        robot.base.footprint_radius = robot.footprint_at_neutral();
        Ok(robot)
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
    /// or, for a [`BaseKind::DifferentialDrive`] base, a lateral limit (`max_velocity[1]`,
    /// `max_acceleration[1]`) other than 0; [`RobotError::NonPositiveLimit`] for any other
    /// velocity or acceleration limit that is not finite and positive.
    pub fn with_base(mut self, base: MobileBase) -> Result<RobotModel, RobotError> {
        if !(base.footprint_radius.is_finite() && base.footprint_radius > 0.0) {
            return Err(InvalidSetting::new(
                "footprint_radius",
                base.footprint_radius,
                "finite and > 0",
            )
            .into());
        }
        let axes = match base.kind {
            BaseKind::DifferentialDrive => {
                for (what, limits) in [
                    ("max_velocity[1]", &base.max_velocity),
                    ("max_acceleration[1]", &base.max_acceleration),
                ] {
                    if limits[1] != 0.0 {
                        return Err(InvalidSetting::new(
                            what,
                            limits[1],
                            "0 for a differential-drive base (it cannot move sideways)",
                        )
                        .into());
                    }
                }
                [Some("base forward"), None, Some("base yaw")]
            }
            _ => [Some("base x"), Some("base y"), Some("base yaw")],
        };
        for (axis, (&v, &a)) in axes
            .iter()
            .zip(base.max_velocity.iter().zip(&base.max_acceleration))
        {
            if let Some(axis) = axis {
                check_positive_limit(axis, "velocity", v)?;
                check_positive_limit(axis, "acceleration", a)?;
            }
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
}

/// The default neutral configuration: 0 clamped into each joint's limits.
fn default_neutral(joints: &[ArmJoint]) -> DVector<f64> {
    DVector::from_iterator(
        joints.len(),
        joints.iter().map(|j| 0.0_f64.clamp(j.lower, j.upper)),
    )
}
