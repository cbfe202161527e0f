//! Import and export options.

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::PathBuf;

use crate::scene::Limits;
use crate::scene::nav::NavGridSettings;

/// How a URDF document becomes a [`SceneModel`](crate::scene::SceneModel).
#[derive(Debug, Clone, PartialEq)]
pub struct ImportOptions {
    /// Package roots: `package://NAME/rest` resolves to `package_paths[NAME]/rest`. Default
    /// empty (a `package://` URI then fails with [`Error::UnknownPackage`]).
    ///
    /// [`Error::UnknownPackage`]: crate::scene::Error::UnknownPackage
    pub package_paths: BTreeMap<String, PathBuf>,
    /// Directory that relative mesh paths resolve against. `None`: the current directory.
    /// [`read_file`](super::read_file) uses the file's directory when this is `None`.
    pub base_dir: Option<PathBuf>,
    /// Working range given to `continuous` joints (rad). Default `[-π, π]`.
    pub continuous_limits: Limits,
    /// Navigation-grid settings of the base map (URDF has none). Default
    /// [`NavGridSettings::default`].
    pub nav: NavGridSettings,
}

impl Default for ImportOptions {
    fn default() -> Self {
        ImportOptions {
            package_paths: BTreeMap::new(),
            base_dir: None,
            continuous_limits: Limits::new(-PI, PI),
            nav: NavGridSettings::default(),
        }
    }
}

/// How a [`SceneModel`](crate::scene::SceneModel) is written as URDF.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExportOptions {
    /// `<robot name>`. `None`: `"kinscene_scene"`.
    pub robot_name: Option<String>,
    /// Directory where convex meshes without a source file are written, one OBJ file (the
    /// convex hull) each, created if missing; existing files of the same name are replaced.
    /// The URDF references them as `mesh_dir/<file>.obj`. For
    /// [`write_file`](super::write_file), a relative `mesh_dir` is relative to the URDF file's
    /// directory (and stays relative in the URDF, so the pair can be moved together); for
    /// [`write_string`](super::write_string), to the current directory. `None`: such meshes
    /// are an error ([`Error::MeshWithoutSource`](crate::scene::Error::MeshWithoutSource)).
    pub mesh_dir: Option<PathBuf>,
}

/// `<robot name>` written when [`ExportOptions::robot_name`] is `None`.
pub(super) const DEFAULT_ROBOT_NAME: &str = "kinscene_scene";

/// Name of the base link written when the base map has no name.
pub(super) const DEFAULT_BASE_NAME: &str = "base";
