//! URDF import/export tests: hand-written snippets with hand-derived poses, meshes written to
//! temporary files, one test per error kind, round-trip property tests on generated scenes,
//! and fuzzing of the importer with mutated documents.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use kinscene::scene::SceneModel;
use kinscene::scene::urdf::{ImportOptions, read_str};
use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};

mod errors;
mod fuzz;
mod io_errors;
mod meshes;
mod mutate;
mod roundtrip;
mod snippets;

/// A fresh directory under the system temp dir, removed when dropped.
pub struct TempDir(PathBuf);

impl TempDir {
    /// Creates `<temp>/kinscene-urdf-<tag>-<pid>-<n>`.
    pub fn new(tag: &str) -> TempDir {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir =
            std::env::temp_dir().join(format!("kinscene-urdf-{tag}-{}-{n}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("create temp dir");
        TempDir(dir)
    }

    /// The directory.
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// `<robot name="test">body</robot>`.
pub fn robot(body: &str) -> String {
    format!("<robot name=\"test\">{body}</robot>")
}

/// Imports with default options, panicking with the error's message.
pub fn import(xml: &str) -> SceneModel {
    read_str(xml, &ImportOptions::default()).unwrap_or_else(|e| panic!("import failed: {e}"))
}

/// The angle (rad) of the rotation between `a` and `b`, accurate for tiny angles (the
/// `acos`-based `angle_to` has an error of about 3e-8 rad near 0).
pub fn rotation_angle(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> f64 {
    let q = a.inverse() * b;
    2.0 * q.imag().norm().atan2(q.scalar().abs())
}

/// The angle (rad) between two vectors, accurate for tiny angles.
pub fn vector_angle(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    a.cross(b).norm().atan2(a.dot(b))
}

/// Asserts two poses agree: translations within `tol` m, rotations within `tol` rad.
pub fn assert_pose(actual: &Isometry3<f64>, expected: &Isometry3<f64>, tol: f64) {
    let dt = (actual.translation.vector - expected.translation.vector).norm();
    let dr = rotation_angle(&actual.rotation, &expected.rotation);
    assert!(
        dt <= tol && dr <= tol,
        "pose {actual:?} differs from {expected:?} by {dt} m, {dr} rad"
    );
}

/// Asserts two points agree within `tol` m.
pub fn assert_point(actual: &Point3<f64>, expected: &Point3<f64>, tol: f64) {
    let d = (actual - expected).norm();
    assert!(d <= tol, "{actual:?} differs from {expected:?} by {d}");
}

/// Asserts two vectors agree within `tol`.
pub fn assert_vector(actual: &Vector3<f64>, expected: &Vector3<f64>, tol: f64) {
    let d = (actual - expected).norm();
    assert!(d <= tol, "{actual:?} differs from {expected:?} by {d}");
}

/// Proptest case count: `PROPTEST_CASES` if set, else `default`.
pub fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}
