//! The mobile base in the URDF: the root link, or the link that a `planar`/`floating` joint or
//! a chain of x, y and yaw joints carries from the root (a `world`/`odom` link).

use nalgebra::{Isometry3, Translation3, Vector3};
use urdf_rs::JointType;

use super::tree::Tree;

/// Largest deviation (of a unit axis component, of an origin coordinate in m or rad) still read
/// as the exact value of a base joint's axis or identity origin.
const BASE_JOINT_TOLERANCE: f64 = 1e-9;

/// The base link and where its frame lies in the base frame.
pub(super) struct BaseLink {
    /// The base link (index in `robot.links`).
    pub(super) link: usize,
    /// The base link's frame in the base frame: the identity, or a lift by the z offsets of
    /// the skipped x/y/yaw joints' origins.
    pub(super) base_from_link: Isometry3<f64>,
}

/// The planar coordinate a base joint moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum BaseAxis {
    X,
    Y,
    Yaw,
}

impl Tree {
    /// The base link: the child of a `planar` or `floating` joint that is the root's only
    /// joint; else the child of the last joint of an x/y/yaw chain from the root (see
    /// [`Tree::planar_chain`]); else the root link itself.
    pub(super) fn base_link(&self, robot: &urdf_rs::Robot) -> BaseLink {
        match self.child_joints[self.root].as_slice() {
            [j] if matches!(
                robot.joints[*j].joint_type,
                JointType::Planar | JointType::Floating
            ) =>
            {
                BaseLink {
                    link: self.ends[*j].1,
                    base_from_link: Isometry3::identity(),
                }
            }
            _ => self.planar_chain(robot).unwrap_or(BaseLink {
                link: self.root,
                base_from_link: Isometry3::identity(),
            }),
        }
    }

    /// The base modelled as joints, recognised by structure, not by name: three joints in a
    /// chain from the root link, each the only joint of its parent link — a `prismatic` joint
    /// along +x and one along +y (in either order), then a `revolute` or `continuous` joint
    /// about +z — each with an origin that is the identity or a pure z offset. Such a chain
    /// moves its last child exactly as [`RobotModel::world_from_base`] moves the base frame
    /// (translations along world x and y, then the yaw), lifted by the offsets' sum, which
    /// commutes with the planar motion.
    ///
    /// [`RobotModel::world_from_base`]: crate::kinematics::robot::RobotModel::world_from_base
    fn planar_chain(&self, robot: &urdf_rs::Robot) -> Option<BaseLink> {
        let mut at = self.root;
        let mut seen = Vec::with_capacity(3);
        let mut height = 0.0;
        for step in 0..3 {
            let [j] = self.child_joints[at].as_slice() else {
                return None;
            };
            let joint = &robot.joints[*j];
            let axis = base_axis(joint)?;
            if seen.contains(&axis) || (axis == BaseAxis::Yaw) != (step == 2) {
                return None;
            }
            seen.push(axis);
            height += z_offset(&joint.origin)?;
            at = self.ends[*j].1;
        }
        Some(BaseLink {
            link: at,
            base_from_link: Translation3::new(0.0, 0.0, height).into(),
        })
    }
}

/// The planar coordinate a joint moves if it is one of the base's: prismatic along +x or +y,
/// revolute or continuous about +z (axes normalised; any other axis, sign or type is not).
fn base_axis(joint: &urdf_rs::Joint) -> Option<BaseAxis> {
    let axis = Vector3::from(*joint.axis.xyz);
    if !axis.iter().all(|c| c.is_finite()) {
        return None;
    }
    let axis = axis.try_normalize(1e-12)?;
    let along = |unit: Vector3<f64>| (axis - unit).amax() <= BASE_JOINT_TOLERANCE;
    match joint.joint_type {
        JointType::Prismatic if along(Vector3::x()) => Some(BaseAxis::X),
        JointType::Prismatic if along(Vector3::y()) => Some(BaseAxis::Y),
        JointType::Revolute | JointType::Continuous if along(Vector3::z()) => Some(BaseAxis::Yaw),
        _ => None,
    }
}

/// The z offset of an origin that is the identity or a pure z translation.
fn z_offset(origin: &urdf_rs::Pose) -> Option<f64> {
    let z = origin.xyz[2];
    let rest = [
        origin.xyz[0],
        origin.xyz[1],
        origin.rpy[0],
        origin.rpy[1],
        origin.rpy[2],
    ];
    (z.is_finite() && rest.iter().all(|c| c.abs() <= BASE_JOINT_TOLERANCE)).then_some(z)
}
