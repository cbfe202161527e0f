//! The arm's reach bound ([`ArmReach`]) the planner hands to the task layer, from the robot
//! model's geometry.

use nalgebra::{Isometry3, Point3, Vector3};

use crate::kinematics::robot::{ArmJointKind, RobotModel};
use crate::task::ArmReach;

/// Configurations sampled to find the joint origins that are fixed in the tool frame.
const SAMPLES: usize = 16;

/// Largest movement (m) in the tool frame over the samples of a joint origin taken as the
/// wrist point; twice the movement seen is added to the bound's slack. URDFs round their
/// angles (3.1416 for π), which leaves a point on an axis a fraction of a millimetre off it.
const FIXED: f64 = 1e-3;

/// Largest tilt (rad) of a first joint axis taken as vertical; the shoulder height's change
/// it allows is added to the slack.
const TILT: f64 = 1e-3;

/// The reach bound of `robot`'s arm with the grasp's tool origin up to `standoff_max` (m) out
/// from the grasp point along the handle's normal.
///
/// Let `P_k` be the origin of arm joint `k`'s frame (fixed in the previous link's frame, so
/// consecutive origins stay a fixed distance apart; a prismatic joint adds its travel).
/// - **Shoulder**: `P_1`, or, when joint 1 is revolute about a vertical axis, `P_2`: it keeps
///   its height and stays within its distance from that axis (`shoulder_radius`).
/// - **Wrist**: the first `P_k` fixed in the tool frame (within 1 mm) whatever the joints do (the last
///   joint's origin always is; on an arm whose last axes meet, an earlier one: for the Gen3,
///   joint 6's origin on joint 7's axis). Found by forward kinematics at 16 seeded
///   configurations.
/// - Twice the wrist point's movement over the samples, and the height change a slightly tilted
///   first axis allows, are added to `wrist_radius` (the bound's slack).
/// - **Radius**: the sum of the distances between consecutive origins from the shoulder to the
///   wrist, plus the travel of the prismatic joints between them.
pub fn arm_reach(robot: &RobotModel, standoff_max: f64) -> ArmReach {
    let joints = robot.arm_joints();
    let n = joints.len();
    let root = *robot.base_from_arm_root();
    // Origins P_1..P_n (index 0..n) and the tool, at configuration `q`, in the base frame.
    let frames = |q: &[f64]| {
        let mut origins = Vec::with_capacity(n);
        let mut link = root;
        for (j, v) in joints.iter().zip(q) {
            let frame = link * j.parent_from_joint;
            origins.push(frame * Point3::origin());
            link = frame * j.motion(*v);
        }
        (origins, link * robot.last_from_tool())
    };
    let travel = |k: usize| match joints[k].kind {
        ArmJointKind::Prismatic => joints[k].lower.abs().max(joints[k].upper.abs()),
        _ => 0.0,
    };
    // The wrist: the first origin at the same place in the tool frame at every sample.
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut uniform = move || {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let samples: Vec<Vec<f64>> = (0..SAMPLES)
        .map(|_| {
            joints
                .iter()
                .map(|j| {
                    let (lo, hi) = (
                        j.lower.max(-std::f64::consts::PI),
                        j.upper.min(std::f64::consts::PI),
                    );
                    lo + (hi - lo) * uniform()
                })
                .collect()
        })
        .collect();
    let in_tool: Vec<Vec<Point3<f64>>> = samples
        .iter()
        .map(|q| {
            let (origins, tool) = frames(q);
            let tool_from_base: Isometry3<f64> = tool.inverse();
            origins.iter().map(|p| tool_from_base * p).collect()
        })
        .collect();
    let movement = |k: usize| {
        in_tool
            .iter()
            .map(|o| (o[k] - in_tool[0][k]).norm())
            .fold(0.0, f64::max)
    };
    let first_fixed = (0..n).find(|&k| movement(k) <= FIXED);
    let (origins, _) = frames(&vec![0.0; n]);
    // The shoulder.
    let axis1 =
        root.rotation * (joints[0].parent_from_joint.rotation * joints[0].axis.into_inner());
    let tilt = axis1.cross(&Vector3::z()).norm();
    let vertical = joints[0].kind != ArmJointKind::Prismatic && n >= 2 && tilt <= TILT;
    let (start, shoulder, shoulder_radius, height_slack) = if vertical {
        let p2 = origins[1];
        let radius = (p2.x - origins[0].x).hypot(p2.y - origins[0].y);
        // Turning about an axis tilted by `tilt` moves P_2's height by at most this.
        let slack = 2.0 * (p2 - origins[0]).norm() * tilt;
        (
            1,
            Point3::new(origins[0].x, origins[0].y, p2.z),
            radius,
            slack,
        )
    } else {
        (0, origins[0], 0.0, 0.0)
    };
    let wrist = first_fixed.filter(|&w| w > start).unwrap_or(n - 1);
    // A one-joint "arm" spans nothing; keep the bound valid (radius > 0).
    let radius = (start..wrist)
        .map(|k| joints[k + 1].parent_from_joint.translation.vector.norm() + travel(k))
        .sum::<f64>()
        .max(1e-9);
    let point = in_tool[0][wrist];
    let out = -point.z;
    let slack = 2.0 * movement(wrist) + height_slack;
    ArmReach {
        shoulder: [shoulder.x, shoulder.y, shoulder.z],
        shoulder_radius,
        radius,
        wrist_out: [out, out + standoff_max.max(0.0)],
        wrist_radius: point.x.hypot(point.y) + slack,
    }
}
