//! The grasp trajectory of Eq. (3)–(5) and the motion bound, on the hand-built scene.

use std::f64::consts::FRAC_PI_2;

use kinscene::scene::motion::{grasp_trajectory, max_displacement, sweep_radius};
use kinscene::scene::{Error, SceneData, State, forward_kinematics, joint_axis, world_from_handle};
use nalgebra::{Point3, Vector3};

use super::fixtures::kitchenette;

/// Positions are within a few metres and built from a handful of products: 1e-12 m covers
/// rounding with a wide margin.
const TOL: f64 = 1e-12;

#[test]
fn revolute_trajectory_of_a_descendant_handle() {
    let m = kitchenette();
    let hinge = m.joint_id("dw_hinge").unwrap();
    let handle = m.handle_id("dw_rack_handle").unwrap();
    let state = State::from_values(&m, [("dw_rack_slide", 0.1), ("dw_hinge", 0.7)]).unwrap();
    let mut data = SceneData::new(&m);
    let (a, b, k) = (0.2, 1.3, 10);
    let traj = grasp_trajectory(&m, &mut data, &state, handle, hinge, a, b, k).unwrap();
    assert_eq!(traj.len(), k + 1);

    // Endpoints equal the forward kinematics of the handle at a and at b.
    for (value, pose) in [(a, traj[0]), (b, traj[k])] {
        let mut s = state.clone();
        s.set(&m, hinge, value).unwrap();
        forward_kinematics(&m, &mut data, &s).unwrap();
        let fk = world_from_handle(&m, &data, handle).unwrap();
        assert!((fk.position - pose.position).norm() < TOL, "value {value}");
        assert!((fk.normal.into_inner() - pose.normal.into_inner()).norm() < TOL);
    }

    // Every point lies on the circle about the hinge axis through p: same distance from the
    // axis, and in the plane through p perpendicular to it.
    let axis = joint_axis(&m, &data, hinge).unwrap();
    let u = axis.direction.into_inner();
    let p0 = traj[0].position;
    let r0 = axis.distance_to_axis(&p0);
    assert!(r0 > 0.1, "the handle is off the axis");
    for pose in &traj {
        assert!((axis.distance_to_axis(&pose.position) - r0).abs() < TOL);
        assert!((pose.position - p0).dot(&u).abs() < TOL);
    }
}

#[test]
fn door_trajectory_ends_at_the_hand_computed_point() {
    let m = kitchenette();
    let hinge = m.joint_id("door_hinge").unwrap();
    let handle = m.handle_id("door_handle").unwrap();
    let mut data = SceneData::new(&m);
    let traj = grasp_trajectory(
        &m,
        &mut data,
        &m.zero_state(),
        handle,
        hinge,
        0.0,
        FRAC_PI_2,
        6,
    )
    .unwrap();
    // See kinematics.rs: the handle at 90° is at (1.02, 2.45, 0.8); at 0° at (1.45, 1.98, 0.8).
    assert!((traj[6].position - Point3::new(1.02, 2.45, 0.8)).norm() < TOL);
    assert!((traj[0].position - Point3::new(1.45, 1.98, 0.8)).norm() < TOL);
    // Step 3 of 6 is 45°: pivot + R_z(45°)·(0.45, -0.02, 0).
    let (s, c) = (FRAC_PI_2 / 2.0).sin_cos();
    let want = Point3::new(1.0 + 0.45 * c + 0.02 * s, 2.0 + 0.45 * s - 0.02 * c, 0.8);
    assert!((traj[3].position - want).norm() < TOL);
}

#[test]
fn prismatic_trajectory_is_evenly_spaced_along_the_axis() {
    let m = kitchenette();
    let slide = m.joint_id("drawer_slide").unwrap();
    let handle = m.handle_id("drawer_handle").unwrap();
    let mut data = SceneData::new(&m);
    let traj =
        grasp_trajectory(&m, &mut data, &m.zero_state(), handle, slide, 0.0, 0.3, 3).unwrap();
    // Eq. (5): p + (i/3)·0.3·(0, -1, 0) with p = (0.5, -0.21, 0.45).
    for (i, pose) in traj.iter().enumerate() {
        let want = Point3::new(0.5, -0.21 - 0.1 * i as f64, 0.45);
        assert!((pose.position - want).norm() < TOL, "step {i}");
        assert!((pose.normal.into_inner() + Vector3::y()).norm() < TOL);
    }
}

#[test]
fn trajectory_rejects_bad_requests() {
    let m = kitchenette();
    let mut data = SceneData::new(&m);
    let s = m.zero_state();
    let door_handle = m.handle_id("door_handle").unwrap();
    let dw_hinge = m.joint_id("dw_hinge").unwrap();
    let door_hinge = m.joint_id("door_hinge").unwrap();
    let err = grasp_trajectory(&m, &mut data, &s, door_handle, dw_hinge, 0.0, 1.0, 5).unwrap_err();
    assert_eq!(
        err,
        Error::NotInSubtree {
            handle: "door_handle".into(),
            joint: "dw_hinge".into()
        }
    );
    let err =
        grasp_trajectory(&m, &mut data, &s, door_handle, door_hinge, 0.0, 2.5, 5).unwrap_err();
    assert!(matches!(err, Error::JointLimit { value, max, .. } if value == 2.5 && max == 2.0));
    let err =
        grasp_trajectory(&m, &mut data, &s, door_handle, door_hinge, 0.0, 1.0, 0).unwrap_err();
    assert!(
        matches!(err, Error::InvalidSetting(s) if s.field == "trajectory steps K" && s.value == 0.0)
    );
}

#[test]
fn motion_bound_of_the_door() {
    let m = kitchenette();
    let hinge = m.joint_id("door_hinge").unwrap();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &m.zero_state()).unwrap();
    // The slab's bounding sphere: centre 0.225 m from the axis, radius
    // |(0.225, 0.01, 0.3)| = 0.37514; the handle is at |(0.45, -0.02)| = 0.45044 from the axis.
    let r = sweep_radius(&m, &data, hinge).unwrap();
    let sphere = 0.225 + (0.225f64.powi(2) + 0.01f64.powi(2) + 0.3f64.powi(2)).sqrt();
    assert!((r - sphere.max(0.45f64.hypot(0.02))).abs() < TOL);
    // Revolute: r·|Δφ|.
    let d = max_displacement(&m, &mut data, &m.zero_state(), hinge, 0.5, 1.5).unwrap();
    assert!((d - r).abs() < TOL);
    // Prismatic: |Δd|.
    let slide = m.joint_id("drawer_slide").unwrap();
    let d = max_displacement(&m, &mut data, &m.zero_state(), slide, 0.1, 0.35).unwrap();
    assert!((d - 0.25).abs() < TOL);
}
