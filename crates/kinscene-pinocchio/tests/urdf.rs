//! Models parsed from URDF by Pinocchio's parser: structure read back into Rust, forward
//! kinematics against placements derived by hand from the document's numbers, and every kind of
//! rejected document as a typed error (the C++ exception path through `ks::guard`).
//!
//! Tolerance 1e-12, as in `forward_kinematics.rs`: each expected pose is a product of at most
//! five rigid transforms with O(1) entries, so rounding stays at a few 1e-16, while a wrong axis,
//! origin or composition order shows up at 1e-2 or more.

use std::f64::consts::PI;

use kinscene_pinocchio::{
    Data, Error, FrameKind, JointIndex, JointKind, JointLimits, Model, forward_kinematics,
    frame_placement, set_joint_value,
};
use kinscene_shim::CallError;
use nalgebra::{DVector, Isometry3, Matrix3, Translation3, Unit, UnitQuaternion, Vector3};

use crate::support::{pose, pose_error};

const TOL: f64 = 1e-12;

/// A fixed-base arm with one joint of each URDF kind the scene exporter writes:
/// base ─shoulder (revolute Z)→ upper ─slide (prismatic along (0, 1, 1)/√2)→ carriage
/// ─tool_mount (fixed)→ tool, and base ─wheel (continuous X)→ wheel_link. `upper` carries an
/// inertial.
const ARM: &str = r#"<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/>
    <child link="upper"/>
    <origin xyz="0.1 0.0 0.3" rpy="0 0 0.4"/>
    <axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="1.5"/>
  </joint>
  <link name="upper">
    <inertial>
      <origin xyz="0.2 0 0"/>
      <mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/>
    </inertial>
  </link>
  <joint name="slide" type="prismatic">
    <parent link="upper"/>
    <child link="carriage"/>
    <origin xyz="0.5 0.05 0" rpy="0.3 0 0"/>
    <axis xyz="0 1 1"/>
    <limit lower="0" upper="0.4" effort="50" velocity="0.2"/>
  </joint>
  <link name="carriage"/>
  <joint name="tool_mount" type="fixed">
    <parent link="carriage"/>
    <child link="tool"/>
    <origin xyz="0.2 0 0.1" rpy="0 0.5 0"/>
  </joint>
  <link name="tool"/>
  <joint name="wheel" type="continuous">
    <parent link="base"/>
    <child link="wheel_link"/>
    <origin xyz="-0.2 0.1 0.05" rpy="0.1 -0.2 0.3"/>
    <axis xyz="1 0 0"/>
  </joint>
  <link name="wheel_link"/>
</robot>
"#;

// The document's origins, as `support::pose` arguments (URDF rpy is R = Rz(y) Ry(p) Rx(r),
// nalgebra's `from_euler_angles(roll, pitch, yaw)`).
const SHOULDER: [f64; 6] = [0.1, 0.0, 0.3, 0.0, 0.0, 0.4];
const SLIDE: [f64; 6] = [0.5, 0.05, 0.0, 0.3, 0.0, 0.0];
const TOOL_MOUNT: [f64; 6] = [0.2, 0.0, 0.1, 0.0, 0.5, 0.0];
const WHEEL: [f64; 6] = [-0.2, 0.1, 0.05, 0.1, -0.2, 0.3];

fn origin(p: [f64; 6]) -> Isometry3<f64> {
    pose(p[0], p[1], p[2], p[3], p[4], p[5])
}

fn rotation(axis: Vector3<f64>, angle: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&Unit::new_normalize(axis), angle),
    )
}

fn translation(axis: Vector3<f64>, d: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::from(axis.normalize() * d),
        UnitQuaternion::identity(),
    )
}

/// `world_from_link` for every link of [`ARM`] at shoulder angle `a`, slide displacement `d`,
/// wheel angle `w`, composed from the document's origins and axes.
fn expected_links(a: f64, d: f64, w: f64) -> [(&'static str, Isometry3<f64>); 5] {
    let upper = origin(SHOULDER) * rotation(Vector3::z(), a);
    let carriage = upper * origin(SLIDE) * translation(Vector3::new(0.0, 1.0, 1.0), d);
    let tool = carriage * origin(TOOL_MOUNT);
    let wheel_link = origin(WHEEL) * rotation(Vector3::x(), w);
    [
        ("base", Isometry3::identity()),
        ("upper", upper),
        ("carriage", carriage),
        ("tool", tool),
        ("wheel_link", wheel_link),
    ]
}

fn joint(model: &Model, name: &str) -> JointIndex {
    model
        .joint_index(name)
        .unwrap_or_else(|| panic!("no joint {name}"))
}

/// q for [`ARM`] with the three joint values, through the names.
fn arm_q(model: &Model, a: f64, d: f64, w: f64) -> DVector<f64> {
    let mut q = model.neutral();
    for (name, value) in [("shoulder", a), ("slide", d), ("wheel", w)] {
        set_joint_value(model, &mut q, joint(model, name), value).unwrap();
    }
    q
}

#[test]
fn urdf_joints_frames_limits_and_bodies_are_read_back() {
    let model = Model::from_urdf_str(ARM).unwrap();
    // revolute (1) + prismatic (1) + continuous (cos, sin: 2) coordinates, 3 degrees of freedom.
    assert_eq!((model.nq(), model.nv(), model.njoints()), (4, 3, 4));

    let shoulder = model.joint(joint(&model, "shoulder")).unwrap();
    assert_eq!(shoulder.kind, JointKind::Revolute { axis: Vector3::z() });
    assert_eq!(shoulder.parent, JointIndex::UNIVERSE);
    assert!(pose_error(&shoulder.parent_from_joint, &origin(SHOULDER)) < TOL);
    assert_eq!(
        shoulder.limits,
        JointLimits::position(-2.0, 2.0)
            .with_velocity(1.5)
            .with_effort(10.0)
    );
    assert_eq!(shoulder.nq(), 1);

    let slide = model.joint(joint(&model, "slide")).unwrap();
    let JointKind::Prismatic { axis } = slide.kind else {
        panic!("slide is {:?}", slide.kind)
    };
    assert!((axis - Vector3::new(0.0, 1.0, 1.0) / 2f64.sqrt()).norm() < TOL);
    assert_eq!(slide.parent, joint(&model, "shoulder"));
    assert!(pose_error(&slide.parent_from_joint, &origin(SLIDE)) < TOL);
    assert_eq!(
        slide.limits,
        JointLimits::position(0.0, 0.4)
            .with_velocity(0.2)
            .with_effort(50.0)
    );

    // A continuous joint is Pinocchio's unbounded revolute: (cos, sin), no position limits,
    // and no velocity/effort limits either, since the document gives none.
    let wheel = model.joint(joint(&model, "wheel")).unwrap();
    assert_eq!(
        wheel.kind,
        JointKind::RevoluteUnbounded { axis: Vector3::x() }
    );
    assert_eq!((wheel.nq(), wheel.nv()), (2, 1));
    assert_eq!(wheel.limits, JointLimits::NONE);

    // The q layout is contiguous and covers 0..nq exactly once.
    let mut covered = vec![false; model.nq()];
    for j in model.joints() {
        for c in &mut covered[j.idx_q..j.idx_q + j.nq()] {
            assert!(!*c, "q entry shared");
            *c = true;
        }
    }
    assert!(covered.iter().all(|&c| c));

    // Links are BODY frames on the nearest moving joint; the fixed joint is a FIXED_JOINT frame.
    for (link, parent) in [
        ("base", JointIndex::UNIVERSE),
        ("upper", joint(&model, "shoulder")),
        ("carriage", joint(&model, "slide")),
        ("tool", joint(&model, "slide")),
        ("wheel_link", joint(&model, "wheel")),
    ] {
        let frame = model.frame(model.link_frame(link).unwrap()).unwrap();
        assert_eq!((frame.kind, frame.parent_joint), (FrameKind::Body, parent));
    }
    let mount = model
        .frame(model.frame_index("tool_mount").unwrap())
        .unwrap();
    assert_eq!(mount.kind, FrameKind::FixedJoint);
    assert!(model.link_frame("tool_mount").is_none());
    assert!(model.link_frame("shoulder").is_none());

    // The one inertial sits on the shoulder joint, expressed in its frame (= the link frame).
    assert_eq!(model.bodies().len(), 1);
    let (on, body) = model.bodies()[0];
    assert_eq!(on, joint(&model, "shoulder"));
    assert!((body.mass - 2.0).abs() < TOL);
    assert!((body.com - Vector3::new(0.2, 0.0, 0.0)).norm() < TOL);
    assert!(
        (body.rotational - Matrix3::from_diagonal(&Vector3::new(0.01, 0.02, 0.03))).amax() < TOL
    );
}

#[test]
fn urdf_forward_kinematics_matches_hand_derived_link_placements() {
    let model = Model::from_urdf_str(ARM).unwrap();
    let mut data = Data::new(&model).unwrap();
    for (a, d, w) in [
        (0.0, 0.0, 0.0),
        (0.7, 0.1, -1.2),
        (-2.0, 0.4, 3.0),
        (1.3, 0.25, PI),
    ] {
        forward_kinematics(&model, &mut data, &arm_q(&model, a, d, w)).unwrap();
        for (link, expected) in expected_links(a, d, w) {
            let got = frame_placement(&model, &data, model.link_frame(link).unwrap()).unwrap();
            assert!(
                pose_error(&got, &expected) < TOL,
                "({a}, {d}, {w}) {link}: {got} vs {expected}"
            );
        }
    }
}

#[test]
fn continuous_joint_value_wraps_by_full_turns() {
    // (cos, sin) of w and of w + 2π differ by rounding only: the same placement.
    let model = Model::from_urdf_str(ARM).unwrap();
    let wheel = model.link_frame("wheel_link").unwrap();
    let mut data = Data::new(&model).unwrap();
    let place = |data: &mut Data, w: f64| {
        forward_kinematics(&model, data, &arm_q(&model, 0.0, 0.0, w)).unwrap();
        frame_placement(&model, data, wheel).unwrap()
    };
    for w in [0.4, -2.9, 3.1] {
        let once = place(&mut data, w);
        let wrapped = place(&mut data, w + 2.0 * PI);
        assert!(pose_error(&once, &wrapped) < TOL);
        assert!(pose_error(&once, &expected_links(0.0, 0.0, w)[4].1) < TOL);
    }
}

#[test]
fn urdf_model_rebuilds_from_its_builder() {
    // to_builder replays the read-back joints, frames (BODY kind included) and bodies into a
    // new C++ model; both must place every frame identically.
    let parsed = Model::from_urdf_str(ARM).unwrap();
    let rebuilt = parsed.to_builder().build().unwrap();
    assert_eq!(parsed.frames(), rebuilt.frames());
    assert_eq!(parsed.joints(), rebuilt.joints());
    let (mut d1, mut d2) = (Data::new(&parsed).unwrap(), Data::new(&rebuilt).unwrap());
    let q = arm_q(&parsed, -0.8, 0.3, 2.2);
    forward_kinematics(&parsed, &mut d1, &q).unwrap();
    forward_kinematics(&rebuilt, &mut d2, &q).unwrap();
    for f in 0..parsed.frames().len() {
        let f = kinscene_pinocchio::FrameIndex(f);
        let (a, b) = (
            frame_placement(&parsed, &d1, f).unwrap(),
            frame_placement(&rebuilt, &d2, f).unwrap(),
        );
        assert!(pose_error(&a, &b) < TOL);
    }
}

#[test]
fn link_and_joint_may_share_a_name() {
    // URDF keeps link and joint names apart; lookups by kind still find each.
    let xml = r#"<robot name="r"><link name="a"/><link name="j"/>
        <joint name="j" type="prismatic"><parent link="a"/><child link="j"/>
        <origin xyz="0 0 0.5"/><axis xyz="1 0 0"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>"#;
    let model = Model::from_urdf_str(xml).unwrap();
    assert_eq!(model.joint_index("j"), Some(JointIndex(1)));
    let link = model.link_frame("j").unwrap();
    assert_eq!(model.frame(link).unwrap().kind, FrameKind::Body);
    // frame_index gives the first frame of that name, the joint's (it precedes its child link).
    let first = model.frame_index("j").unwrap();
    assert_eq!(model.frame(first).unwrap().kind, FrameKind::Joint);
}

#[test]
fn set_joint_value_rejects_bad_input() {
    let model = Model::from_urdf_str(ARM).unwrap();
    let mut q = model.neutral();
    let shoulder = joint(&model, "shoulder");
    assert!(matches!(
        set_joint_value(&model, &mut DVector::zeros(3), shoulder, 0.1),
        Err(Error::DimensionMismatch {
            expected: 4,
            got: 3,
            ..
        })
    ));
    assert!(matches!(
        set_joint_value(&model, &mut q, JointIndex::UNIVERSE, 0.1),
        Err(Error::JointOutOfRange { index: 0, .. })
    ));
    assert!(matches!(
        set_joint_value(&model, &mut q, JointIndex(9), 0.1),
        Err(Error::JointOutOfRange { index: 9, .. })
    ));
    assert!(matches!(
        set_joint_value(&model, &mut q, shoulder, f64::NAN),
        Err(Error::NonFinite { .. })
    ));
    assert_eq!(q, model.neutral(), "failed calls leave q unchanged");

    let planar = r#"<robot name="r"><link name="a"/><link name="b"/>
        <joint name="p" type="planar"><parent link="a"/><child link="b"/></joint></robot>"#;
    let model = Model::from_urdf_str(planar).unwrap();
    assert_eq!(model.joints()[0].kind, JointKind::Planar);
    let mut q = model.neutral();
    assert!(matches!(
        set_joint_value(&model, &mut q, JointIndex(1), 0.1),
        Err(Error::NotScalarJoint { joint }) if joint == "p"
    ));
}

/// The message of a rejected document: a Pinocchio exception caught by the shim's guard.
fn exception(xml: &str) -> String {
    match Model::from_urdf_str(xml) {
        Err(Error::Backend(CallError::Exception { function, message })) => {
            assert_eq!(function, "ks_pin_model_from_urdf");
            message
        }
        other => panic!("expected a C++ exception, got {other:?}"),
    }
}

#[test]
fn malformed_xml_is_a_typed_error_with_urdfdom_diagnostic() {
    for xml in [
        "<robot name='r'><link name='a'>",
        "<robot name='r'><link name='a'/></robt>",
        "",
        "not xml at all",
    ] {
        let message = exception(xml);
        assert!(
            message.contains("does not contain a valid URDF model"),
            "{xml:?}: {message}"
        );
        // urdfdom's reason (tinyxml2's error), captured from console_bridge.
        assert!(
            message.contains("(urdfdom: ") && message.contains("XML_ERROR"),
            "{xml:?}: {message}"
        );
    }
}

#[test]
fn invalid_urdf_documents_are_typed_errors_naming_the_element() {
    let link2 =
        |joint: &str| format!(r#"<robot name="r"><link name="a"/><link name="b"/>{joint}</robot>"#);
    // Rejected by urdfdom: the message names the offending joint or link.
    let cases = [
        (
            link2(r#"<joint name="j" type="banana"><parent link="a"/><child link="b"/></joint>"#),
            "no known type [banana]",
        ),
        (
            r#"<robot name="r"><link name="a"/><joint name="j" type="fixed"><parent link="a"/><child link="ghost"/></joint></robot>"#
                .to_owned(),
            "[ghost]",
        ),
        (
            r#"<robot name="r"><link name="a"/><link name="b"/></robot>"#.to_owned(),
            "Two root links",
        ),
        (
            link2(r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>"#),
            "Joint [j] is of type REVOLUTE but it does not specify limits",
        ),
        (
            link2(r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><limit lower="-1" upper="1"/></joint>"#),
            "no effort",
        ),
        (
            link2(r#"<joint name="j" type="fixed"><origin xyz="nan 0 0"/><parent link="a"/><child link="b"/></joint>"#),
            "[nan]",
        ),
    ];
    for (xml, needle) in cases {
        let message = exception(&xml);
        assert!(message.contains(needle), "{xml}: {message}");
    }

    // Accepted by Pinocchio, rejected by this crate's checks on the read-back model.
    let revolute = |axis: &str, lower: f64, upper: f64| {
        link2(&format!(
            r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="{axis}"/><limit lower="{lower}" upper="{upper}" effort="1" velocity="1"/></joint>"#
        ))
    };
    assert!(matches!(
        Model::from_urdf_str(&revolute("0 0 1", 1.0, -1.0)),
        Err(Error::InvertedLimits { joint, lower: 1.0, upper: -1.0 }) if joint == "j"
    ));
    assert!(matches!(
        Model::from_urdf_str(&revolute("0 0 0", -1.0, 1.0)),
        Err(Error::InvalidAxis { joint, .. }) if joint == "j"
    ));
    let floating =
        link2(r#"<joint name="j" type="floating"><parent link="a"/><child link="b"/></joint>"#);
    assert!(matches!(
        Model::from_urdf_str(&floating),
        Err(Error::UnsupportedJoint { joint, kind }) if joint == "j" && kind == "JointModelFreeFlyer"
    ));
    // The root link's inertia is summed into the universe joint (0).
    let negative_mass = r#"<robot name="r"><link name="a"><inertial><mass value="-1"/>
        <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link></robot>"#;
    assert!(matches!(
        Model::from_urdf_str(negative_mass),
        Err(Error::NegativeMass { joint: 0, .. })
    ));
}

#[test]
fn urdf_parses_from_several_threads() {
    // The shim serialises parses (console_bridge's handler is process-global); concurrent
    // callers must all get complete, identical models.
    let handles: Vec<_> = (0..4)
        .map(|_| {
            std::thread::spawn(|| {
                (0..10)
                    .map(|_| {
                        let m = Model::from_urdf_str(ARM).unwrap();
                        (m.nq(), m.nv(), m.frames().len())
                    })
                    .collect::<Vec<_>>()
            })
        })
        .collect();
    let reference = Model::from_urdf_str(ARM).unwrap();
    let expected = (reference.nq(), reference.nv(), reference.frames().len());
    for h in handles {
        assert!(h.join().unwrap().iter().all(|&s| s == expected));
    }
}
