//! Shared models and helpers.

use kinscene_pinocchio::{FrameIndex, JointIndex, JointKind, JointLimits, Model, ModelBuilder};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// `parent_from_child` from a translation (m) and roll/pitch/yaw (rad).
pub fn pose(x: f64, y: f64, z: f64, roll: f64, pitch: f64, yaw: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}

/// Largest entry-wise difference of translations and rotation matrices.
pub fn pose_error(a: &Isometry3<f64>, b: &Isometry3<f64>) -> f64 {
    let dt = (a.translation.vector - b.translation.vector).amax();
    let dr = (a.rotation.to_rotation_matrix().matrix() - b.rotation.to_rotation_matrix().matrix())
        .amax();
    dt.max(dr)
}

/// The 3-link arm of the FK test, with the constants its hand-derived chain uses.
pub struct Arm {
    pub model: Model,
    pub tool: FrameIndex,
}

pub const P1: [f64; 6] = [0.0, 0.0, 0.3, 0.0, 0.0, 0.0];
pub const P2: [f64; 6] = [0.1, 0.0, 0.4, 0.3, 0.0, 0.0];
pub const P3: [f64; 6] = [0.5, 0.05, 0.0, 0.0, 0.0, -0.2];
pub const TOOL: [f64; 6] = [0.2, 0.0, 0.1, 0.0, 0.5, 0.0];

pub fn iso(p: [f64; 6]) -> Isometry3<f64> {
    pose(p[0], p[1], p[2], p[3], p[4], p[5])
}

/// Revolute Z, revolute Y (its frame rolled by 0.3 rad), prismatic X (yawed by -0.2 rad), and
/// a tool frame.
pub fn three_link_arm() -> Arm {
    let mut b = ModelBuilder::new();
    let j1 = b
        .add_joint(
            "j1",
            JointIndex::UNIVERSE,
            iso(P1),
            JointKind::Revolute { axis: Vector3::z() },
            JointLimits::position(-3.0, 3.0),
        )
        .unwrap();
    let j2 = b
        .add_joint(
            "j2",
            j1,
            iso(P2),
            JointKind::Revolute { axis: Vector3::y() },
            JointLimits::NONE,
        )
        .unwrap();
    let j3 = b
        .add_joint(
            "j3",
            j2,
            iso(P3),
            JointKind::Prismatic { axis: Vector3::x() },
            JointLimits::position(0.0, 0.5),
        )
        .unwrap();
    let tool = b.add_frame("tool", j3, iso(TOOL)).unwrap();
    Arm {
        model: b.build().unwrap(),
        tool,
    }
}

/// One of every joint kind, with unaligned axes, for Jacobian and configuration tests:
/// planar base, revolute Z, unbounded revolute about (1, 2, 2)/3, revolute Y, prismatic along
/// (0, 1, 1)/√2, and a tool frame.
pub fn mixed_model() -> (Model, FrameIndex) {
    let mut b = ModelBuilder::new();
    let base = b
        .add_joint(
            "base",
            JointIndex::UNIVERSE,
            Isometry3::identity(),
            JointKind::Planar,
            JointLimits::NONE,
        )
        .unwrap();
    let j1 = b
        .add_joint(
            "j1",
            base,
            pose(0.1, 0.0, 0.5, 0.0, 0.0, 0.0),
            JointKind::Revolute { axis: Vector3::z() },
            JointLimits::NONE,
        )
        .unwrap();
    let j2 = b
        .add_joint(
            "j2",
            j1,
            pose(0.0, 0.1, 0.3, 0.2, 0.0, 0.0),
            JointKind::RevoluteUnbounded {
                axis: Vector3::new(1.0, 2.0, 2.0),
            },
            JointLimits::NONE,
        )
        .unwrap();
    let j3 = b
        .add_joint(
            "j3",
            j2,
            pose(0.4, 0.0, 0.0, 0.0, 0.3, 0.1),
            JointKind::Revolute { axis: Vector3::y() },
            JointLimits::NONE,
        )
        .unwrap();
    let j4 = b
        .add_joint(
            "j4",
            j3,
            pose(0.3, 0.0, 0.0, 0.0, 0.0, 0.0),
            JointKind::Prismatic {
                axis: Vector3::new(0.0, 1.0, 1.0),
            },
            JointLimits::NONE,
        )
        .unwrap();
    let tool = b
        .add_frame("tool", j4, pose(0.1, 0.05, 0.0, 0.4, -0.3, 0.2))
        .unwrap();
    (b.build().unwrap(), tool)
}

/// A configuration of [`mixed_model`]: base (x, y, θ), j1, j2 (angle), j3, j4.
pub fn mixed_q(base: [f64; 3], j1: f64, j2: f64, j3: f64, j4: f64) -> nalgebra::DVector<f64> {
    nalgebra::DVector::from_vec(vec![
        base[0],
        base[1],
        base[2].cos(),
        base[2].sin(),
        j1,
        j2.cos(),
        j2.sin(),
        j3,
        j4,
    ])
}
