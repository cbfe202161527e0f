//! Hand-written URDF snippets with hand-derived expected poses.

use std::f64::consts::{FRAC_PI_2, PI};

use kinscene::scene::urdf::{ImportOptions, read_str};
use kinscene::scene::{
    JointKind, Limits, Parent, SceneData, Shape, State, forward_kinematics, world_from_handle,
};
use nalgebra::{Isometry3, Matrix3, Point3, Translation3, UnitQuaternion, Vector3};

use super::{assert_point, assert_pose, assert_vector, import, robot};

fn rx(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}
fn ry(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}
fn rz(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Pose from a translation and a hand-built rotation matrix.
fn pose(t: [f64; 3], r: Matrix3<f64>) -> Isometry3<f64> {
    let rotation = UnitQuaternion::from_matrix(&r);
    Isometry3::from_parts(Translation3::new(t[0], t[1], t[2]), rotation)
}

/// URDF `rpy` is fixed-axis roll-pitch-yaw, R = Rz(yaw)·Ry(pitch)·Rx(roll), for joint and
/// collision origins alike.
#[test]
fn rpy_is_fixed_axis_roll_pitch_yaw() {
    let (r, p, y) = (0.3, -0.7, 1.1);
    let model = import(&robot(&format!(
        r#"<link name="base"/>
        <link name="door"><collision><origin xyz="0 0 0" rpy="{r} {p} {y}"/>
          <geometry><sphere radius="0.1"/></geometry></collision></link>
        <joint name="hinge" type="revolute"><origin xyz="1 2 3" rpy="{r} {p} {y}"/>
          <parent link="base"/><child link="door"/><axis xyz="0 0 1"/>
          <limit lower="0" upper="1" effort="0" velocity="0"/></joint>"#
    )));
    let expected = rz(y) * ry(p) * rx(r);
    // The opposite composition order gives a clearly different matrix, so the check below
    // discriminates between the conventions.
    assert!((rx(r) * ry(p) * rz(y) - expected).norm() > 0.1);
    let joint = &model.joints()[0];
    let actual = joint.parent_from_joint.rotation.to_rotation_matrix();
    assert!((actual.matrix() - expected).norm() < 1e-12);
    assert_eq!(
        joint.parent_from_joint.translation.vector,
        Vector3::new(1.0, 2.0, 3.0)
    );
    let collider = &model.parts()[0].colliders()[0];
    let actual = collider.part_from_shape.rotation.to_rotation_matrix();
    assert!((actual.matrix() - expected).norm() < 1e-12);
}

/// Fixed chains merge into the part; a movable joint on a merged link composes the origins.
#[test]
fn fixed_chain_merges_and_composes_origins() {
    let model = import(&robot(
        r#"<link name="room"/>
        <link name="door"/>
        <joint name="hinge" type="revolute"><origin xyz="1 0 0"/><parent link="room"/>
          <child link="door"/><axis xyz="0 0 1"/><limit lower="0" upper="1.5" effort="0" velocity="0"/></joint>
        <link name="panel"><collision><origin xyz="0.1 0 0"/><geometry><box size="0.2 0.4 0.6"/></geometry></collision></link>
        <joint name="panel_fix" type="fixed"><origin xyz="0 0.5 0" rpy="0 0 1.5707963267948966"/>
          <parent link="door"/><child link="panel"/></joint>
        <link name="knob"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>
        <joint name="knob_fix" type="fixed"><origin xyz="0.2 0 0.3"/><parent link="panel"/><child link="knob"/></joint>
        <link name="drawer"/>
        <joint name="slide" type="prismatic"><origin xyz="0 0 0.1"/><parent link="knob"/>
          <child link="drawer"/><axis xyz="1 0 0"/><limit lower="0" upper="0.4" effort="0" velocity="0"/></joint>"#,
    ));
    assert_eq!(model.nq(), 2);
    let door = &model.parts()[model.part_id("door").unwrap().index()];
    let drawer = &model.parts()[model.part_id("drawer").unwrap().index()];
    assert!(model.part_id("panel").is_err() && model.part_id("knob").is_err());
    // door_from_panel = T(0, 0.5, 0)·Rz(90°); panel box at door_from_panel·T(0.1, 0, 0):
    // (0, 0.5, 0) + Rz(90°)·(0.1, 0, 0) = (0, 0.6, 0), rotation Rz(90°).
    assert_eq!(door.colliders().len(), 2);
    assert_pose(
        &door.colliders()[0].part_from_shape,
        &pose([0.0, 0.6, 0.0], rz(FRAC_PI_2)),
        1e-12,
    );
    assert_eq!(
        door.colliders()[0].shape,
        Shape::cuboid(Vector3::new(0.1, 0.2, 0.3))
    );
    // door_from_knob = door_from_panel·T(0.2, 0, 0.3) = (0, 0.5, 0) + Rz(90°)·(0.2, 0, 0.3)
    // = (0, 0.7, 0.3), rotation Rz(90°).
    assert_pose(
        &door.colliders()[1].part_from_shape,
        &pose([0.0, 0.7, 0.3], rz(FRAC_PI_2)),
        1e-12,
    );
    // The slide hangs on the merged knob: its origin in the door frame is
    // door_from_knob·T(0, 0, 0.1) = (0, 0.7, 0.4), rotation Rz(90°).
    assert_eq!(drawer.parent(), Parent::Part(door.id()));
    let slide = &model.joints()[drawer.joint().index()];
    assert_eq!(slide.kind, JointKind::Prismatic);
    assert_pose(
        &slide.parent_from_joint,
        &pose([0.0, 0.7, 0.4], rz(FRAC_PI_2)),
        1e-12,
    );
    // FK at hinge 0, slide 0.2: world drawer origin = (1, 0, 0) + (0, 0.7, 0.4) +
    // Rz(90°)·(0.2, 0, 0) = (1, 0.9, 0.4).
    let state = State::from_values(&model, [("slide", 0.2)]).unwrap();
    let mut data = SceneData::new(&model);
    forward_kinematics(&model, &mut data, &state).unwrap();
    let world = data.world_from_part(drawer.id()).unwrap();
    assert_point(
        &Point3::from(world.translation.vector),
        &Point3::new(1.0, 0.9, 0.4),
        1e-12,
    );
}

/// The root link and links fixed to it become named base shapes in world coordinates.
#[test]
fn fixed_links_on_the_base_become_base_shapes() {
    let model = import(&robot(
        r#"<link name="room">
          <collision name="floor"><origin xyz="0 0 -0.05"/><geometry><box size="4 4 0.1"/></geometry></collision>
          <collision><geometry><sphere radius="0.3"/></geometry></collision></link>
        <link name="counter"><collision><origin xyz="0.1 0 0"/><geometry><box size="0.6 1.2 0.9"/></geometry></collision></link>
        <joint name="counter_fix" type="fixed"><origin xyz="2 0 0.45" rpy="0 0 1.5707963267948966"/>
          <parent link="room"/><child link="counter"/></joint>
        <link name="shelf"><collision name="shelf_board"><geometry><cylinder radius="0.2" length="0.02"/></geometry></collision></link>
        <joint name="shelf_fix" type="fixed"><origin xyz="0 0 0.5"/><parent link="counter"/><child link="shelf"/></joint>"#,
    ));
    assert_eq!(model.nq(), 0);
    let base = model.base();
    assert_eq!(base.name.as_deref(), Some("room"));
    let names: Vec<&str> = base.shapes.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["floor", "room#1", "counter#0", "shelf_board"]);
    assert_pose(
        &base.shapes[0].world_from_shape,
        &Isometry3::translation(0.0, 0.0, -0.05),
        0.0,
    );
    // counter: (2, 0, 0.45) + Rz(90°)·(0.1, 0, 0) = (2, 0.1, 0.45); shelf: (2, 0, 0.95).
    assert_pose(
        &base.shapes[2].world_from_shape,
        &pose([2.0, 0.1, 0.45], rz(FRAC_PI_2)),
        1e-12,
    );
    assert_pose(
        &base.shapes[3].world_from_shape,
        &pose([2.0, 0.0, 0.95], rz(FRAC_PI_2)),
        1e-12,
    );
    assert_eq!(base.shapes[3].shape, Shape::cylinder(0.2, 0.02));
}

/// Handle links: origin = grasp point, +x = outward normal, also through fixed chains.
#[test]
fn handles_from_fixed_links() {
    let model = import(&robot(
        r#"<link name="carcass"/><link name="door"/>
        <joint name="hinge" type="revolute"><origin xyz="0.5 0 0"/><parent link="carcass"/>
          <child link="door"/><axis xyz="0 0 1"/><limit lower="0" upper="2" effort="0" velocity="0"/></joint>
        <link name="door_handle"/>
        <joint name="h_fix" type="fixed"><origin xyz="0.02 -0.4 0.9" rpy="0 0 1.5707963267948966"/>
          <parent link="door"/><child link="door_handle"/></joint>
        <link name="bar"/>
        <joint name="bar_fix" type="fixed"><origin xyz="0 0 0.1" rpy="0 -1.5707963267948966 0"/>
          <parent link="door"/><child link="bar"/></joint>
        <link name="bar_handle"/>
        <joint name="bar_h_fix" type="fixed"><origin xyz="0.05 0 0"/><parent link="bar"/><child link="bar_handle"/></joint>"#,
    ));
    let door = &model.parts()[0];
    let names: Vec<&str> = door.handles().iter().map(|h| h.name.as_str()).collect();
    assert_eq!(names, ["door_handle", "bar_handle"]);
    let h = &door.handles()[0];
    assert_eq!(h.position, Point3::new(0.02, -0.4, 0.9));
    // Rz(90°)·x = y.
    assert_vector(&h.normal, &Vector3::y(), 1e-15);
    // Through bar: (0, 0, 0.1) + Ry(-90°)·(0.05, 0, 0) = (0, 0, 0.15); normal Ry(-90°)·x = z.
    let h = &door.handles()[1];
    assert_point(&h.position, &Point3::new(0.0, 0.0, 0.15), 1e-15);
    assert_vector(&h.normal, &Vector3::z(), 1e-15);
    // Door at 90°: (0.5, 0, 0) + Rz(90°)·(0.02, -0.4, 0.9) = (0.9, 0.02, 0.9), normal -x.
    let state = State::from_values(&model, [("hinge", FRAC_PI_2)]).unwrap();
    let mut data = SceneData::new(&model);
    forward_kinematics(&model, &mut data, &state).unwrap();
    let world = world_from_handle(&model, &data, model.handle_id("door_handle").unwrap()).unwrap();
    assert_point(&world.position, &Point3::new(0.9, 0.02, 0.9), 1e-12);
    assert_vector(&world.normal, &-Vector3::x(), 1e-12);
}

const CONTINUOUS: &str = r#"<link name="b"/><link name="wheel"/>
    <joint name="spin" type="continuous"><parent link="b"/><child link="wheel"/><axis xyz="0 1 0"/>
      <limit lower="-1" upper="1" effort="3" velocity="4"/></joint>"#;

/// Continuous joints: revolute, flagged, with the working range of the options (their
/// `<limit>` bounds are ignored).
#[test]
fn continuous_joint_gets_the_working_range() {
    let model = import(&robot(CONTINUOUS));
    let joint = &model.joints()[0];
    assert_eq!(joint.kind, JointKind::Revolute);
    assert!(joint.continuous);
    assert_eq!(joint.limits, Limits::new(-PI, PI));
    let options = ImportOptions {
        continuous_limits: Limits::new(-10.0, 10.0),
        ..ImportOptions::default()
    };
    let model = read_str(&robot(CONTINUOUS), &options).unwrap();
    assert_eq!(model.joints()[0].limits, Limits::new(-10.0, 10.0));
    assert!(State::from_values(&model, [("spin", 9.0)]).is_ok());
}

/// Prismatic joints: axis normalised, limits kept, FK translates along the axis.
#[test]
fn prismatic_joint() {
    let model = import(&robot(
        r#"<link name="b"/><link name="drawer"/>
        <joint name="slide" type="prismatic"><origin xyz="0.1 0.2 0.3"/><parent link="b"/>
          <child link="drawer"/><axis xyz="0 0 2"/><limit lower="0" upper="0.45" effort="0" velocity="0"/></joint>"#,
    ));
    let joint = &model.joints()[0];
    assert_eq!(joint.kind, JointKind::Prismatic);
    assert!(!joint.continuous);
    assert_eq!(joint.axis, Vector3::z());
    assert_eq!(joint.limits, Limits::new(0.0, 0.45));
    let poses = model.world_from_parts(&State::from_values(&model, [("slide", 0.3)]).unwrap());
    // (0.1, 0.2, 0.3) + 0.3·z.
    assert_point(
        &Point3::from(poses.unwrap()[0].translation.vector),
        &Point3::new(0.1, 0.2, 0.6),
        1e-15,
    );
}

/// A joint without `<axis>` turns about (1, 0, 0).
#[test]
fn axis_defaults_to_x() {
    let model = import(&robot(
        r#"<link name="b"/><link name="flap"/>
        <joint name="j" type="revolute"><parent link="b"/><child link="flap"/>
          <limit lower="0" upper="1" effort="0" velocity="0"/></joint>"#,
    ));
    assert_eq!(model.joints()[0].axis, Vector3::x());
}

/// Visuals, inertials, materials, dynamics, mimic, calibration, safety controllers and
/// unknown elements do not change the model.
#[test]
fn ignored_elements_do_not_change_the_model() {
    let plain = robot(
        r#"<link name="b"/><link name="flap"><collision><geometry><sphere radius="0.1"/></geometry></collision></link>
        <joint name="j" type="revolute"><parent link="b"/><child link="flap"/>
          <limit lower="0" upper="1" effort="0" velocity="0"/></joint>"#,
    );
    let decorated = robot(
        r#"<material name="red"><color rgba="1 0 0 1"/></material>
        <link name="b"><visual><geometry><box size="9 9 9"/></geometry></visual>
          <inertial><mass value="3"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
        <link name="flap"><visual><geometry><mesh filename="missing.stl"/></geometry></visual>
          <collision><geometry><sphere radius="0.1"/></geometry></collision></link>
        <joint name="j" type="revolute"><parent link="b"/><child link="flap"/>
          <limit lower="0" upper="1" effort="7" velocity="8"/><dynamics damping="1" friction="2"/>
          <calibration rising="0.1"/><safety_controller k_velocity="1"/><mimic joint="j"/></joint>
        <gazebo reference="flap"><material>Gazebo/Red</material></gazebo>
        <transmission name="t"><type>x</type></transmission>"#,
    );
    assert_eq!(import(&plain), import(&decorated));
}
