//! The robot description file (TOML), [`RobotDescription`], and its loader.

mod footprint;
mod load;
mod paths;

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::{BaseKind, DEFAULT_BASE_ACCELERATION, DEFAULT_BASE_VELOCITY, RobotError};
#[cfg(doc)]
use super::{MobileBase, RobotModel};

/// A robot description file: everything the loader needs besides the URDF — package paths,
/// the tool, the arm root, the SRDF, frozen joints, the stowed configuration and the mobile
/// base — for the library ([`RobotModel::from_description_file`]) and the CLI
/// (`kinscene plan --robot robot.toml`). Unknown keys are errors. Paths are kept as written;
/// [`RobotModel::from_description`] resolves them.
///
/// ```toml
/// urdf = "kinova_gen3_mobile.urdf"    # relative to this file, or package://NAME/rest
/// srdf = "kinova_gen3_mobile.srdf"    # optional: disable_collisions pairs and stow state
///
/// [packages]                          # optional: package://NAME roots for meshes
/// my_robot_description = "${MY_ROBOT}/share/my_robot_description"
///
/// [tool]
/// link = "tool_frame"                 # the TCP link (required)
/// approach = [0.0, 0.0, 1.0]          # optional: approach axis in the link frame (default +z)
/// contact_links = ["left_pad"]        # optional: default, links named *finger* or *pad*
///
/// [arm]
/// root = "torso_lift_link"            # optional: the link the arm starts at
///
/// [frozen]                            # optional: values of movable joints off the arm
/// head_1_joint = 0.0
///
/// [stow]                              # optional: every arm joint's stowed value
/// joint_1 = 0.0
///
/// [base]                              # optional
/// kind = "holonomic"                  # or "differential_drive"; default "holonomic"
/// max_velocity = [0.5, 0.5, 1.0]      # x, y (m/s), yaw (rad/s); y = 0 for a differential drive
/// max_acceleration = [0.5, 0.5, 1.0]  # x, y (m/s²), yaw (rad/s²)
/// footprint_radius = 0.45             # optional (m): default computed at the stow
/// # footprint = [[-0.3, -0.25], [0.3, -0.25], [0.3, 0.25], [-0.3, 0.25]]  # or a polygon (m)
/// ```
///
/// # Paths
/// `urdf`, `srdf` and the `[packages]` values are file paths: `${NAME}` is replaced by the
/// environment variable `NAME` (for data installed in a place only the user knows, such as a
/// Python environment: `${EXAMPLE_ROBOT_DATA}`); `urdf` and `srdf` may be
/// `package://NAME/rest` URIs resolved through `[packages]`; relative paths resolve against
/// the description file's directory.
///
/// # Stowed configuration
/// [`RobotModel::neutral`] is, in this order: the SRDF's stow group state
/// ([`Srdf::stow_state`](super::Srdf::stow_state)); the description's `[stow]` (which must name
/// every arm joint, within its limits, free of self-collision; it is checked even when the
/// SRDF's wins); otherwise the computed stow ([`RobotModel::with_computed_stow`] with
/// [`StowSearch::default`](super::StowSearch)). Without an SRDF, the self-collision exemptions
/// are computed ([`RobotModel::with_sampled_pairs`] with
/// [`PairSampling::default`](super::PairSampling)).
///
/// # Footprint
/// The footprint is a radius ([`MobileBase::footprint_radius`]) or a polygon in the base frame
/// (`footprint`, as navigation stacks write it), never both. The navigation grid inflates
/// obstacles by a disc, so a polygon becomes the disc about the base origin that encloses it
/// at every yaw (its farthest vertex): sound, and as conservative as that disc; a
/// yaw-dependent grid that would use the polygon's shape is not built. Base poses and base
/// paths are always checked against the robot's real collision shapes.
///
/// # Bad input
/// Every bad input is a [`RobotError`] naming its element: [`RobotError::Description`] for the
/// file itself (TOML syntax, unknown keys, missing `urdf` or `[tool] link`, values of the wrong
/// type, an unknown base kind, an unset variable, a bad stow), and the URDF and SRDF loaders'
/// errors for what they find.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RobotDescription {
    /// The robot URDF: a path (relative to the description file) or a `package://` URI;
    /// `${NAME}` is an environment variable.
    pub urdf: String,
    /// The robot's SRDF (optional), written as [`RobotDescription::urdf`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub srdf: Option<String>,
    /// `package://NAME` roots: `NAME = "path"` (relative to the description file; `${NAME}`
    /// expanded).
    #[serde(default)]
    pub packages: BTreeMap<String, String>,
    /// The tool.
    pub tool: ToolDescription,
    /// The arm.
    #[serde(default)]
    pub arm: ArmDescription,
    /// Values (rad or m) of movable joints that are not arm joints
    /// ([`RobotImportOptions::frozen`](super::RobotImportOptions::frozen)).
    #[serde(default)]
    pub frozen: BTreeMap<String, f64>,
    /// The stowed configuration: arm joint name → value (rad or m). Empty: the SRDF's or the
    /// computed one (see [`RobotDescription`]).
    #[serde(default)]
    pub stow: BTreeMap<String, f64>,
    /// The mobile base.
    #[serde(default)]
    pub base: BaseDescription,
}

/// The `[tool]` table.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ToolDescription {
    /// The link whose frame is the tool frame (TCP).
    pub link: String,
    /// The approach direction in the tool link's frame when it is not +z.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub approach: Option<[f64; 3]>,
    /// The gripper's contact links; absent: the naming convention of
    /// [`RobotImportOptions::contact_links`](super::RobotImportOptions::contact_links).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_links: Option<Vec<String>>,
}

/// The `[arm]` table.
#[derive(Debug, Clone, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ArmDescription {
    /// The link the arm starts at; absent: the base link.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub root: Option<String>,
}

/// The `[base]` table.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BaseDescription {
    /// How the base moves: `"holonomic"` or `"differential_drive"` (see
    /// [`BaseDescription::base_kind`]; a differential drive's y limits must be 0). Default
    /// `"holonomic"`.
    #[serde(default = "default_kind")]
    pub kind: String,
    /// Velocity limits: x (m/s), y (m/s), yaw (rad/s). Default [`DEFAULT_BASE_VELOCITY`].
    #[serde(default = "default_velocity")]
    pub max_velocity: [f64; 3],
    /// Acceleration limits: x (m/s²), y (m/s²), yaw (rad/s²). Default
    /// [`DEFAULT_BASE_ACCELERATION`].
    #[serde(default = "default_acceleration")]
    pub max_acceleration: [f64; 3],
    /// The footprint radius (m); absent: computed from the collision geometry at the stow
    /// ([`MobileBase::footprint_radius`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub footprint_radius: Option<f64>,
    /// The footprint as a polygon: vertices `[x, y]` (m) in the base frame, in order (either
    /// sense), at least 3, simple; the radius is then its farthest vertex's distance from the
    /// origin (see [`RobotDescription`]'s Footprint). Exclusive with
    /// [`BaseDescription::footprint_radius`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub footprint: Option<Vec<[f64; 2]>>,
}

fn default_kind() -> String {
    "holonomic".to_owned()
}

fn default_velocity() -> [f64; 3] {
    DEFAULT_BASE_VELOCITY
}

fn default_acceleration() -> [f64; 3] {
    DEFAULT_BASE_ACCELERATION
}

impl Default for BaseDescription {
    fn default() -> Self {
        BaseDescription {
            kind: default_kind(),
            max_velocity: DEFAULT_BASE_VELOCITY,
            max_acceleration: DEFAULT_BASE_ACCELERATION,
            footprint_radius: None,
            footprint: None,
        }
    }
}

impl BaseDescription {
    /// The [`BaseKind`] that [`BaseDescription::kind`] names: `"holonomic"` or
    /// `"differential_drive"`.
    ///
    /// # Errors
    /// [`RobotError::Description`] naming `base.kind` for any other name.
    pub fn base_kind(&self) -> Result<BaseKind, RobotError> {
        match self.kind.as_str() {
            "holonomic" => Ok(BaseKind::Holonomic),
            "differential_drive" => Ok(BaseKind::DifferentialDrive),
            other => Err(RobotError::Description {
                field: "base.kind".to_owned(),
                message: format!(
                    "unknown base kind {other:?} (known: \"holonomic\", \"differential_drive\")"
                ),
            }),
        }
    }
}

impl RobotDescription {
    /// Parses a description from TOML text (paths are not resolved).
    ///
    /// # Errors
    /// [`RobotError::Description`] naming the key and line at fault: TOML syntax, an unknown
    /// key, a missing `urdf` or `[tool] link`, a value of the wrong type.
    pub fn parse(text: &str) -> Result<RobotDescription, RobotError> {
        toml::from_str(text).map_err(|e| RobotError::Description {
            field: syntax_location(text, e.span()),
            message: e.message().trim_end().to_owned(),
        })
    }

    /// Reads and parses a description file.
    ///
    /// # Errors
    /// [`RobotError::Io`] if the file cannot be read, otherwise as [`RobotDescription::parse`].
    pub fn from_file(path: &Path) -> Result<RobotDescription, RobotError> {
        let text = std::fs::read_to_string(path).map_err(|e| RobotError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        RobotDescription::parse(&text)
    }

    /// The description as TOML text (parses back to an equal value).
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }
}

/// Where a TOML error is: the text at its span (a key or value), the enclosing `[table]`, and
/// the line (`document` without a span).
fn syntax_location(text: &str, span: Option<std::ops::Range<usize>>) -> String {
    let Some(span) = span.filter(|s| s.start <= text.len()) else {
        return "document".to_owned();
    };
    let before = &text[..span.start];
    let line = before.matches('\n').count() + 1;
    let table = before
        .lines()
        .rev()
        .map(str::trim)
        .find(|l| l.starts_with('['))
        .and_then(|l| l.split('#').next())
        .map(str::trim);
    let at = text
        .get(span.clone())
        .filter(|s| !s.is_empty() && s.len() <= 60 && !s.contains('\n'))
        .map(|s| format!("`{s}` "))
        .unwrap_or_default();
    match table {
        Some(table) => format!("{at}in {table} (line {line})"),
        None => format!("{at}(line {line})"),
    }
}
