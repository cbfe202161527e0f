//! `kinscene inspect --scene S.urdf [--package NAME=PATH ...]`: loads a scene URDF
//! ([`kinscene::scene::urdf::read_file`]) and prints it as pretty JSON on standard output.
//!
//! Relative mesh paths resolve against the URDF's directory; `--package NAME=PATH` (repeatable)
//! resolves `package://NAME/rest` to `PATH/rest`. World-frame values are at the scene's zero
//! state (every joint at 0 clamped into its limits), which the document lists.
//!
//! # JSON schema
//!
//! ```text
#![doc = include_str!("inspect_schema.txt")]
//! ```

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use kinscene::scene::{
    Error, JointKind, Parent, SceneData, SceneModel, Shape, forward_kinematics, joint_axis,
    world_from_handle,
};
use nalgebra::{Isometry3, Point3, Vector3};
use serde::Serialize;

use kinscene::task::{CollidingPair, TaskSettings, colliding_pairs};

use crate::input::SceneArgs;
use crate::{CliError, Verdict};

/// Identifies the document format; changes when a field changes meaning or disappears.
const FORMAT: &str = "kinscene-inspect/1";

/// Arguments of `kinscene inspect`.
#[derive(Debug, clap::Args)]
#[command(
    about = "Print a scene URDF's joints, handles, base shapes and navigation grid as JSON",
    long_about = "Loads a scene URDF (root link = static base; revolute, continuous and \
                  prismatic joints = parts; fixed links ending in `_handle` = handles) and \
                  prints it as pretty JSON on stdout. World values are at the zero state.",
    after_long_help = concat!("JSON schema:\n\n", include_str!("inspect_schema.txt"))
)]
pub struct Args {
    /// The scene and its mesh packages.
    #[command(flatten)]
    input: SceneArgs,
}

/// Runs `inspect`: loads the scene and writes the JSON document to `out`.
///
/// # Errors
/// A [`CliError`] naming the file for an unreadable or malformed URDF or an invalid scene,
/// or a package name given twice.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<Verdict, CliError> {
    let model = args.input.load()?;
    let report = Report::new(&model, &args.input.scene)?;
    if !report.zero_state_collisions.is_empty() {
        eprintln!(
            "kinscene: warning: {} colliding pair(s) at the zero state (a planner refuses this \
             start state): {}",
            report.zero_state_collisions.len(),
            report
                .zero_state_collisions
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join("; ")
        );
    }
    serde_json::to_writer_pretty(&mut *out, &report)
        .map_err(|e| CliError::new(format!("cannot write JSON: {e}")))?;
    writeln!(out).map_err(|e| CliError::new(format!("cannot write JSON: {e}")))?;
    Ok(Verdict::Success)
}

/// The document `inspect` prints (see the module docs for the schema).
#[derive(Debug, Serialize)]
struct Report {
    format: &'static str,
    file: String,
    name: Option<String>,
    zero_state: BTreeMap<String, f64>,
    zero_state_collisions: Vec<CollidingPair>,
    joints: Vec<JointReport>,
    handles: Vec<HandleReport>,
    base_shapes: Vec<BaseShapeReport>,
    nav_grid: NavGridReport,
}

#[derive(Debug, Serialize)]
struct JointReport {
    name: String,
    #[serde(rename = "type")]
    kind: &'static str,
    parent: Option<String>,
    parent_kind: &'static str,
    child: String,
    axis: AxisReport,
    origin: OriginReport,
    pivot: [f64; 3],
    limits: LimitsReport,
}

#[derive(Debug, Serialize)]
struct AxisReport {
    joint: [f64; 3],
    world: [f64; 3],
}

#[derive(Debug, Serialize)]
struct OriginReport {
    xyz: [f64; 3],
    rpy: [f64; 3],
    quaternion: [f64; 4],
    parent_from_joint: [[f64; 4]; 4],
}

#[derive(Debug, Serialize)]
struct LimitsReport {
    lower: f64,
    upper: f64,
    unit: &'static str,
}

#[derive(Debug, Serialize)]
struct HandleReport {
    name: String,
    part: String,
    joint: String,
    part_frame: PointNormal,
    world: PointNormal,
}

#[derive(Debug, Serialize)]
struct PointNormal {
    position: [f64; 3],
    normal: [f64; 3],
}

#[derive(Debug, Serialize)]
struct BaseShapeReport {
    name: String,
    kind: &'static str,
    position: [f64; 3],
    #[serde(skip_serializing_if = "Option::is_none")]
    mesh: Option<String>,
}

#[derive(Debug, Serialize)]
struct NavGridReport {
    resolution: f64,
    width: usize,
    height: usize,
    origin: [f64; 2],
    occupied_cells: usize,
}

/// `x` with a negative zero made positive (`-0.0 + 0.0 = 0.0`), for tidier output.
fn tidy(x: f64) -> f64 {
    x + 0.0
}

fn vector(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z].map(tidy)
}

fn point(p: &Point3<f64>) -> [f64; 3] {
    vector(&p.coords)
}

fn origin(iso: &Isometry3<f64>) -> OriginReport {
    let (roll, pitch, yaw) = iso.rotation.euler_angles();
    let q = iso.rotation.quaternion();
    let m = iso.to_homogeneous();
    OriginReport {
        xyz: vector(&iso.translation.vector),
        rpy: [roll, pitch, yaw].map(tidy),
        quaternion: [q.i, q.j, q.k, q.w].map(tidy),
        parent_from_joint: std::array::from_fn(|r| std::array::from_fn(|c| tidy(m[(r, c)]))),
    }
}

fn shape_kind(shape: &Shape) -> (&'static str, Option<String>) {
    match shape {
        Shape::Cuboid { .. } => ("box", None),
        Shape::Cylinder { .. } => ("cylinder", None),
        Shape::Sphere { .. } => ("sphere", None),
        Shape::Capsule { .. } => ("capsule", None),
        Shape::ConvexMesh { source, .. } => ("mesh", source.as_ref().map(|s| s.uri.clone())),
        _ => ("other", None),
    }
}

/// Maps a scene error of a query on a valid model (not expected) to a CLI error.
fn internal(e: Error) -> CliError {
    CliError::new(format!("cannot evaluate the scene: {e}"))
}

impl Report {
    fn new(model: &SceneModel, file: &Path) -> Result<Report, CliError> {
        let state = model.zero_state();
        let mut data = SceneData::new(model);
        forward_kinematics(model, &mut data, &state).map_err(internal)?;
        let base_name = model.base().name.clone();
        let parts = model.parts();

        let mut joints = Vec::with_capacity(parts.len());
        for part in parts {
            let id = part.joint();
            let joint = &model.joints()[id.index()];
            let axis = joint_axis(model, &data, id).map_err(internal)?;
            let (parent, parent_kind) = match part.parent() {
                Parent::Base => (base_name.clone(), "base"),
                Parent::Part(p) => (Some(parts[p.index()].name().to_string()), "part"),
            };
            let (kind, unit) = match (joint.kind, joint.continuous) {
                (JointKind::Revolute, false) => ("revolute", "rad"),
                (JointKind::Revolute, true) => ("continuous", "rad"),
                (JointKind::Prismatic, _) => ("prismatic", "m"),
            };
            joints.push(JointReport {
                name: joint.name.clone(),
                kind,
                parent,
                parent_kind,
                child: part.name().to_string(),
                axis: AxisReport {
                    joint: vector(&joint.axis),
                    world: vector(&axis.direction),
                },
                origin: origin(&joint.parent_from_joint),
                pivot: point(&axis.pivot),
                limits: LimitsReport {
                    lower: joint.limits.lower,
                    upper: joint.limits.upper,
                    unit,
                },
            });
        }

        let mut handles = Vec::new();
        for (id, handle) in model.handles() {
            let part = &parts[id.part().index()];
            let world = world_from_handle(model, &data, id).map_err(internal)?;
            handles.push(HandleReport {
                name: handle.name.clone(),
                part: part.name().to_string(),
                joint: model.joints()[part.joint().index()].name.clone(),
                part_frame: PointNormal {
                    position: point(&handle.position),
                    normal: vector(&handle.normal),
                },
                world: PointNormal {
                    position: point(&world.position),
                    normal: vector(&world.normal),
                },
            });
        }

        let base_shapes = model
            .base()
            .shapes
            .iter()
            .map(|s| {
                let (kind, mesh) = shape_kind(&s.shape);
                BaseShapeReport {
                    name: s.name.clone(),
                    kind,
                    position: vector(&s.world_from_shape.translation.vector),
                    mesh,
                }
            })
            .collect();

        let grid = model.base_grid();
        let zero_state = state.to_map(model).map_err(internal)?;
        // The predicate the planner's start check uses (its default sweep settings).
        let collision = TaskSettings::default().sweep.collision;
        let zero_state_collisions = colliding_pairs(model, &state, &collision)
            .map_err(|e| CliError::new(format!("cannot evaluate the scene: {e}")))?;
        Ok(Report {
            format: FORMAT,
            file: file.display().to_string(),
            name: base_name,
            zero_state,
            zero_state_collisions,
            joints,
            handles,
            base_shapes,
            nav_grid: NavGridReport {
                resolution: grid.resolution(),
                width: grid.width(),
                height: grid.height(),
                origin: [grid.origin().x, grid.origin().y],
                occupied_cells: grid.occupied_count(),
            },
        })
    }
}
