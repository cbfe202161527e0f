//! Frame Jacobians against central finite differences of the frame pose.
//!
//! Column i of the finite-difference Jacobian perturbs q along tangent direction e_i with
//! `integrate(q, ±h e_i)` (the planar and unbounded joints have nq ≠ nv; for the other joints
//! this is plain q ± h). With p(t), R(t) the frame's world position and rotation,
//! ṗ ≈ (p₊ − p₋)/2h and Ṙ ≈ (R₊ − R₋)/2h, and each reference frame means:
//! - LOCAL (body twist T⁻¹Ṫ): v = Rᵀṗ, ω = vee(RᵀṘ);
//! - WORLD (spatial twist ṪT⁻¹): ω = vee(ṘRᵀ), v = ṗ − ω × p (velocity of the body point at
//!   the world origin);
//! - LOCAL_WORLD_ALIGNED: v = ṗ, ω = vee(ṘRᵀ).
//!
//! h = 1e-6 and tolerance 1e-6: central differences err by h²/6·|f'''| ≈ 1e-12 (derivatives are
//! O(1) for a metre-scale arm) plus rounding ≈ ε·|f|/h ≈ 2e-10, so the true error is below 1e-9;
//! 1e-6 keeps a 1000× margin, while a wrong column, sign or reference frame is off by O(0.1).

use kinscene_pinocchio::{
    Data, FrameIndex, Model, ReferenceFrame, forward_kinematics, frame_jacobian, frame_placement,
    frame_placement_and_jacobian, integrate,
};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};

use crate::support::{mixed_model, mixed_q, three_link_arm};

const H: f64 = 1e-6;
const TOL: f64 = 1e-6;

fn vee(m: &Matrix3<f64>) -> Vector3<f64> {
    // Skew part only: the symmetric part of the difference quotient is O(h²) noise.
    let s = (m - m.transpose()) * 0.5;
    Vector3::new(s[(2, 1)], s[(0, 2)], s[(1, 0)])
}

fn finite_difference_jacobian(
    model: &Model,
    data: &mut Data,
    q: &DVector<f64>,
    frame: FrameIndex,
    reference: ReferenceFrame,
) -> DMatrix<f64> {
    forward_kinematics(model, data, q).unwrap();
    let at = frame_placement(model, data, frame).unwrap();
    let (r, p) = (
        at.rotation.to_rotation_matrix().into_inner(),
        at.translation.vector,
    );
    let mut jacobian = DMatrix::zeros(6, model.nv());
    for i in 0..model.nv() {
        let mut pose_at = |sign: f64| {
            let mut v = DVector::zeros(model.nv());
            v[i] = sign * H;
            forward_kinematics(model, data, &integrate(model, q, &v).unwrap()).unwrap();
            frame_placement(model, data, frame).unwrap()
        };
        let (plus, minus) = (pose_at(1.0), pose_at(-1.0));
        let p_dot = (plus.translation.vector - minus.translation.vector) / (2.0 * H);
        let r_dot = (plus.rotation.to_rotation_matrix().into_inner()
            - minus.rotation.to_rotation_matrix().into_inner())
            / (2.0 * H);
        let omega_world = vee(&(r_dot * r.transpose()));
        let (linear, angular) = match reference {
            ReferenceFrame::Local => (r.transpose() * p_dot, vee(&(r.transpose() * r_dot))),
            ReferenceFrame::World => (p_dot - omega_world.cross(&p), omega_world),
            ReferenceFrame::LocalWorldAligned => (p_dot, omega_world),
        };
        let column = Vector6::new(
            linear.x, linear.y, linear.z, angular.x, angular.y, angular.z,
        );
        jacobian.set_column(i, &column);
    }
    jacobian
}

fn check(model: &Model, q: &DVector<f64>, frame: FrameIndex) {
    let mut data = Data::new(model).unwrap();
    for reference in ReferenceFrame::ALL {
        let expected = finite_difference_jacobian(model, &mut data, q, frame, reference);
        let got = frame_jacobian(model, &mut data, q, frame, reference).unwrap();
        assert_eq!(got.shape(), (6, model.nv()));
        let error = (&got - &expected).amax();
        assert!(
            error < TOL,
            "{reference:?}: error {error}\n got {got}\n fd {expected}"
        );
        // Not a vacuous comparison: the Jacobian has O(0.1..1) entries.
        assert!(got.amax() > 0.1);
    }
}

#[test]
fn three_link_arm_jacobian_matches_finite_differences() {
    let arm = three_link_arm();
    for q in [[0.3, -0.4, 0.2], [2.0, 1.0, 0.45]] {
        check(&arm.model, &DVector::from_row_slice(&q), arm.tool);
    }
}

#[test]
fn mixed_joints_jacobian_matches_finite_differences() {
    let (model, tool) = mixed_model();
    check(
        &model,
        &mixed_q([0.5, -1.0, 0.8], 0.3, 2.9, -0.7, 0.15),
        tool,
    );
    check(
        &model,
        &mixed_q([-2.0, 0.3, -2.5], -1.2, -3.0, 1.1, -0.3),
        tool,
    );
}

#[test]
fn columns_of_joints_not_supporting_the_frame_are_zero() {
    // The base joint's frame is moved by the base only: columns 3.. are exactly zero.
    let (model, _) = mixed_model();
    let base_frame = model.frame_index("base").unwrap();
    let mut data = Data::new(&model).unwrap();
    let q = mixed_q([0.5, -1.0, 0.8], 0.3, 2.9, -0.7, 0.15);
    let j = frame_jacobian(&model, &mut data, &q, base_frame, ReferenceFrame::World).unwrap();
    assert!(j.columns(3, model.nv() - 3).iter().all(|&x| x == 0.0));
    assert!(j.columns(0, 3).amax() > 0.5);
}

/// The one-pass placement and Jacobian equal the separate calls (the full forward pass, the
/// placement, then `frame_jacobian`) to rounding: the same Pinocchio arithmetic on the
/// support, so 1e-12 (the Jacobian's entries are O(1)).
#[test]
fn placement_and_jacobian_in_one_pass_match_the_separate_calls() {
    let (model, tool) = mixed_model();
    let mut data = Data::new(&model).unwrap();
    let mut jacobian = DMatrix::zeros(6, model.nv());
    for q in [
        mixed_q([0.5, -1.0, 0.8], 0.3, 2.9, -0.7, 0.15),
        mixed_q([-2.0, 0.3, -2.5], -1.2, -3.0, 1.1, -0.3),
    ] {
        forward_kinematics(&model, &mut data, &q).unwrap();
        let expected_pose = frame_placement(&model, &data, tool).unwrap();
        let expected = frame_jacobian(
            &model,
            &mut data,
            &q,
            tool,
            ReferenceFrame::LocalWorldAligned,
        )
        .unwrap();
        // A different configuration first, so stale placements would show.
        let other = mixed_q([0.1, 0.2, 0.3], 0.0, 0.5, 0.5, 0.0);
        forward_kinematics(&model, &mut data, &other).unwrap();
        let pose =
            frame_placement_and_jacobian(&model, &mut data, &q, tool, &mut jacobian).unwrap();
        assert!((pose.translation.vector - expected_pose.translation.vector).amax() < 1e-12);
        assert!(pose.rotation.angle_to(&expected_pose.rotation) < 1e-12);
        assert!(
            (&jacobian - &expected).amax() < 1e-12,
            "{jacobian}\n{expected}"
        );
        assert!(expected.amax() > 0.1);
    }
    let mut wrong = DMatrix::zeros(6, model.nv() + 1);
    let q = mixed_q([0.5, -1.0, 0.8], 0.3, 2.9, -0.7, 0.15);
    assert!(matches!(
        frame_placement_and_jacobian(&model, &mut data, &q, tool, &mut wrong),
        Err(kinscene_pinocchio::Error::DimensionMismatch { .. })
    ));
}
