//! Bad input around files: meshes (missing, unreadable, unsupported format or scheme, unknown
//! package, flat), unreadable URDF files, and export errors. Each test asserts the variant and
//! that the message names the element.

use std::path::PathBuf;

use kinscene::scene::urdf::{ExportOptions, ImportOptions, read_file, write_string};
use kinscene::scene::{
    Error, Handle, Joint, Limits, PartSpec, SceneModel, SceneModelBuilder, Shape,
};
use nalgebra::{Isometry3, Point3, Vector3};

use super::TempDir;
use super::errors::fails;
use super::meshes::{TETRA, ascii_stl, mesh_robot};

#[test]
fn mesh_errors_name_the_uri_and_path() {
    let dir = TempDir::new("mesh-errors");
    let path = |f: &str| dir.path().join(f);
    let e = fails(
        &mesh_robot("nowhere.stl", "1 1 1"),
        Some(&dir),
        &["\"door\"", "nowhere.stl"],
    );
    assert!(
        matches!(&e, Error::MeshNotFound { uri, path: p, .. }
        if uri == "nowhere.stl" && *p == path("nowhere.stl")),
        "{e:?}"
    );

    std::fs::write(path("junk.stl"), "not a mesh").unwrap();
    let e = fails(&mesh_robot("junk.stl", "1 1 1"), Some(&dir), &["junk.stl"]);
    assert!(
        matches!(&e, Error::MeshUnreadable { path: p, .. } if *p == path("junk.stl")),
        "{e:?}"
    );
    std::fs::create_dir_all(path("folder.stl")).unwrap();
    let e = fails(
        &mesh_robot("folder.stl", "1 1 1"),
        Some(&dir),
        &["folder.stl"],
    );
    assert!(matches!(e, Error::MeshUnreadable { .. }), "{e:?}");

    std::fs::write(path("t.ply"), ascii_stl(&TETRA)).unwrap();
    let e = fails(&mesh_robot("t.ply", "1 1 1"), Some(&dir), &["t.ply"]);
    assert!(
        matches!(&e, Error::UnsupportedMeshFormat { path: p, .. } if *p == path("t.ply")),
        "{e:?}"
    );

    let e = fails(
        &mesh_robot("https://example.com/t.stl", "1 1 1"),
        None,
        &["https://example.com/t.stl"],
    );
    assert!(matches!(e, Error::UnsupportedMeshUri { .. }), "{e:?}");

    let e = fails(
        &mesh_robot("package://nope/t.stl", "1 1 1"),
        None,
        &["package://nope/t.stl", "\"nope\""],
    );
    assert!(
        matches!(&e, Error::UnknownPackage { package, .. } if package == "nope"),
        "{e:?}"
    );

    // A flat mesh spans no volume.
    let flat = TETRA.map(|[x, y, _]| [x, y, 0.0]);
    std::fs::write(path("flat.stl"), ascii_stl(&flat)).unwrap();
    let e = fails(
        &mesh_robot("flat.stl", "1 1 1"),
        Some(&dir),
        &["flat.stl", "\"door\""],
    );
    assert!(matches!(e, Error::DegenerateMesh { .. }), "{e:?}");
}

#[test]
fn unreadable_urdf_file_is_an_io_error() {
    let dir = TempDir::new("io");
    let missing = dir.path().join("missing.urdf");
    let e = read_file(&missing, &ImportOptions::default()).unwrap_err();
    assert!(
        matches!(&e, Error::Io { path, .. } if *path == missing),
        "{e:?}"
    );
    assert!(e.to_string().contains("missing.urdf"));
}

/// A one-part model with the given collider shape, part name and handle name.
fn model_with(shape: Shape, part: &str, handle: &str) -> SceneModel {
    let joint = Joint::revolute(
        "hinge",
        Point3::origin(),
        Vector3::z(),
        Limits::new(0.0, 1.0),
    );
    let mut b = SceneModelBuilder::new();
    b.add_part(
        PartSpec::on_base(part, joint)
            .with_collider(shape, Isometry3::identity())
            .with_handle(Handle::new(handle, Point3::origin(), Vector3::x())),
    );
    b.build().unwrap()
}

#[test]
fn export_errors() {
    let hull = Shape::ConvexMesh {
        vertices: TETRA
            .iter()
            .map(|v| Point3::new(v[0].into(), v[1].into(), v[2].into()))
            .collect(),
        source: None,
    };
    let e = write_string(&model_with(hull, "door", "knob"), &ExportOptions::default()).unwrap_err();
    assert!(matches!(e, Error::MeshWithoutSource { .. }), "{e:?}");
    assert!(e.to_string().contains("\"door\""));

    // The handle `door` is written as link `door_handle`, which is the part's name.
    let model = model_with(Shape::sphere(0.1), "door_handle", "door");
    let e = write_string(&model, &ExportOptions::default()).unwrap_err();
    assert!(
        matches!(&e, Error::UnwritableName { name, .. } if name == "door_handle"),
        "{e:?}"
    );

    let model = model_with(Shape::sphere(0.1), "bell\u{7}", "knob");
    let e = write_string(&model, &ExportOptions::default()).unwrap_err();
    assert!(
        matches!(&e, Error::UnwritableName { name, .. } if name == "bell\u{7}"),
        "{e:?}"
    );

    let options = ExportOptions {
        mesh_dir: Some(PathBuf::from("/proc/kinscene-no-such-dir/meshes")),
        ..ExportOptions::default()
    };
    let hull = Shape::ConvexMesh {
        vertices: TETRA
            .iter()
            .map(|v| Point3::new(v[0].into(), v[1].into(), v[2].into()))
            .collect(),
        source: None,
    };
    let e = write_string(&model_with(hull, "door", "knob"), &options).unwrap_err();
    assert!(
        matches!(&e, Error::Io { path, .. } if path.starts_with("/proc")),
        "{e:?}"
    );
}
