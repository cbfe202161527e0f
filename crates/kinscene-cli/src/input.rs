//! Input files shared by the subcommands: the scene URDF (with `--package` paths), goal
//! documents and plan documents. Every error names the file it comes from.

use std::path::{Path, PathBuf};

use kinscene::scene::SceneModel;
use kinscene::scene::urdf::{ImportOptions, read_file};
use kinscene::task::{PlanFile, Problem};

use crate::CliError;

/// The scene arguments every subcommand takes: `--scene S.urdf [--package NAME=PATH ...]`.
#[derive(Debug, clap::Args)]
pub struct SceneArgs {
    /// The scene URDF file.
    #[arg(long, value_name = "FILE")]
    pub scene: PathBuf,
    /// Resolve `package://NAME/...` mesh URIs under PATH (repeatable).
    #[arg(long = "package", value_name = "NAME=PATH", value_parser = parse_package)]
    pub packages: Vec<(String, PathBuf)>,
}

/// Parses `NAME=PATH`.
fn parse_package(s: &str) -> Result<(String, PathBuf), String> {
    match s.split_once('=') {
        Some((name, path)) if !name.is_empty() && !path.is_empty() => {
            Ok((name.to_string(), PathBuf::from(path)))
        }
        _ => Err(format!("expected NAME=PATH, got {s:?}")),
    }
}

impl SceneArgs {
    /// Loads the scene ([`read_file`]): relative mesh paths resolve against the URDF's
    /// directory, `package://NAME/rest` against the `--package` paths.
    ///
    /// # Errors
    /// A [`CliError`] naming the file for an unreadable or malformed URDF or an invalid scene,
    /// or a package name given twice.
    pub fn load(&self) -> Result<SceneModel, CliError> {
        let mut options = ImportOptions::default();
        for (name, path) in &self.packages {
            if options
                .package_paths
                .insert(name.clone(), path.clone())
                .is_some()
            {
                return Err(CliError::new(format!("package {name:?} given twice")));
            }
        }
        read_file(&self.scene, &options).map_err(|e| match e {
            // The I/O error names the file already.
            kinscene::scene::Error::Io { .. } => CliError::new(e.to_string()),
            _ => CliError::new(format!("{}: {e}", self.scene.display())),
        })
    }
}

/// A [`CliError`] for a problem with the file at `path`: `<path>: <message>`.
pub fn file_error(path: &Path, e: impl std::fmt::Display) -> CliError {
    CliError::new(format!("{}: {e}", path.display()))
}

/// Reads the goal document at `path` and resolves it against `model`
/// ([`Problem::from_goal_file`]: JSON if its name ends in `.json`, TOML otherwise).
///
/// # Errors
/// A [`CliError`] naming the file: unreadable, malformed, an unknown joint, a target or start
/// value outside the joint's limits, an invalid robot.
pub fn load_problem(model: &SceneModel, path: &Path) -> Result<Problem, CliError> {
    Problem::from_goal_file(model, path).map_err(|e| CliError::new(e.to_string()))
}

/// Reads the plan document at `path` ([`PlanFile::from_file`]).
///
/// # Errors
/// A [`CliError`] naming the file: unreadable or malformed.
pub fn load_plan(path: &Path) -> Result<PlanFile, CliError> {
    PlanFile::from_file(path).map_err(|e| CliError::new(e.to_string()))
}
