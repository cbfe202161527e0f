//! The lever arms that bound how fast the robot's points move for given joint speeds
//! ([`levers`]), shared by the arm check's spans and the robot's speed bounds.

use crate::kinematics::robot::{ArmJoint, ArmJointKind, RobotModel};

/// The farthest any point of `spheres` (a link's, in its frame) is from the link's origin:
/// the largest `|c| + r` (0 without spheres).
pub(crate) fn reach(spheres: &[super::Sphere]) -> f64 {
    spheres
        .iter()
        .map(|s| s.center.coords.norm() + s.radius)
        .fold(0.0, f64::max)
}

/// The most a link's origin can be from its parent link's origin through arm joint `j`: the
/// joint's fixed offset, plus a prismatic joint's largest travel.
pub(crate) fn chain_step(j: &ArmJoint) -> f64 {
    let travel = match j.kind {
        ArmJointKind::Prismatic => j.lower.abs().max(j.upper.abs()),
        _ => 0.0,
    };
    j.parent_from_joint.translation.vector.norm() + travel
}

/// For links `i < k`: the arm joints `j` with `i <= j < k` (those that move link `k` but not
/// link `i`; joint `j` moves links `j + 1 ..`) with lever arm `λ_j`, so that along a straight
/// motion with joint displacements `Δq`, no point of link `k` moves relative to link `i` by
/// more than `Σ_j |Δq_j|·λ_j` per unit of the motion's parameter. Revolute `j`: `λ_j` bounds
/// the distance from the joint's axis to any point of link `k`: for the last joint
/// (`j = k − 1`, link `k`'s origin on its axis, the axis fixed in link `k`'s frame) the
/// largest distance `|c⊥| + r` of link `k`'s spheres from the axis (`c⊥`: the centre's
/// component normal to it); for an earlier one the offsets from link `j + 1`'s origin (on the
/// axis) down the chain to link `k`'s origin (a prismatic joint in between adding its largest
/// travel), plus the largest `|c| + r` of link `k`'s spheres. The spheres contain the link's
/// shapes. Prismatic `j`: `λ_j = 1`. The relative velocity is `Σ_j q̇_j·(ω_j × (p − o_j))`
/// (revolute) `+ Σ_j q̇_j·v_j` (prismatic), whose norm is at most that sum.
/// `links`: the sphere covers, per link (as [`RobotSpheres::links`]).
pub(crate) fn levers(
    robot: &RobotModel,
    links: &[Vec<super::Sphere>],
    i: usize,
    k: usize,
) -> Vec<(usize, f64)> {
    let joints = robot.arm_joints();
    let reach = links.get(k).map_or(0.0, |l| reach(l));
    (i..k.min(joints.len()))
        .map(|j| {
            let lever = match joints[j].kind {
                ArmJointKind::Prismatic => 1.0,
                _ if j + 1 == k => {
                    // Link k's frame is the joint's frame turned about the axis: the axis has
                    // the same components in it and passes through its origin.
                    let axis = joints[j].axis;
                    links.get(k).map_or(0.0, |l| {
                        l.iter()
                            .map(|s| {
                                let c = s.center.coords;
                                (c - axis.into_inner() * c.dot(&axis)).norm() + s.radius
                            })
                            .fold(0.0, f64::max)
                    })
                }
                _ => {
                    joints
                        .get(j + 1..k)
                        .unwrap_or(&[])
                        .iter()
                        .map(chain_step)
                        .sum::<f64>()
                        + reach
                }
            };
            (j, lever)
        })
        .collect()
}
