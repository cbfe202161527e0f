//! The robot's tool pose as CasADi expressions of the base pose and the arm joints.

use kinscene_casadi::Expr;
use nalgebra::{Isometry3, Matrix3, Vector3};

use crate::kinematics::robot::{ArmJoint, ArmJointKind, RobotModel};

/// A rigid transform with symbolic entries: `p ↦ rotation · p + translation`.
#[derive(Debug, Clone)]
pub(crate) struct Frame {
    pub rotation: Matrix3<Expr>,
    pub translation: Vector3<Expr>,
}

/// Entries this close to 0 become exact zeros, so products fold them away (a change of at
/// most 1e-14 in a transform entry, far below the 1e-8 constraint tolerance).
const ZERO: f64 = 1e-14;

fn constant(v: f64) -> Expr {
    Expr::constant(if v.abs() < ZERO { 0.0 } else { v })
}

impl Frame {
    /// A constant transform.
    pub(crate) fn constant(iso: &Isometry3<f64>) -> Frame {
        let r = iso.rotation.to_rotation_matrix().into_inner();
        let t = iso.translation.vector;
        Frame {
            rotation: Matrix3::from_fn(|i, j| constant(r[(i, j)])),
            translation: Vector3::from_fn(|i, _| constant(t[i])),
        }
    }

    /// `self · other`.
    pub(crate) fn then(&self, other: &Frame) -> Frame {
        Frame {
            rotation: &self.rotation * &other.rotation,
            translation: &self.rotation * &other.translation + &self.translation,
        }
    }

    /// The planar base pose `(x, y, yaw)`: [`RobotModel::world_from_base`] in expressions.
    pub(crate) fn planar(x: &Expr, y: &Expr, yaw: &Expr) -> Frame {
        let (c, s) = (yaw.cos(), yaw.sin());
        let zero = Expr::constant(0.0);
        let one = Expr::constant(1.0);
        Frame {
            rotation: Matrix3::new(
                c.clone(),
                -&s,
                zero.clone(),
                s,
                c,
                zero.clone(),
                zero.clone(),
                zero.clone(),
                one,
            ),
            translation: Vector3::new(x.clone(), y.clone(), zero),
        }
    }

    /// The motion of `joint` at value `q` in its joint frame ([`ArmJoint::motion`]): the
    /// Rodrigues rotation `R = cos q · I + sin q · [u]× + (1 − cos q) · u uᵀ` about the unit
    /// axis `u`, or the translation `q · u`.
    pub(crate) fn joint(joint: &ArmJoint, q: &Expr) -> Frame {
        let u = joint.axis.into_inner().map(constant_value);
        match joint.kind {
            ArmJointKind::Revolute | ArmJointKind::Continuous => {
                let (c, s) = (q.cos(), q.sin());
                let versine = 1.0 - &c;
                let cross = [
                    [0.0, -u.z, u.y], //
                    [u.z, 0.0, -u.x],
                    [-u.y, u.x, 0.0],
                ];
                let rotation = Matrix3::from_fn(|i, j| {
                    let diagonal = if i == j {
                        c.clone()
                    } else {
                        Expr::constant(0.0)
                    };
                    diagonal + &s * cross[i][j] + &versine * (u[i] * u[j])
                });
                Frame {
                    rotation,
                    translation: Vector3::from_fn(|_, _| Expr::constant(0.0)),
                }
            }
            ArmJointKind::Prismatic => Frame {
                rotation: Matrix3::identity(),
                translation: Vector3::from_fn(|i, _| q * u[i]),
            },
        }
    }
}

fn constant_value(v: f64) -> f64 {
    if v.abs() < ZERO { 0.0 } else { v }
}

/// `world_from_tool` for base `(x, y, yaw)` and arm joints `q` (one per arm joint):
/// `world_from_base · base_from_arm_root · Π (parent_from_joint_i · motion_i(q_i)) ·
/// last_from_tool`, the same chain as [`RobotModel::world_from_tool`].
pub(crate) fn world_from_tool(robot: &RobotModel, base: &[Expr; 3], q: &[Expr]) -> Frame {
    let mut frame = Frame::planar(&base[0], &base[1], &base[2])
        .then(&Frame::constant(robot.base_from_arm_root()));
    for (joint, qi) in robot.arm_joints().iter().zip(q) {
        frame = frame
            .then(&Frame::constant(&joint.parent_from_joint))
            .then(&Frame::joint(joint, qi));
    }
    frame.then(&Frame::constant(robot.last_from_tool()))
}

#[cfg(test)]
mod tests {
    use kinscene_casadi::Nlp;
    use nalgebra::DVector;

    use super::*;
    use crate::kinematics::robot::RobotConfig;

    /// The expressions, evaluated in Rust at a few configurations, give the robot's own
    /// pure-Rust forward kinematics (an independent implementation of the same chain).
    #[test]
    fn symbolic_tool_pose_matches_the_robot_fk() {
        let robot = RobotModel::kinova_gen3_mobile();
        let mut nlp = Nlp::new();
        let inf = f64::INFINITY;
        let base = [
            nlp.variable("x", -inf, inf).unwrap(),
            nlp.variable("y", -inf, inf).unwrap(),
            nlp.variable("yaw", -inf, inf).unwrap(),
        ];
        let q: Vec<Expr> = (0..robot.dof())
            .map(|i| nlp.variable(&format!("q{i}"), -inf, inf).unwrap())
            .collect();
        let frame = world_from_tool(&robot, &base, &q);
        for (b, arm) in [
            ([0.0, 0.0, 0.0], vec![0.0; 7]),
            ([1.2, -0.4, 2.5], vec![0.3, -1.0, 2.0, 1.5, -0.7, 0.9, -2.8]),
            (
                [-3.0, 0.7, -1.1],
                vec![-2.9, 2.0, -0.4, -2.5, 3.1, -2.0, 0.1],
            ),
        ] {
            let x: Vec<f64> = b.iter().chain(&arm).copied().collect();
            let expected = robot
                .world_from_tool(&RobotConfig {
                    base: b,
                    arm: DVector::from_vec(arm),
                })
                .unwrap();
            let r = expected.rotation.to_rotation_matrix().into_inner();
            for i in 0..3 {
                let t = nlp.eval(&frame.translation[i], &x, &[]).unwrap();
                assert!((t - expected.translation.vector[i]).abs() < 1e-12);
                for j in 0..3 {
                    let v = nlp.eval(&frame.rotation[(i, j)], &x, &[]).unwrap();
                    assert!((v - r[(i, j)]).abs() < 1e-12);
                }
            }
        }
    }
}
