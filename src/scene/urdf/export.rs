//! URDF export: the base map, the parts, their joints and handles as links and joints.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;

use super::numbers::{canonical_axis, normal_rpy_text, number, vector};
use super::obj::{Slot, write_sourceless_meshes};
use super::options::{DEFAULT_BASE_NAME, DEFAULT_ROBOT_NAME};
use super::xml::{base_groups, element, escape, origin, same_mesh_element};
use super::{ExportOptions, HANDLE_SUFFIX};
use crate::scene::{Error, JointKind, Parent, SceneModel};

/// Writes `model` as a scene URDF document (see the [module docs](super) for the layout).
/// Convex meshes without a source file are written into `options.mesh_dir` (relative to the
/// current directory) as OBJ files.
///
/// # Errors
/// [`Error::UnwritableName`] if two links would get the same name or a name holds a character
/// XML cannot; [`Error::MeshWithoutSource`] for a sourceless mesh without a mesh directory;
/// [`Error::Io`] if an OBJ file cannot be written.
pub fn write_string(model: &SceneModel, options: &ExportOptions) -> Result<String, Error> {
    export(model, options, None)
}

/// Writes `model` as a scene URDF file; a relative `options.mesh_dir` is relative to the
/// file's directory. See [`write_string`].
///
/// # Errors
/// As [`write_string`], and [`Error::Io`] if the file cannot be written.
pub fn write_file(
    model: &SceneModel,
    path: impl AsRef<Path>,
    options: &ExportOptions,
) -> Result<(), Error> {
    let path = path.as_ref();
    let xml = export(model, options, Some(path.parent().unwrap_or(Path::new(""))))?;
    std::fs::write(path, xml).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Link and joint names of the document.
struct Names {
    base_link: String,
    /// Per part, per handle: (handle link, fixed joint).
    handles: Vec<Vec<(String, String)>>,
}

fn export(
    model: &SceneModel,
    options: &ExportOptions,
    urdf_dir: Option<&Path>,
) -> Result<String, Error> {
    let names = plan_names(model)?;
    let robot = options.robot_name.as_deref().unwrap_or(DEFAULT_ROBOT_NAME);
    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    x.push_str("<!-- Scene model written by kinscene: the root link is the static base map, each movable joint's child link is an articulated part, each *_handle link is a handle (origin = grasp point, +x = outward normal). -->\n");
    let _ = writeln!(x, "<robot name=\"{}\">", escape(robot)?);
    let meshes = write_sourceless_meshes(model, &names.base_link, options, urdf_dir)?;

    let _ = writeln!(x, "  <link name=\"{}\">", escape(&names.base_link)?);
    for (k, name) in base_groups(&model.base().shapes) {
        let s = &model.base().shapes[k];
        let uri = meshes.get(&Slot::Base(k)).map(String::as_str);
        element(&mut x, Some(&name), &s.shape, &s.world_from_shape, uri)?;
    }
    x.push_str("  </link>\n");

    for (p, part) in model.parts().iter().enumerate() {
        let link = escape(part.name())?;
        let _ = writeln!(x, "  <link name=\"{link}\">");
        let colliders = part.colliders();
        for (k, c) in colliders.iter().enumerate() {
            if k > 0 && same_mesh_element(&colliders[k - 1], c) {
                continue;
            }
            let uri = meshes.get(&Slot::Part(p, k)).map(String::as_str);
            element(&mut x, None, &c.shape, &c.part_from_shape, uri)?;
        }
        x.push_str("  </link>\n");

        let joint = &model.joints()[p];
        let parent = match part.parent() {
            Parent::Base => names.base_link.as_str(),
            Parent::Part(id) => model.parts()[id.index()].name(),
        };
        let kind = match (joint.kind, joint.continuous) {
            (JointKind::Revolute, true) => "continuous",
            (JointKind::Revolute, false) => "revolute",
            (JointKind::Prismatic, _) => "prismatic",
        };
        let _ = writeln!(
            x,
            "  <joint name=\"{}\" type=\"{kind}\">",
            escape(&joint.name)?
        );
        origin(&mut x, "    ", &joint.parent_from_joint);
        let _ = writeln!(x, "    <parent link=\"{}\"/>", escape(parent)?);
        let _ = writeln!(x, "    <child link=\"{link}\"/>");
        let _ = writeln!(
            x,
            "    <axis xyz=\"{}\"/>",
            vector(&canonical_axis(&joint.axis))
        );
        if !joint.continuous {
            // urdfdom requires effort and velocity; the scene model has no dynamics.
            let _ = writeln!(
                x,
                "    <limit lower=\"{}\" upper=\"{}\" effort=\"0\" velocity=\"0\"/>",
                number(joint.limits.lower),
                number(joint.limits.upper)
            );
        }
        x.push_str("  </joint>\n");

        for (h, (handle_link, handle_joint)) in part.handles().iter().zip(&names.handles[p]) {
            let handle_link = escape(handle_link)?;
            let _ = writeln!(x, "  <link name=\"{handle_link}\"/>");
            let _ = writeln!(
                x,
                "  <joint name=\"{}\" type=\"fixed\">",
                escape(handle_joint)?
            );
            let _ = writeln!(
                x,
                "    <origin xyz=\"{}\" rpy=\"{}\"/>",
                vector(&h.position.coords),
                normal_rpy_text(&h.normal)
            );
            let _ = writeln!(x, "    <parent link=\"{link}\"/>");
            let _ = writeln!(x, "    <child link=\"{handle_link}\"/>");
            x.push_str("  </joint>\n");
        }
    }
    x.push_str("</robot>\n");
    Ok(x)
}

/// Chooses link names (base, parts, handle links: one namespace) and the handle joints'
/// names (unique among all joints).
fn plan_names(model: &SceneModel) -> Result<Names, Error> {
    let base_link = model
        .base()
        .name
        .clone()
        .unwrap_or_else(|| DEFAULT_BASE_NAME.to_string());
    let mut links = BTreeSet::new();
    let mut claim = |name: &str| {
        if links.insert(name.to_string()) {
            Ok(())
        } else {
            Err(Error::UnwritableName {
                name: name.to_string(),
                reason: "two URDF links would share it (the base, the parts and the handle \
                         links share one namespace)"
                    .into(),
            })
        }
    };
    claim(&base_link)?;
    for part in model.parts() {
        claim(part.name())?;
    }
    let mut joints: BTreeSet<String> = model.joints().iter().map(|j| j.name.clone()).collect();
    let mut handles = Vec::with_capacity(model.parts().len());
    for part in model.parts() {
        let mut of_part = Vec::with_capacity(part.handles().len());
        for h in part.handles() {
            let link = if h.name.ends_with(HANDLE_SUFFIX) {
                h.name.clone()
            } else {
                format!("{}{HANDLE_SUFFIX}", h.name)
            };
            claim(&link)?;
            let stem = format!("{link}_joint");
            let mut joint = stem.clone();
            let mut n = 2;
            while !joints.insert(joint.clone()) {
                joint = format!("{stem}_{n}");
                n += 1;
            }
            of_part.push((link, joint));
        }
        handles.push(of_part);
    }
    Ok(Names { base_link, handles })
}
