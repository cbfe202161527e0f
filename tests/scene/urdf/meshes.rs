//! Meshes: STL (binary and ASCII), OBJ and COLLADA files written into a temporary directory,
//! loaded with their scale, resolved through base directories, package:// and file:// URIs.

use std::collections::BTreeMap;
use std::path::Path;

use kinscene::scene::urdf::{ExportOptions, ImportOptions, read_file, read_str, write_string};
use kinscene::scene::{MeshSource, SceneModel, Shape};
use nalgebra::Vector3;

use super::{TempDir, robot};

/// A tetrahedron with coordinates exact in `f32` (mesh-loader reads `f32`): its bounding box
/// is [0, 0.5] × [0, 0.25] × [0, 0.125].
pub const TETRA: [[f32; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [0.5, 0.0, 0.0],
    [0.0, 0.25, 0.0],
    [0.0, 0.0, 0.125],
];
/// The tetrahedron's faces (outward, counter-clockwise), 0-based.
const FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];

/// A binary STL of `vertices` and `FACES`.
pub fn binary_stl(vertices: &[[f32; 3]; 4]) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&(FACES.len() as u32).to_le_bytes());
    for f in FACES {
        out.extend_from_slice(&[0u8; 12]); // normal, recomputed by readers
        for &v in &f {
            for c in vertices[v] {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        out.extend_from_slice(&[0u8; 2]);
    }
    out
}

/// An ASCII STL of `vertices` and `FACES`.
pub fn ascii_stl(vertices: &[[f32; 3]; 4]) -> String {
    let mut out = String::from("solid tetra\n");
    for f in FACES {
        out.push_str(" facet normal 0 0 0\n  outer loop\n");
        for &v in &f {
            let [x, y, z] = vertices[v];
            out.push_str(&format!("   vertex {x} {y} {z}\n"));
        }
        out.push_str("  endloop\n endfacet\n");
    }
    out.push_str("endsolid tetra\n");
    out
}

/// An OBJ of `vertices` and `FACES`.
pub fn obj(vertices: &[[f32; 3]; 4]) -> String {
    let mut out = String::new();
    for [x, y, z] in vertices {
        out.push_str(&format!("v {x} {y} {z}\n"));
    }
    for [a, b, c] in FACES {
        out.push_str(&format!("f {} {} {}\n", a + 1, b + 1, c + 1));
    }
    out
}

/// A COLLADA document with one tetrahedron geometry per entry of `meshes`.
pub fn dae(meshes: &[[[f32; 3]; 4]]) -> String {
    let (mut geometries, mut nodes) = (String::new(), String::new());
    for (k, m) in meshes.iter().enumerate() {
        let floats: Vec<String> = m.iter().flatten().map(|c| c.to_string()).collect();
        let p: Vec<String> = FACES.iter().flatten().map(|i| i.to_string()).collect();
        geometries.push_str(&format!(
            r##"<geometry id="g{k}"><mesh>
  <source id="g{k}-pos"><float_array id="g{k}-arr" count="12">{}</float_array>
    <technique_common><accessor source="#g{k}-arr" count="4" stride="3">
      <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
    </accessor></technique_common></source>
  <vertices id="g{k}-vtx"><input semantic="POSITION" source="#g{k}-pos"/></vertices>
  <triangles count="4"><input semantic="VERTEX" source="#g{k}-vtx" offset="0"/><p>{}</p></triangles>
</mesh></geometry>"##,
            floats.join(" "),
            p.join(" ")
        ));
        nodes.push_str(&format!(
            r##"<node id="n{k}"><instance_geometry url="#g{k}"/></node>"##
        ));
    }
    format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
<library_geometries>{geometries}</library_geometries>
<library_visual_scenes><visual_scene id="s">{nodes}</visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##
    )
}

/// A scene whose part `door` has one mesh collision element `filename` with `scale`.
pub fn mesh_robot(filename: &str, scale: &str) -> String {
    robot(&format!(
        r#"<link name="b"/><link name="door"><collision>
          <geometry><mesh filename="{filename}" scale="{scale}"/></geometry></collision></link>
        <joint name="hinge" type="revolute"><parent link="b"/><child link="door"/>
          <limit lower="0" upper="1" effort="0" velocity="0"/></joint>"#
    ))
}

/// Axis-aligned bounds of the vertices of the part's colliders, one entry per collider.
fn bounds(model: &SceneModel) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    model.parts()[0]
        .colliders()
        .iter()
        .map(|c| match &c.shape {
            Shape::ConvexMesh { vertices, .. } => vertices.iter().fold(
                (
                    Vector3::repeat(f64::INFINITY),
                    Vector3::repeat(f64::NEG_INFINITY),
                ),
                |(lo, hi), v| (lo.inf(&v.coords), hi.sup(&v.coords)),
            ),
            other => panic!("expected a convex mesh, got {other:?}"),
        })
        .collect()
}

/// Scale (2, -1, 4) maps the tetrahedron's bounds [0, 0.5]×[0, 0.25]×[0, 0.125] to
/// [0, 1]×[-0.25, 0]×[0, 0.5].
fn assert_scaled_tetra(model: &SceneModel, uri: &str) {
    assert_eq!(
        bounds(model),
        [(Vector3::new(0.0, -0.25, 0.0), Vector3::new(1.0, 0.0, 0.5))]
    );
    let Shape::ConvexMesh { source, .. } = &model.parts()[0].colliders()[0].shape else {
        unreachable!()
    };
    let expected = MeshSource {
        uri: uri.to_string(),
        scale: Vector3::new(2.0, -1.0, 4.0),
    };
    assert_eq!(source.as_ref(), Some(&expected));
}

fn with_base_dir(dir: &Path) -> ImportOptions {
    ImportOptions {
        base_dir: Some(dir.to_path_buf()),
        ..ImportOptions::default()
    }
}

#[test]
fn stl_obj_and_dae_load_with_scale() {
    let dir = TempDir::new("formats");
    std::fs::write(dir.path().join("bin.stl"), binary_stl(&TETRA)).unwrap();
    std::fs::write(dir.path().join("ascii.STL"), ascii_stl(&TETRA)).unwrap();
    std::fs::write(dir.path().join("t.obj"), obj(&TETRA)).unwrap();
    std::fs::write(dir.path().join("t.dae"), dae(&[TETRA])).unwrap();
    for file in ["bin.stl", "ascii.STL", "t.obj", "t.dae"] {
        let xml = mesh_robot(file, "2 -1 4");
        let model = read_str(&xml, &with_base_dir(dir.path())).unwrap();
        assert_scaled_tetra(&model, file);
    }
}

#[test]
fn package_file_and_relative_uris_resolve() {
    let dir = TempDir::new("uris");
    std::fs::create_dir_all(dir.path().join("kitchen/meshes")).unwrap();
    let path = dir.path().join("kitchen/meshes/t.stl");
    std::fs::write(&path, binary_stl(&TETRA)).unwrap();

    let uri = "package://kitchen_description/meshes/t.stl";
    let mut package_paths = BTreeMap::new();
    package_paths.insert(
        "kitchen_description".to_string(),
        dir.path().join("kitchen"),
    );
    let options = ImportOptions {
        package_paths,
        ..ImportOptions::default()
    };
    assert_scaled_tetra(
        &read_str(&mesh_robot(uri, "2 -1 4"), &options).unwrap(),
        uri,
    );

    let uri = format!("file://{}", path.display());
    let model = read_str(&mesh_robot(&uri, "2 -1 4"), &ImportOptions::default()).unwrap();
    assert_scaled_tetra(&model, &uri);

    // read_file resolves relative paths against the file's directory.
    let urdf = dir.path().join("kitchen/scene.urdf");
    std::fs::write(&urdf, mesh_robot("meshes/t.stl", "2 -1 4")).unwrap();
    assert_scaled_tetra(
        &read_file(&urdf, &ImportOptions::default()).unwrap(),
        "meshes/t.stl",
    );
}

/// A mesh without `scale` has scale 1; each sub-mesh of a COLLADA file is one collider.
#[test]
fn sub_meshes_become_colliders() {
    let dir = TempDir::new("submeshes");
    let shifted = TETRA.map(|[x, y, z]| [x + 1.0, y, z]);
    std::fs::write(dir.path().join("two.dae"), dae(&[TETRA, shifted])).unwrap();
    let xml = robot(
        r#"<link name="b"/><link name="door"><collision><geometry><mesh filename="two.dae"/></geometry></collision></link>
        <joint name="hinge" type="revolute"><parent link="b"/><child link="door"/>
          <limit lower="0" upper="1" effort="0" velocity="0"/></joint>"#,
    );
    let model = read_str(&xml, &with_base_dir(dir.path())).unwrap();
    assert_eq!(
        bounds(&model),
        [
            (Vector3::zeros(), Vector3::new(0.5, 0.25, 0.125)),
            (Vector3::new(1.0, 0.0, 0.0), Vector3::new(1.5, 0.25, 0.125)),
        ]
    );
}

/// Base shapes from a mesh with several sub-meshes are named `<name>/<i>`; export writes them
/// back as one `<mesh>` element and re-import gives the same model.
#[test]
fn base_sub_meshes_are_named_and_exported_once() {
    let dir = TempDir::new("base-submeshes");
    let path = dir.path().join("carcass.dae");
    std::fs::write(&path, dae(&[TETRA, TETRA.map(|[x, y, z]| [x, y, z + 1.0])])).unwrap();
    let xml = robot(&format!(
        r#"<link name="room"><collision name="carcass"><origin xyz="1 0 0"/>
          <geometry><mesh filename="{}"/></geometry></collision></link>"#,
        path.display()
    ));
    let model = read_str(&xml, &ImportOptions::default()).unwrap();
    let names: Vec<&str> = model
        .base()
        .shapes
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(names, ["carcass/0", "carcass/1"]);
    let exported = write_string(&model, &ExportOptions::default()).unwrap();
    assert_eq!(exported.matches("<collision name=\"carcass\">").count(), 1);
    assert_eq!(
        exported.matches("<mesh ").count(),
        2,
        "one visual, one collision"
    );
    let again = read_str(&exported, &ImportOptions::default()).unwrap();
    assert_eq!(again, model);
    let vertex = |m: &SceneModel| match &m.base().shapes[1].shape {
        Shape::ConvexMesh { vertices, .. } => vertices[0],
        _ => unreachable!(),
    };
    assert_eq!(vertex(&again), vertex(&model));
    assert!(
        vertex(&model).z >= 1.0,
        "second sub-mesh is the shifted one"
    );
}
