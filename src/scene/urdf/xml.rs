//! XML elements of the export: geometry, origins, escaping, and the grouping of sub-meshes.

use std::fmt::Write as _;

use nalgebra::{Isometry3, Vector3};

use super::numbers::{number, rpy_text, vector};
use crate::scene::{BaseShape, Collider, Error, MeshSource, Shape};

/// Base shapes to write: (first index, collision name). A run of convex
/// meshes from one file at one pose named `stem/0`, `stem/1`, ... (the sub-meshes of one
/// imported `<mesh>`) is written as one element named `stem`.
pub(super) fn base_groups(shapes: &[BaseShape]) -> Vec<(usize, String)> {
    let mut groups = Vec::new();
    let mut i = 0;
    while i < shapes.len() {
        let run = shapes[i]
            .name
            .strip_suffix("/0")
            .filter(|_| {
                matches!(
                    shapes[i].shape,
                    Shape::ConvexMesh {
                        source: Some(_),
                        ..
                    }
                )
            })
            .map(|stem| {
                let len = shapes[i..]
                    .iter()
                    .enumerate()
                    .take_while(|(j, s)| {
                        s.name == format!("{stem}/{j}")
                            && s.world_from_shape == shapes[i].world_from_shape
                            && mesh_source(&s.shape).is_some()
                            && mesh_source(&s.shape) == mesh_source(&shapes[i].shape)
                    })
                    .count();
                (stem.to_string(), len)
            })
            .filter(|(_, len)| *len >= 2);
        let (name, len) = run.unwrap_or_else(|| (shapes[i].name.clone(), 1));
        groups.push((i, name));
        i += len;
    }
    groups
}

/// Whether `b` is a further sub-mesh of the `<mesh>` element written for `a`: both convex
/// meshes from the same file and scale, at the same pose.
pub(super) fn same_mesh_element(a: &Collider, b: &Collider) -> bool {
    mesh_source(&a.shape).is_some()
        && mesh_source(&a.shape) == mesh_source(&b.shape)
        && a.part_from_shape == b.part_from_shape
}

fn mesh_source(shape: &Shape) -> Option<&MeshSource> {
    match shape {
        Shape::ConvexMesh { source, .. } => source.as_ref(),
        _ => None,
    }
}

/// A `<visual>` and an identical `<collision>` element.
pub(super) fn element(
    x: &mut String,
    name: Option<&str>,
    shape: &Shape,
    pose: &Isometry3<f64>,
    sourceless_uri: Option<&str>,
) -> Result<(), Error> {
    let name = match name {
        Some(n) => format!(" name=\"{}\"", escape(n)?),
        None => String::new(),
    };
    let geometry = geometry(shape, sourceless_uri)?;
    for tag in ["visual", "collision"] {
        let _ = writeln!(x, "    <{tag}{name}>");
        origin(x, "      ", pose);
        let _ = writeln!(x, "      <geometry>\n        {geometry}\n      </geometry>");
        let _ = writeln!(x, "    </{tag}>");
    }
    Ok(())
}

fn geometry(shape: &Shape, sourceless_uri: Option<&str>) -> Result<String, Error> {
    Ok(match shape {
        Shape::Cuboid { half_extents } => {
            format!("<box size=\"{}\"/>", vector(&(half_extents * 2.0)))
        }
        Shape::Cylinder { radius, length } => format!(
            "<cylinder radius=\"{}\" length=\"{}\"/>",
            number(*radius),
            number(*length)
        ),
        Shape::Sphere { radius } => format!("<sphere radius=\"{}\"/>", number(*radius)),
        Shape::Capsule { radius, length } => format!(
            "<capsule radius=\"{}\" length=\"{}\"/>",
            number(*radius),
            number(*length)
        ),
        Shape::ConvexMesh { source, .. } => {
            let (uri, scale) = match (source, sourceless_uri) {
                (Some(s), _) => (s.uri.as_str(), s.scale),
                (None, Some(uri)) => (uri, Vector3::repeat(1.0)),
                // write_sourceless_meshes gives every sourceless mesh a URI or fails first.
                (None, None) => {
                    return Err(Error::MeshWithoutSource {
                        what: "a convex mesh".into(),
                    });
                }
            };
            format!(
                "<mesh filename=\"{}\" scale=\"{}\"/>",
                escape(uri)?,
                vector(&scale)
            )
        }
    })
}

/// An `<origin xyz rpy>` line.
pub(super) fn origin(x: &mut String, indent: &str, pose: &Isometry3<f64>) {
    let _ = writeln!(
        x,
        "{indent}<origin xyz=\"{}\" rpy=\"{}\"/>",
        vector(&pose.translation.vector),
        rpy_text(&pose.rotation)
    );
}

/// `text` escaped for an XML attribute value.
///
/// # Errors
/// [`Error::UnwritableName`] for characters XML 1.0 cannot hold (control characters other
/// than tab, newline and carriage return; U+FFFE; U+FFFF).
pub(crate) fn escape(text: &str) -> Result<String, Error> {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => {
                let _ = write!(out, "&#{};", u32::from(c));
            }
            c if u32::from(c) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => {
                return Err(Error::UnwritableName {
                    name: text.to_string(),
                    reason: format!("it contains U+{:04X}, which XML cannot hold", u32::from(c)),
                });
            }
            c => out.push(c),
        }
    }
    Ok(out)
}
