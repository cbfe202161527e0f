//! Joints (the edges E): kind, axis, origin and limits.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use super::Error;
use super::validate::{check_finite, check_isometry, renormalized, unit_direction};

/// The kind of a one-degree-of-freedom joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum JointKind {
    /// Rotation about the axis; values in radians.
    Revolute,
    /// Translation along the axis; values in metres.
    Prismatic,
}

impl JointKind {
    /// The URDF joint type: `revolute` or `prismatic` (also its `Display`).
    ///
    /// ```
    /// use kinscene::scene::JointKind;
    /// assert_eq!(JointKind::Prismatic.as_str(), "prismatic");
    /// assert_eq!(JointKind::Revolute.to_string(), "revolute");
    /// ```
    pub fn as_str(self) -> &'static str {
        match self {
            JointKind::Revolute => "revolute",
            JointKind::Prismatic => "prismatic",
        }
    }
}

impl std::fmt::Display for JointKind {
    /// The URDF joint type ([`JointKind::as_str`]).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Joint limits, `lower <= upper`, in radians (revolute) or metres (prismatic).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    /// Lowest allowed value.
    pub lower: f64,
    /// Highest allowed value.
    pub upper: f64,
}

impl Limits {
    /// Limits `[lower, upper]` (validated when the model is built).
    pub fn new(lower: f64, upper: f64) -> Self {
        Limits { lower, upper }
    }

    /// Whether `lower <= value <= upper` (false for NaN).
    pub fn contains(&self, value: f64) -> bool {
        self.lower <= value && value <= self.upper
    }

    /// `value` clamped into `[lower, upper]`. NaN stays NaN.
    pub fn clamp(&self, value: f64) -> f64 {
        value.max(self.lower).min(self.upper)
    }
}

/// A joint: connects a part (the child) to its parent, as a URDF `<joint>` does.
///
/// Frames follow URDF: the joint frame sits at `parent_from_joint` in the parent frame (URDF
/// `origin`); the child part frame coincides with the joint frame at value 0 and is moved by
/// [`Joint::joint_from_child`] otherwise (rotation about / translation along `axis`, expressed
/// in the joint frame). The paper's pivot `q` of a revolute joint is the joint-frame origin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Joint {
    /// Unique joint name.
    pub name: String,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Direction of the axis in the joint frame. Normalised by the builder; in a built model
    /// it has unit norm.
    pub axis: Vector3<f64>,
    /// Pose of the joint frame in the parent frame (the parent part's frame, or the world
    /// frame for a part on the base).
    pub parent_from_joint: Isometry3<f64>,
    /// Range of allowed values (rad or m).
    pub limits: Limits,
    /// URDF `continuous`: a revolute joint without mechanical stops. The limits still bound
    /// the values a [`State`](crate::scene::State) may hold (an importer chooses a working
    /// range, e.g. `[-π, π]`); the flag records the joint type for export. Must be false for
    /// prismatic joints.
    pub continuous: bool,
}

impl Joint {
    /// A joint with the given frame, axis and limits.
    pub fn new(
        name: impl Into<String>,
        kind: JointKind,
        parent_from_joint: Isometry3<f64>,
        axis: Vector3<f64>,
        limits: Limits,
    ) -> Self {
        Joint {
            name: name.into(),
            kind,
            axis,
            parent_from_joint,
            limits,
            continuous: false,
        }
    }

    /// A revolute joint in the paper's parameters: pivot `q` and axis `u`, both in the parent
    /// frame (the joint frame is the parent frame translated to `q`).
    pub fn revolute(
        name: impl Into<String>,
        pivot: Point3<f64>,
        axis: Vector3<f64>,
        limits: Limits,
    ) -> Self {
        let origin =
            Isometry3::from_parts(Translation3::from(pivot.coords), UnitQuaternion::identity());
        Joint::new(name, JointKind::Revolute, origin, axis, limits)
    }

    /// A prismatic joint whose frame is the parent frame translated to `origin`, sliding along
    /// `axis` (parent frame).
    pub fn prismatic(
        name: impl Into<String>,
        origin: Point3<f64>,
        axis: Vector3<f64>,
        limits: Limits,
    ) -> Self {
        let origin = Isometry3::from_parts(
            Translation3::from(origin.coords),
            UnitQuaternion::identity(),
        );
        Joint::new(name, JointKind::Prismatic, origin, axis, limits)
    }

    /// The joint motion at `value`: the pose of the child part frame in the joint frame.
    /// A rotation by `value` rad about `axis` (revolute) or a translation by `value` m along it
    /// (prismatic). Assumes a unit axis (true in a built model).
    pub fn joint_from_child(&self, value: f64) -> Isometry3<f64> {
        match self.kind {
            JointKind::Revolute => Isometry3::rotation(self.axis * value),
            JointKind::Prismatic => Isometry3::translation(
                self.axis.x * value,
                self.axis.y * value,
                self.axis.z * value,
            ),
        }
    }

    /// `parent_from_joint · joint_from_child(value)`: the child part frame in the parent frame.
    pub fn parent_from_child(&self, value: f64) -> Isometry3<f64> {
        self.parent_from_joint * self.joint_from_child(value)
    }

    /// Validates and returns the joint with a unit axis and a renormalised origin.
    pub(crate) fn validated(&self) -> Result<Joint, Error> {
        let name = &self.name;
        let axis = unit_direction(
            &self.axis,
            || format!("joint {name:?} axis"),
            || Error::ZeroAxis {
                joint: name.clone(),
            },
        )?;
        check_isometry(&self.parent_from_joint, &format!("joint {name:?} origin"))?;
        let Limits { lower, upper } = self.limits;
        check_finite([lower, upper], || format!("joint {name:?} limits"))?;
        if lower > upper {
            return Err(Error::InvalidLimits {
                joint: name.clone(),
                lower,
                upper,
            });
        }
        if self.continuous && self.kind == JointKind::Prismatic {
            return Err(Error::ContinuousPrismatic {
                joint: name.clone(),
            });
        }
        Ok(Joint {
            axis: axis.into_inner(),
            parent_from_joint: renormalized(&self.parent_from_joint),
            ..self.clone()
        })
    }
}
