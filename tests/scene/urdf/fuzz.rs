//! Fuzzing the importer: proptest over mutated documents. Seeds are exported generated scenes
//! (with OBJ meshes) and hand-written snippets (with STL, OBJ and COLLADA meshes); mutations
//! (`mutate.rs`) delete, duplicate and swap byte ranges and elements, replace numbers with NaN,
//! infinities, -0, huge or empty values, change joint types, break tags and inject unicode and
//! markup.
//!
//! Property: `read_str` returns `Ok` or `Err` and never panics; a model it returns exports and
//! re-imports. The case count is `PROPTEST_CASES` (default 300, a few seconds); a long
//! campaign: `PROPTEST_CASES=100000 cargo test --release --test lib urdf_fuzz`.

use std::cell::{Cell, RefCell};
use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

use kinscene::scene::urdf::{ExportOptions, ImportOptions, read_str, write_string};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseError, TestRunner};

use super::super::generators::urdf_scene;
use super::meshes::{TETRA, ascii_stl, binary_stl, dae, obj};
use super::mutate::{apply, mutation};
use super::{TempDir, cases};

/// Hand-written seeds; meshes resolve against the fuzz directory.
const SNIPPETS: [&str; 3] = [
    r#"<?xml version="1.0"?>
<robot name="kitchen">
  <link name="room">
    <collision name="floor"><origin xyz="0 0 -0.05" rpy="0 0 0"/><geometry><box size="4 4 0.1"/></geometry></collision>
    <collision><geometry><mesh filename="t.dae" scale="1 1 1"/></geometry></collision>
  </link>
  <link name="counter"><collision><origin xyz="0.1 0 0"/><geometry><mesh filename="bin.stl" scale="2 2 2"/></geometry></collision></link>
  <joint name="counter_fix" type="fixed"><origin xyz="2 0 0.45" rpy="0 0 1.5707963"/><parent link="room"/><child link="counter"/></joint>
  <link name="door"><collision><origin xyz="0 -0.3 0.4"/><geometry><box size="0.02 0.6 0.8"/></geometry></collision></link>
  <joint name="hinge" type="revolute"><origin xyz="0.31 0.3 0"/><parent link="counter"/><child link="door"/>
    <axis xyz="0 0 1"/><limit lower="0" upper="1.9" effort="0" velocity="0"/></joint>
  <link name="door_handle"/>
  <joint name="door_handle_joint" type="fixed"><origin xyz="0.03 -0.55 0.5" rpy="0 0 0"/><parent link="door"/><child link="door_handle"/></joint>
  <link name="drawer"><collision><geometry><mesh filename="t.obj"/></geometry></collision></link>
  <joint name="slide" type="prismatic"><origin xyz="0 0 0.1"/><parent link="door"/><child link="drawer"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.4" effort="0" velocity="0"/></joint>
</robot>"#,
    r#"<robot name="wheel" version="1.2">
  <link name="b"><visual><geometry><cylinder radius="1" length="2"/></geometry></visual></link>
  <link name="w"><collision><origin rpy="1.5707963267948966 0 0"/><geometry><cylinder radius="0.3" length="0.1"/></geometry></collision>
    <collision><geometry><capsule radius="0.1" length="0.2"/></geometry></collision></link>
  <joint name="spin" type="continuous"><parent link="b"/><child link="w"/><axis xyz="0 1 0"/><limit effort="1" velocity="2"/></joint>
  <link name="knob"><collision><geometry><mesh filename="ascii.stl" scale="0.5 0.5 0.5"/></geometry></collision></link>
  <joint name="knob_fix" type="fixed"><origin xyz="0.2 0 0"/><parent link="w"/><child link="knob"/></joint>
  <link name="knob_handle"/>
  <joint name="kh" type="fixed"><origin xyz="0.1 0 0" rpy="0 -1.5707963267948966 0"/><parent link="knob"/><child link="knob_handle"/></joint>
</robot>"#,
    r#"<robot name="m"><link name="a"/><link name="b"/><link name="c"/>
  <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 0"/><limit lower="1" upper="0" effort="0" velocity="0"/></joint>
  <joint name="j2" type="planar"><parent link="b"/><child link="c"/></joint>
  <gazebo><plugin name="x"><x><y/></x></plugin></gazebo>
</robot>"#,
];

#[test]
fn urdf_fuzz_mutated_documents_never_panic() {
    let dir = TempDir::new("fuzz");
    std::fs::write(dir.path().join("bin.stl"), binary_stl(&TETRA)).unwrap();
    std::fs::write(dir.path().join("ascii.stl"), ascii_stl(&TETRA)).unwrap();
    std::fs::write(dir.path().join("t.obj"), obj(&TETRA)).unwrap();
    std::fs::write(
        dir.path().join("t.dae"),
        dae(&[TETRA, TETRA.map(|[x, y, z]| [x, y, z + 1.0])]),
    )
    .unwrap();
    let export = ExportOptions {
        mesh_dir: Some(dir.path().join("meshes")),
        ..ExportOptions::default()
    };
    let import = ImportOptions {
        base_dir: Some(dir.path().to_path_buf()),
        ..ImportOptions::default()
    };

    let seed_export = export.clone();
    let seeds = prop_oneof![
        3 => urdf_scene(6).prop_map(move |m| write_string(&m, &seed_export).expect("generated scenes export")),
        2 => (0..SNIPPETS.len()).prop_map(|k| SNIPPETS[k].to_string()),
    ];
    let inputs = (seeds, prop::collection::vec(mutation(), 1..=3)).prop_map(|(seed, mutations)| {
        let mut doc = seed.into_bytes();
        for m in &mutations {
            apply(&mut doc, m);
        }
        String::from_utf8_lossy(&doc).into_owned()
    });

    let config = Config {
        cases: cases(300),
        failure_persistence: None,
        ..Config::default()
    };
    let mut runner = TestRunner::new(config);
    let (ok, err) = (Cell::new(0usize), Cell::new(0usize));
    let kinds = RefCell::new(BTreeMap::<String, usize>::new());
    let start = Instant::now();
    let result = runner.run(&inputs, |doc| {
        let outcome = catch_unwind(AssertUnwindSafe(|| read_str(&doc, &import)))
            .map_err(|_| TestCaseError::fail(format!("read_str panicked on input:\n{doc}")))?;
        match outcome {
            Err(e) => {
                err.set(err.get() + 1);
                let kind = format!("{e:?}");
                let kind = kind.split([' ', '{', '(']).next().unwrap_or("").to_string();
                *kinds.borrow_mut().entry(kind).or_default() += 1;
            }
            Ok(model) => {
                ok.set(ok.get() + 1);
                let text = write_string(&model, &export).map_err(|e| {
                    TestCaseError::fail(format!("export failed: {e}\ninput:\n{doc}"))
                })?;
                read_str(&text, &import).map_err(|e| {
                    TestCaseError::fail(format!("re-import failed: {e}\ninput:\n{doc}"))
                })?;
            }
        }
        Ok(())
    });
    eprintln!(
        "urdf fuzz: {} cases ({} imported, {} rejected) in {:.1} s",
        ok.get() + err.get(),
        ok.get(),
        err.get(),
        start.elapsed().as_secs_f64()
    );
    eprintln!("urdf fuzz: rejections by kind {:?}", kinds.borrow());
    if let Err(e) = result {
        panic!("{e}");
    }
}
