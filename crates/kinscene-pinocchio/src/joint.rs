//! Joints: kinds, limits, indices and what a built model knows about each joint.

use nalgebra::{Isometry3, Unit, Vector3};

use crate::Error;

/// Index of a joint in a [`crate::Model`] (Pinocchio's `JointIndex`). Joint 0 is the universe
/// (the fixed world); joints added by [`crate::ModelBuilder::add_joint`] count from 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct JointIndex(pub usize);

impl JointIndex {
    /// The universe (world) joint, root of every model.
    pub const UNIVERSE: JointIndex = JointIndex(0);
}

/// The motion a joint allows, in the joint's own frame (placed by `parent_from_joint`).
///
/// Axes need not be unit length: they are normalised when the joint is added. An axis equal to
/// a coordinate axis (after normalisation) uses Pinocchio's specialised joint (`RX`, `PZ`,
/// `RUBY`...), any other one the `...Unaligned` variant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointKind {
    /// Rotation about `axis`; q = angle (radians), nq = nv = 1.
    Revolute {
        /// Rotation axis in the joint frame.
        axis: Vector3<f64>,
    },
    /// Continuous rotation about `axis` (no angle wrap-around); q = (cos θ, sin θ), nq = 2,
    /// nv = 1. Use this for joints without position limits (URDF `continuous`).
    RevoluteUnbounded {
        /// Rotation axis in the joint frame.
        axis: Vector3<f64>,
    },
    /// Translation along `axis`; q = displacement (metres), nq = nv = 1.
    Prismatic {
        /// Translation axis in the joint frame.
        axis: Vector3<f64>,
    },
    /// Motion in the joint frame's XY plane (a mobile base): q = (x, y, cos θ, sin θ) in metres
    /// and a unit pair, nq = 4; v = (vx, vy, ω) in the moving frame's axes (m/s, rad/s), nv = 3.
    Planar,
}

impl JointKind {
    /// Number of configuration coordinates.
    pub fn nq(&self) -> usize {
        match self {
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => 1,
            JointKind::RevoluteUnbounded { .. } => 2,
            JointKind::Planar => 4,
        }
    }

    /// Number of velocity coordinates (degrees of freedom).
    pub fn nv(&self) -> usize {
        match self {
            JointKind::Planar => 3,
            _ => 1,
        }
    }

    /// The offset, inside this joint's q block, of a `(cos, sin)` pair that must stay unit.
    pub fn unit_pair_offset(&self) -> Option<usize> {
        match self {
            JointKind::RevoluteUnbounded { .. } => Some(0),
            JointKind::Planar => Some(2),
            _ => None,
        }
    }

    /// The unit axis, if the kind has one.
    pub fn axis(&self) -> Option<Unit<Vector3<f64>>> {
        match self {
            JointKind::Revolute { axis }
            | JointKind::RevoluteUnbounded { axis }
            | JointKind::Prismatic { axis } => Unit::try_new(*axis, 0.0),
            JointKind::Planar => None,
        }
    }

    /// The same kind with its axis normalised; `Err` for a zero or non-finite axis.
    pub(crate) fn normalised(self, joint: &str) -> Result<JointKind, Error> {
        let fix = |axis: Vector3<f64>| {
            let norm = axis.norm();
            if !axis.iter().all(|c| c.is_finite()) || norm < 1e-12 {
                Err(Error::InvalidAxis {
                    joint: joint.to_owned(),
                    axis: [axis.x, axis.y, axis.z],
                })
            } else {
                Ok(axis / norm)
            }
        };
        Ok(match self {
            JointKind::Revolute { axis } => JointKind::Revolute { axis: fix(axis)? },
            JointKind::RevoluteUnbounded { axis } => {
                JointKind::RevoluteUnbounded { axis: fix(axis)? }
            }
            JointKind::Prismatic { axis } => JointKind::Prismatic { axis: fix(axis)? },
            JointKind::Planar => JointKind::Planar,
        })
    }
}

/// Optional limits of one joint. `None` means unlimited.
///
/// Velocity and effort limits are symmetric magnitudes applied to every degree of freedom of
/// the joint. They are stored in the model (and in Pinocchio's) for planners and controllers;
/// the kinematics functions of this crate do not enforce any limit.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointLimits {
    /// `(lower, upper)` position range: radians (revolute) or metres (prismatic). Only for
    /// [`JointKind::Revolute`] and [`JointKind::Prismatic`]; infinite bounds are allowed.
    pub position: Option<(f64, f64)>,
    /// Largest speed, rad/s or m/s.
    pub velocity: Option<f64>,
    /// Largest effort, N m or N.
    pub effort: Option<f64>,
}

impl JointLimits {
    /// No limits at all.
    pub const NONE: JointLimits = JointLimits {
        position: None,
        velocity: None,
        effort: None,
    };

    /// Position limits only.
    pub fn position(lower: f64, upper: f64) -> JointLimits {
        JointLimits {
            position: Some((lower, upper)),
            ..JointLimits::NONE
        }
    }

    /// These limits with a velocity limit.
    pub fn with_velocity(self, velocity: f64) -> JointLimits {
        JointLimits {
            velocity: Some(velocity),
            ..self
        }
    }

    /// These limits with an effort limit.
    pub fn with_effort(self, effort: f64) -> JointLimits {
        JointLimits {
            effort: Some(effort),
            ..self
        }
    }

    /// Checks the limits for a joint of `kind` named `joint`.
    ///
    /// # Errors
    /// [`Error::InvertedLimits`] when `lower > upper` or a bound is NaN,
    /// [`Error::NegativeLimit`] for a negative or NaN velocity/effort limit,
    /// [`Error::LimitsNotSupported`] for position limits on an unbounded or planar joint.
    pub fn validate(&self, joint: &str, kind: &JointKind) -> Result<(), Error> {
        if let Some((lower, upper)) = self.position {
            if kind.nq() != 1 {
                return Err(Error::LimitsNotSupported {
                    joint: joint.to_owned(),
                });
            }
            if lower.is_nan() || upper.is_nan() || lower > upper {
                return Err(Error::InvertedLimits {
                    joint: joint.to_owned(),
                    lower,
                    upper,
                });
            }
        }
        for (what, value) in [("velocity", self.velocity), ("effort", self.effort)] {
            if let Some(value) = value {
                if value.is_nan() || value < 0.0 {
                    return Err(Error::NegativeLimit {
                        joint: joint.to_owned(),
                        what,
                        value,
                    });
                }
            }
        }
        Ok(())
    }
}

/// What a [`crate::Model`] knows about one of its joints.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Unique name (also the name of the joint's frame).
    pub name: String,
    /// Kind, with its axis normalised.
    pub kind: JointKind,
    /// Parent joint.
    pub parent: JointIndex,
    /// Placement of this joint's frame in its parent joint's frame at q = neutral.
    pub parent_from_joint: Isometry3<f64>,
    /// Limits as given.
    pub limits: JointLimits,
    /// First index of this joint's coordinates in q.
    pub idx_q: usize,
    /// First index of this joint's coordinates in v (and Jacobian columns).
    pub idx_v: usize,
    /// The joint's own frame (type `JOINT` in Pinocchio).
    pub frame: crate::FrameIndex,
}

impl Joint {
    /// Number of this joint's configuration coordinates: `q[idx_q..idx_q + nq()]` (2 for a
    /// continuous joint, whose coordinates are `(cos θ, sin θ)`).
    pub fn nq(&self) -> usize {
        self.kind.nq()
    }

    /// Number of this joint's velocity coordinates: `v[idx_v..idx_v + nv()]`.
    pub fn nv(&self) -> usize {
        self.kind.nv()
    }
}
