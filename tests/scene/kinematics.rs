//! Forward kinematics against hand-derived poses.

use std::f64::consts::FRAC_PI_2;

use kinscene::scene::{SceneData, State, forward_kinematics, joint_axis, world_from_handle};
use nalgebra::{Matrix3, Point3, Vector3};

use super::fixtures::kitchenette;

/// Poses below are products of exact rotations by 90° and short decimal translations:
/// rounding error is a few ulps of 1, far below 1e-12.
const TOL: f64 = 1e-12;

fn assert_point(got: &Point3<f64>, want: [f64; 3]) {
    let want = Point3::new(want[0], want[1], want[2]);
    assert!((got - want).norm() < TOL, "got {got}, want {want}");
}

#[test]
fn cabinet_door_handle_at_ninety_degrees() {
    let m = kitchenette();
    let s = State::from_values(&m, [("door_hinge", FRAC_PI_2)]).unwrap();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &s).unwrap();
    let h = world_from_handle(&m, &data, m.handle_id("door_handle").unwrap()).unwrap();
    // R_z(90°) maps (x, y, z) to (-y, x, z): (0.45, -0.02, 0.3) -> (0.02, 0.45, 0.3), plus the
    // pivot (1, 2, 0.5).
    assert_point(&h.position, [1.02, 2.45, 0.8]);
    // Normal -y -> +x.
    assert!((h.normal.into_inner() - Vector3::x()).norm() < TOL);
}

#[test]
fn drawer_translated_twenty_centimetres() {
    let m = kitchenette();
    let s = State::from_values(&m, [("drawer_slide", 0.2)]).unwrap();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &s).unwrap();
    let h = world_from_handle(&m, &data, m.handle_id("drawer_handle").unwrap()).unwrap();
    // Origin (0.5, 0, 0.4) + 0.2·(0, -1, 0) + (0, -0.21, 0.05).
    assert_point(&h.position, [0.5, -0.41, 0.45]);
}

#[test]
fn dishwasher_rack_rides_on_the_door() {
    let m = kitchenette();
    let rack = m.part_id("dw_rack").unwrap();
    let mut data = SceneData::new(&m);

    // Door closed, rack out 0.15: translation (2, 0, 0.1) + (0, -0.1, 0.4 + 0.15).
    let closed = State::from_values(&m, [("dw_rack_slide", 0.15)]).unwrap();
    forward_kinematics(&m, &mut data, &closed).unwrap();
    let pose = data.world_from_part(rack).unwrap();
    assert_point(&Point3::from(pose.translation.vector), [2.0, -0.1, 0.65]);
    assert!((pose.rotation.to_rotation_matrix().into_inner() - Matrix3::identity()).norm() < TOL);

    // Door open 90° about -x, i.e. R_x(-90°): (x, y, z) -> (x, z, -y).
    // world_from_rack = T(2, 0, 0.1) · R · T(0, -0.1, 0.55), translation
    // (2, 0, 0.1) + R·(0, -0.1, 0.55) = (2, 0.55, 0.2).
    let open = State::from_values(&m, [("dw_hinge", FRAC_PI_2), ("dw_rack_slide", 0.15)]).unwrap();
    forward_kinematics(&m, &mut data, &open).unwrap();
    let pose = data.world_from_part(rack).unwrap();
    assert_point(&Point3::from(pose.translation.vector), [2.0, 0.55, 0.2]);
    let r = Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
    assert!((pose.rotation.to_rotation_matrix().into_inner() - r).norm() < TOL);

    // The rack handle (0, 0, 0.2) in the rack frame: (2, 0.55, 0.2) + R·(0, 0, 0.2).
    let h = world_from_handle(&m, &data, m.handle_id("dw_rack_handle").unwrap()).unwrap();
    assert_point(&h.position, [2.0, 0.75, 0.2]);
    assert!((h.normal.into_inner() - Vector3::y()).norm() < TOL);

    // The rack's world axis follows the door: R·z = +y through (2, 0, 0.1) + R·(0, -0.1, 0.4).
    let axis = joint_axis(&m, &data, rack.joint()).unwrap();
    assert!((axis.direction.into_inner() - Vector3::y()).norm() < TOL);
    assert_point(&axis.pivot, [2.0, 0.4, 0.2]);
}

#[test]
fn convenience_poses_match_data() {
    let m = kitchenette();
    let s = State::from_values(&m, [("dw_hinge", 0.3), ("door_hinge", 1.1)]).unwrap();
    let all = m.world_from_parts(&s).unwrap();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &s).unwrap();
    assert_eq!(all.as_slice(), data.world_from_parts());
}

#[test]
fn tree_structure_and_ids() {
    let m = kitchenette();
    let door = m.part(m.part_id("dw_door").unwrap()).unwrap();
    let rack = m.part_id("dw_rack").unwrap();
    // Pre-order numbering: a parent comes before its child, the subtree is contiguous.
    assert!(door.id() < rack);
    assert_eq!(door.children(), &[rack]);
    assert!(door.subtree_contains(rack));
    assert_eq!(door.subtree().count(), 2);
    assert_eq!(m.part(rack).unwrap().depth(), 2);
    assert_eq!(m.joint_id("dw_rack_slide").unwrap(), rack.joint());
}
