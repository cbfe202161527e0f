//! Planar and unbounded joints: nq ≠ nv, integrate/difference, neutral, normalisation.

use std::f64::consts::PI;

use kinscene_pinocchio::{
    Data, Error, JointIndex, JointKind, JointLimits, Model, ModelBuilder, check_configuration,
    difference, forward_kinematics, frame_placement, integrate, normalize,
};
use nalgebra::{DVector, Isometry3, Matrix2, Vector2, Vector3};

use crate::support::{mixed_model, mixed_q, pose, pose_error};

/// Round trips and closed forms involve a handful of trigonometric evaluations and products of
/// O(1) numbers: errors are a few 1e-16, so 1e-12 is safe and still tight.
const TOL: f64 = 1e-12;

fn planar_model() -> Model {
    let mut b = ModelBuilder::new();
    b.add_joint(
        "base",
        JointIndex::UNIVERSE,
        Isometry3::identity(),
        JointKind::Planar,
        JointLimits::NONE,
    )
    .unwrap();
    b.build().unwrap()
}

fn planar_q(x: f64, y: f64, theta: f64) -> DVector<f64> {
    DVector::from_vec(vec![x, y, theta.cos(), theta.sin()])
}

#[test]
fn planar_joint_sizes_and_neutral() {
    let model = planar_model();
    assert_eq!((model.nq(), model.nv()), (4, 3));
    assert_eq!(model.neutral().as_slice(), &[0.0, 0.0, 1.0, 0.0]);
    // The Rust-side layout of q (x, y, cos, sin) is Pinocchio's.
    assert_eq!(model.pinocchio_neutral().unwrap(), model.neutral());
}

#[test]
fn planar_integrate_matches_the_se2_exponential() {
    // q ⊕ v = (p + R(θ) V(ω) (vx, vy), θ + ω), V(ω) = [[sin ω, −(1 − cos ω)], [1 − cos ω, sin ω]] / ω:
    // the SE(2) exponential of the body-frame twist v, composed on the right of q.
    let model = planar_model();
    let (x, y, theta): (f64, f64, f64) = (0.3, -0.2, 0.7);
    let q = planar_q(x, y, theta);
    let rot = |a: f64| Matrix2::new(a.cos(), -a.sin(), a.sin(), a.cos());
    for (vx, vy, w) in [
        (0.4_f64, -0.1_f64, 0.9_f64),
        (0.0, 0.0, -2.0),
        (1.0, 0.5, 0.0),
    ] {
        let local = if w == 0.0 {
            Vector2::new(vx, vy)
        } else {
            Matrix2::new(w.sin(), -(1.0 - w.cos()), 1.0 - w.cos(), w.sin()) / w
                * Vector2::new(vx, vy)
        };
        let p = Vector2::new(x, y) + rot(theta) * local;
        let expected = planar_q(p.x, p.y, theta + w);
        let got = integrate(&model, &q, &DVector::from_vec(vec![vx, vy, w])).unwrap();
        assert!(
            (&got - &expected).amax() < TOL,
            "v = ({vx}, {vy}, {w}): {got} vs {expected}"
        );
    }
    // Pure rotation leaves the position alone; pure translation moves along the heading.
    let spun = integrate(&model, &q, &DVector::from_vec(vec![0.0, 0.0, 1.3])).unwrap();
    assert!((spun[0] - x).abs() < TOL && (spun[1] - y).abs() < TOL);
    let moved = integrate(&model, &q, &DVector::from_vec(vec![2.0, 0.0, 0.0])).unwrap();
    assert!((moved[0] - (x + 2.0 * theta.cos())).abs() < TOL);
    assert!((moved[1] - (y + 2.0 * theta.sin())).abs() < TOL);
}

#[test]
fn integrate_then_difference_round_trips() {
    let (model, _) = mixed_model();
    let q = mixed_q([0.5, -1.0, 0.8], 0.3, 2.9, -0.7, 0.15);
    for v in [
        [0.4, -0.1, 0.9, 0.2, -0.5, 0.3, 0.05],
        [-1.0, 2.0, -3.0, 1.0, 3.0, -2.0, -0.4],
    ] {
        let v = DVector::from_row_slice(&v);
        let q1 = integrate(&model, &q, &v).unwrap();
        check_configuration(&model, &q1).unwrap();
        let back = difference(&model, &q, &q1).unwrap();
        assert!((&back - &v).amax() < TOL, "{back} vs {v}");
    }
    let zero = difference(&model, &q, &q).unwrap();
    assert!(zero.amax() < 1e-15, "{zero}");
}

#[test]
fn unbounded_revolute_has_nq_2_and_matches_a_plain_revolute() {
    // Same axis and placement, one joint as Revolute (q = θ), one as RevoluteUnbounded
    // (q = (cos θ, sin θ)): identical tool poses for every θ, including |θ| > π.
    let build = |kind| {
        let mut b = ModelBuilder::new();
        let j = b
            .add_joint(
                "j",
                JointIndex::UNIVERSE,
                pose(0.1, 0.2, 0.3, 0.4, 0.0, 0.0),
                kind,
                JointLimits::NONE,
            )
            .unwrap();
        let tool = b
            .add_frame("tool", j, pose(0.5, 0.0, 0.1, 0.0, 0.0, 0.3))
            .unwrap();
        (b.build().unwrap(), tool)
    };
    let axis = Vector3::new(0.0, 1.0, 1.0);
    let (plain, tool) = build(JointKind::Revolute { axis });
    let (unbounded, tool_u) = build(JointKind::RevoluteUnbounded { axis });
    assert_eq!((unbounded.nq(), unbounded.nv()), (2, 1));
    assert_eq!(
        unbounded.pinocchio_neutral().unwrap().as_slice(),
        &[1.0, 0.0]
    );
    let (mut d1, mut d2) = (Data::new(&plain).unwrap(), Data::new(&unbounded).unwrap());
    for theta in [0.0, 0.4, -2.0, 3.5, -7.0] {
        forward_kinematics(&plain, &mut d1, &DVector::from_vec(vec![theta])).unwrap();
        forward_kinematics(
            &unbounded,
            &mut d2,
            &DVector::from_vec(vec![theta.cos(), theta.sin()]),
        )
        .unwrap();
        let a = frame_placement(&plain, &d1, tool).unwrap();
        let b = frame_placement(&unbounded, &d2, tool_u).unwrap();
        assert!(pose_error(&a, &b) < TOL, "θ = {theta}");
    }
    // difference wraps to (−π, π]: from 3 rad to −3 rad is +2π − 6 rad.
    let q = |a: f64| DVector::from_vec(vec![a.cos(), a.sin()]);
    let v = difference(&unbounded, &q(3.0), &q(-3.0)).unwrap();
    assert!((v[0] - (2.0 * PI - 6.0)).abs() < TOL);
}

#[test]
fn normalize_fixes_pairs_and_unnormalised_q_is_rejected() {
    let (model, _) = mixed_model();
    let mut q = mixed_q([0.5, -1.0, 0.8], 0.3, 2.9, -0.7, 0.15);
    let good = q.clone();
    q[2] *= 2.0;
    q[3] *= 2.0; // base pair scaled by 2
    q[5] *= 0.5;
    q[6] *= 0.5; // j2 pair scaled by 1/2
    let mut data = Data::new(&model).unwrap();
    match forward_kinematics(&model, &mut data, &q) {
        Err(Error::NotNormalized { joint, norm }) => {
            assert_eq!(joint, "base");
            assert!((norm - 2.0).abs() < TOL);
        }
        other => panic!("expected NotNormalized, got {other:?}"),
    }
    normalize(&model, &mut q).unwrap();
    assert!((&q - &good).amax() < TOL);
    forward_kinematics(&model, &mut data, &q).unwrap();
    // A zero pair has no direction.
    q[5] = 0.0;
    q[6] = 0.0;
    assert!(matches!(
        normalize(&model, &mut q),
        Err(Error::NotNormalized { .. })
    ));
}
