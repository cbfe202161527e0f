//! Round trips: generated scenes survive build → export → import within stated tolerances,
//! and export → import → export reproduces the text exactly.
//!
//! Tolerances: lengths, limits, scales and translations are written with Rust's shortest
//! round-trip formatting and compared exactly. Rotations are written as `rpy` on a 1e-12 rad
//! grid (the exporter's documented precision, about 1e-11 rad on the rotation), compared
//! within 1e-9 rad. Axes are re-normalised to an exact unit vector (a few ulps), compared
//! within 1e-12. Convex meshes without a source come back from an OBJ file that mesh-loader
//! reads as `f32`: coordinates of at most 0.3 m in magnitude are rounded by at most
//! 0.3·2⁻²⁴ ≈ 1.8e-8 m per component, compared within 1e-7 m.

use kinscene::scene::urdf::{
    ExportOptions, ImportOptions, read_file, read_str, write_file, write_string,
};
use kinscene::scene::{BaseShape, Parent, SceneModel, SceneModelBuilder, Shape};
use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use proptest::strategy::ValueTree;

use super::super::fixtures::kitchenette;
use super::super::generators::{hull_points, urdf_scene};
use super::{TempDir, cases, import, robot, rotation_angle, vector_angle};

const ROTATION_TOL: f64 = 1e-9;
const AXIS_TOL: f64 = 1e-12;
const MESH_TOL: f64 = 1e-7;

fn check_pose(what: &str, a: &Isometry3<f64>, b: &Isometry3<f64>) -> Result<(), String> {
    if a.translation != b.translation {
        return Err(format!("{what}: translation {a:?} became {b:?}"));
    }
    let angle = rotation_angle(&a.rotation, &b.rotation);
    if angle > ROTATION_TOL {
        return Err(format!("{what}: rotation off by {angle} rad"));
    }
    Ok(())
}

fn check_shape(what: &str, a: &Shape, b: &Shape) -> Result<(), String> {
    match (a, b) {
        (
            Shape::ConvexMesh {
                vertices: va,
                source: None,
            },
            Shape::ConvexMesh {
                vertices: vb,
                source: Some(s),
            },
        ) => {
            if !s.uri.ends_with(".obj") || s.scale != Vector3::repeat(1.0) {
                return Err(format!("{what}: unexpected source {s:?}"));
            }
            // Every vertex read back is a hull vertex (within f32 rounding) of the original, and
            // the hull keeps the extreme points, so the bounding boxes agree.
            let near = |p: &Point3<f64>| va.iter().any(|q| (p - q).norm() <= MESH_TOL);
            if let Some(p) = vb.iter().find(|p| !near(p)) {
                return Err(format!("{what}: vertex {p:?} is not an original vertex"));
            }
            let bounds = |v: &[Point3<f64>]| {
                v.iter().fold(
                    (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN)),
                    |(lo, hi), p| (lo.inf(&p.coords), hi.sup(&p.coords)),
                )
            };
            let ((la, ha), (lb, hb)) = (bounds(va), bounds(vb));
            if (la - lb).norm() > MESH_TOL || (ha - hb).norm() > MESH_TOL {
                return Err(format!("{what}: bounds changed"));
            }
            Ok(())
        }
        _ if a == b => Ok(()),
        _ => Err(format!("{what}: shape {a:?} became {b:?}")),
    }
}

/// Compares `b` (imported) with `a` (exported) field by field within the module's tolerances.
fn check_same(a: &SceneModel, b: &SceneModel) -> Result<(), String> {
    let base_name = a.base().name.clone().unwrap_or_else(|| "base".into());
    if b.base().name.as_deref() != Some(&base_name) || a.base().nav != b.base().nav {
        return Err(format!(
            "base {:?} became {:?}",
            a.base().name,
            b.base().name
        ));
    }
    let (sa, sb): (&[BaseShape], &[BaseShape]) = (&a.base().shapes, &b.base().shapes);
    if sa.len() != sb.len() {
        return Err(format!("{} base shapes became {}", sa.len(), sb.len()));
    }
    for (x, y) in sa.iter().zip(sb) {
        let what = format!("base shape {:?}", x.name);
        if x.name != y.name {
            return Err(format!("{what} renamed to {:?}", y.name));
        }
        check_shape(&what, &x.shape, &y.shape)?;
        check_pose(&what, &x.world_from_shape, &y.world_from_shape)?;
    }
    if a.parts().len() != b.parts().len() {
        return Err(format!(
            "{} parts became {}",
            a.parts().len(),
            b.parts().len()
        ));
    }
    for ((pa, pb), (ja, jb)) in a
        .parts()
        .iter()
        .zip(b.parts())
        .zip(a.joints().iter().zip(b.joints()))
    {
        let what = format!("part {:?}", pa.name());
        let parent = |m: &SceneModel, p: Parent| match p {
            Parent::Base => None,
            Parent::Part(id) => Some(m.parts()[id.index()].name().to_string()),
        };
        if pa.name() != pb.name() || parent(a, pa.parent()) != parent(b, pb.parent()) {
            return Err(format!("{what} became {:?} or changed parent", pb.name()));
        }
        if (ja.name.as_str(), ja.kind, ja.continuous, ja.limits)
            != (jb.name.as_str(), jb.kind, jb.continuous, jb.limits)
        {
            return Err(format!("joint {ja:?} became {jb:?}"));
        }
        if (ja.axis - jb.axis).norm() > AXIS_TOL {
            return Err(format!(
                "joint {:?} axis {} became {}",
                ja.name, ja.axis, jb.axis
            ));
        }
        check_pose(
            &format!("joint {:?} origin", ja.name),
            &ja.parent_from_joint,
            &jb.parent_from_joint,
        )?;
        if pa.colliders().len() != pb.colliders().len() {
            return Err(format!(
                "{what}: {} colliders became {}",
                pa.colliders().len(),
                pb.colliders().len()
            ));
        }
        for (k, (ca, cb)) in pa.colliders().iter().zip(pb.colliders()).enumerate() {
            check_shape(&format!("{what} collider {k}"), &ca.shape, &cb.shape)?;
            check_pose(
                &format!("{what} collider {k}"),
                &ca.part_from_shape,
                &cb.part_from_shape,
            )?;
        }
        if pa.handles().len() != pb.handles().len() {
            return Err(format!("{what}: handle count changed"));
        }
        for (ha, hb) in pa.handles().iter().zip(pb.handles()) {
            let angle = vector_angle(&ha.normal, &hb.normal);
            if ha.name != hb.name || ha.position != hb.position || angle > ROTATION_TOL {
                return Err(format!("handle {ha:?} became {hb:?}"));
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(48), ..ProptestConfig::default() })]

    /// build → write_string → read_str gives the same model; the export parses with urdf-rs;
    /// exporting the imported model reproduces the text.
    #[test]
    fn generated_scenes_round_trip(model in urdf_scene(12)) {
        let dir = TempDir::new("roundtrip");
        let options = ExportOptions { mesh_dir: Some(dir.path().join("meshes")), ..ExportOptions::default() };
        let text = write_string(&model, &options).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let robot = urdf_rs::read_from_string(&text).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(robot.joints.len(), model.nq() + model.handles().count());
        let back = read_str(&text, &ImportOptions::default()).map_err(|e| TestCaseError::fail(e.to_string()))?;
        check_same(&model, &back).map_err(TestCaseError::fail)?;
        let again = write_string(&back, &options).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(again, text);
    }
}

/// write_file with a relative mesh directory writes the OBJ files next to the URDF and
/// references them relatively, so read_file finds them.
#[test]
fn files_round_trip_with_a_relative_mesh_dir() {
    let mut builder: SceneModelBuilder = kitchenette().to_builder();
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let points = hull_points().new_tree(&mut runner).unwrap().current();
    let hull = Shape::ConvexMesh {
        vertices: points,
        source: None,
    };
    builder.add_base_shape(BaseShape::new(
        "rock",
        hull.clone(),
        Isometry3::translation(3.0, 0.0, 0.0),
    ));
    builder.parts[0]
        .colliders
        .push(kinscene::scene::Collider::new(hull, Isometry3::identity()));
    let model = builder.build().unwrap();

    let dir = TempDir::new("files");
    let path = dir.path().join("scene.urdf");
    let options = ExportOptions {
        mesh_dir: Some("meshes".into()),
        robot_name: Some("kitchenette".into()),
    };
    write_file(&model, &path, &options).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("<robot name=\"kitchenette\">"));
    assert!(text.contains("filename=\"meshes/"), "relative mesh URIs");
    let objs = std::fs::read_dir(dir.path().join("meshes"))
        .unwrap()
        .count();
    assert_eq!(objs, 2);
    let back = read_file(&path, &ImportOptions::default()).unwrap();
    check_same(&model, &back).unwrap();
    write_file(&back, &path, &options).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
}

/// Rotations at and near gimbal lock (pitch ±π/2, and a human-written 1.5708) round-trip
/// within tolerance and re-export to the same text.
#[test]
fn rotations_near_gimbal_lock_are_a_textual_fixed_point() {
    let mut body = String::from(r#"<link name="b"/>"#);
    let angles = [
        "0 1.5707963267948966 0.3",
        "0.2 1.5708 -0.4",
        "-3 -1.5707963 2",
        "3.14159 0 -3.14159",
        "1e-9 -1.5707963267948966 0",
    ];
    for (k, rpy) in angles.iter().enumerate() {
        body.push_str(&format!(
            r#"<link name="p{k}"><collision><origin rpy="{rpy}"/><geometry><sphere radius="0.1"/></geometry></collision></link>
            <joint name="j{k}" type="revolute"><origin xyz="0 0 {k}" rpy="{rpy}"/><parent link="b"/><child link="p{k}"/>
              <limit lower="0" upper="1" effort="0" velocity="0"/></joint>"#
        ));
    }
    let model = import(&robot(&body));
    for (k, rpy) in angles.iter().enumerate() {
        let v: Vec<f64> = rpy.split(' ').map(|x| x.parse().unwrap()).collect();
        let expected = UnitQuaternion::from_euler_angles(v[0], v[1], v[2]);
        assert!(rotation_angle(&model.joints()[k].parent_from_joint.rotation, &expected) < 1e-15);
    }
    let text = write_string(&model, &ExportOptions::default()).unwrap();
    let back = import(&text);
    check_same(&model, &back).unwrap();
    assert_eq!(
        write_string(&back, &ExportOptions::default()).unwrap(),
        text
    );
}
