//! Typed errors for bad model descriptions.

use kinscene::scene::nav::NavGridSettings;
use kinscene::scene::{
    BaseShape, ElementKind, Error, Handle, Joint, JointKind, Limits, MIN_AXIS_NORM, PartSpec,
    SceneModelBuilder, Shape,
};
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};

use super::fixtures::kitchenette;

pub(super) fn hinge(name: &str, axis: Vector3<f64>, limits: Limits) -> Joint {
    Joint::revolute(name, Point3::origin(), axis, limits)
}

pub(super) fn part(name: &str, parent: Option<&str>, joint: Joint) -> PartSpec {
    let spec = match parent {
        None => PartSpec::on_base(name, joint),
        Some(p) => PartSpec::on_part(name, p, joint),
    };
    spec.with_collider(Shape::sphere(0.1), Isometry3::identity())
}

pub(super) fn ok_joint(name: &str) -> Joint {
    hinge(name, Vector3::z(), Limits::new(0.0, 1.0))
}

pub(super) fn build(parts: Vec<PartSpec>) -> Result<kinscene::scene::SceneModel, Error> {
    SceneModelBuilder {
        parts,
        ..Default::default()
    }
    .build()
}

#[test]
fn rejects_structural_errors() {
    let dup = build(vec![
        part("a", None, ok_joint("j1")),
        part("a", None, ok_joint("j2")),
    ]);
    assert_eq!(
        dup.unwrap_err(),
        Error::DuplicateName {
            kind: ElementKind::Part,
            name: "a".into()
        }
    );
    let dup = build(vec![
        part("a", None, ok_joint("j")),
        part("b", None, ok_joint("j")),
    ]);
    assert_eq!(
        dup.unwrap_err(),
        Error::DuplicateName {
            kind: ElementKind::Joint,
            name: "j".into()
        }
    );
    let unknown = build(vec![part("a", Some("ghost"), ok_joint("j"))]);
    assert_eq!(
        unknown.unwrap_err(),
        Error::UnknownParent {
            part: "a".into(),
            parent: "ghost".into()
        }
    );
    let empty = build(vec![part("", None, ok_joint("j"))]);
    assert_eq!(
        empty.unwrap_err(),
        Error::EmptyName {
            kind: ElementKind::Part
        }
    );
    // c -> a -> b -> a: the cycle is a, b (c hangs off it).
    let cycle = build(vec![
        part("c", Some("a"), ok_joint("j0")),
        part("a", Some("b"), ok_joint("j1")),
        part("b", Some("a"), ok_joint("j2")),
    ]);
    match cycle.unwrap_err() {
        Error::Cycle { parts } => {
            let mut sorted = parts.clone();
            sorted.sort();
            assert_eq!(sorted, vec!["a".to_string(), "b".to_string()]);
        }
        e => panic!("expected a cycle, got {e}"),
    }
    let self_loop = build(vec![part("a", Some("a"), ok_joint("j"))]);
    assert_eq!(
        self_loop.unwrap_err(),
        Error::Cycle {
            parts: vec!["a".into()]
        }
    );
}

#[test]
fn rejects_bad_joints() {
    let nan = build(vec![part(
        "a",
        None,
        hinge("j", Vector3::new(f64::NAN, 0.0, 1.0), Limits::new(0.0, 1.0)),
    )]);
    assert!(matches!(nan.unwrap_err(), Error::NonFinite { what } if what.contains("\"j\" axis")));
    // The zero-axis threshold is MIN_AXIS_NORM = 1e-9: just below is rejected, just above is
    // accepted and normalised.
    let tiny = build(vec![part(
        "a",
        None,
        hinge(
            "j",
            Vector3::z() * 0.5 * MIN_AXIS_NORM,
            Limits::new(0.0, 1.0),
        ),
    )]);
    assert_eq!(tiny.unwrap_err(), Error::ZeroAxis { joint: "j".into() });
    let small = build(vec![part(
        "a",
        None,
        hinge(
            "j",
            Vector3::z() * 2.0 * MIN_AXIS_NORM,
            Limits::new(0.0, 1.0),
        ),
    )]);
    assert_eq!(small.unwrap().joints()[0].axis, Vector3::z());
    let limits = build(vec![part(
        "a",
        None,
        hinge("j", Vector3::z(), Limits::new(1.0, 0.5)),
    )]);
    assert_eq!(
        limits.unwrap_err(),
        Error::InvalidLimits {
            joint: "j".into(),
            lower: 1.0,
            upper: 0.5
        }
    );
    let inf = build(vec![part(
        "a",
        None,
        hinge("j", Vector3::z(), Limits::new(f64::NEG_INFINITY, 0.5)),
    )]);
    assert!(matches!(inf.unwrap_err(), Error::NonFinite { .. }));
    let mut continuous =
        Joint::prismatic("j", Point3::origin(), Vector3::x(), Limits::new(0.0, 1.0));
    continuous.continuous = true;
    let cont = build(vec![part("a", None, continuous)]);
    assert_eq!(
        cont.unwrap_err(),
        Error::ContinuousPrismatic { joint: "j".into() }
    );
    let skewed = Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::new_unchecked(Quaternion::new(2.0, 0.0, 0.0, 0.0)),
    );
    let rot = build(vec![part(
        "a",
        None,
        Joint::new(
            "j",
            JointKind::Revolute,
            skewed,
            Vector3::z(),
            Limits::new(0.0, 1.0),
        ),
    )]);
    assert!(matches!(rot.unwrap_err(), Error::InvalidRotation { norm, .. } if norm == 2.0));
}

#[test]
fn rejects_bad_geometry_and_handles() {
    let with = |shape: Shape| {
        build(vec![
            PartSpec::on_base("a", ok_joint("j")).with_collider(shape, Isometry3::identity()),
        ])
    };
    let neg = with(Shape::cuboid(Vector3::new(0.1, -0.1, 0.1))).unwrap_err();
    assert!(
        matches!(neg, Error::NonPositive { what, value } if what.contains("half extent y") && value == -0.1)
    );
    assert!(matches!(
        with(Shape::sphere(f64::NAN)).unwrap_err(),
        Error::NonFinite { .. }
    ));
    assert!(matches!(
        with(Shape::cylinder(0.1, 0.0)).unwrap_err(),
        Error::NonPositive { .. }
    ));
    let flat = Shape::ConvexMesh {
        vertices: vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
        ],
        source: None,
    };
    assert!(matches!(
        with(flat).unwrap_err(),
        Error::DegenerateMesh { .. }
    ));
    let three = Shape::ConvexMesh {
        vertices: vec![Point3::origin(); 3],
        source: None,
    };
    assert!(matches!(
        with(three).unwrap_err(),
        Error::DegenerateMesh { .. }
    ));

    let zero_normal =
        build(vec![part("a", None, ok_joint("j")).with_handle(
            Handle::new("h", Point3::origin(), Vector3::zeros()),
        )]);
    assert_eq!(
        zero_normal.unwrap_err(),
        Error::ZeroNormal { handle: "h".into() }
    );
    let dup_handle = build(vec![
        part("a", None, ok_joint("j1")).with_handle(Handle::new(
            "h",
            Point3::origin(),
            Vector3::x(),
        )),
        part("b", None, ok_joint("j2")).with_handle(Handle::new(
            "h",
            Point3::origin(),
            Vector3::x(),
        )),
    ]);
    assert_eq!(
        dup_handle.unwrap_err(),
        Error::DuplicateName {
            kind: ElementKind::Handle,
            name: "h".into()
        }
    );

    let mut b = SceneModelBuilder::new();
    b.add_base_shape(BaseShape::new(
        "wall",
        Shape::sphere(1.0),
        Isometry3::identity(),
    ));
    b.nav_settings(NavGridSettings {
        resolution: 0.0,
        ..Default::default()
    });
    assert!(matches!(
        b.build().unwrap_err(),
        Error::InvalidSetting(s) if s.field == "nav.resolution"
    ));
    b.nav_settings(NavGridSettings {
        resolution: 1e-4,
        padding: 100.0,
        ..Default::default()
    });
    assert!(matches!(b.build().unwrap_err(), Error::GridTooLarge { .. }));
}

#[test]
fn model_round_trips_through_its_builder() {
    let m = kitchenette();
    let again = m.to_builder().build().unwrap();
    assert_eq!(m, again);
    assert_eq!(m.to_builder(), again.to_builder());
}

#[test]
fn out_of_range_values_are_rejected() {
    let far = build(vec![PartSpec::on_base("a", ok_joint("j")).with_collider(
        Shape::sphere(0.1),
        Isometry3::translation(1e7, 0.0, 0.0),
    )]);
    assert!(matches!(far.unwrap_err(), Error::OutOfRange { value, .. } if value == 1e7));
    let huge = build(vec![
        PartSpec::on_base("a", ok_joint("j"))
            .with_collider(Shape::sphere(1e300), Isometry3::identity()),
    ]);
    assert!(matches!(huge.unwrap_err(), Error::OutOfRange { .. }));
}
