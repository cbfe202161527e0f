//! Convex meshes without a source file, written on export as OBJ files of their convex hull.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use nalgebra::Point3;

use super::ExportOptions;
use super::numbers::number;
use crate::scene::collision::convert;
use crate::scene::{Error, SceneModel, Shape};

/// Where a sourceless mesh sits in the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Slot {
    /// Base shape by index.
    Base(usize),
    /// Part index, collider index.
    Part(usize, usize),
}

/// Writes every convex mesh of `model` that has no source file into the mesh directory and
/// returns the URI to reference each by.
///
/// All hulls are computed before anything is written, so a failing export writes no file.
///
/// # Errors
/// [`Error::MeshWithoutSource`] if there is such a mesh but no mesh directory;
/// [`Error::DegenerateMesh`] if a hull cannot be built; [`Error::Io`] if the directory or a
/// file cannot be written or the path is not UTF-8.
pub(super) fn write_sourceless_meshes(
    model: &SceneModel,
    base_link: &str,
    options: &ExportOptions,
    urdf_dir: Option<&Path>,
) -> Result<BTreeMap<Slot, String>, Error> {
    let mut jobs = Vec::new();
    for (k, s) in model.base().shapes.iter().enumerate() {
        if let Shape::ConvexMesh {
            vertices,
            source: None,
        } = &s.shape
        {
            let what = format!("base shape {:?}", s.name);
            jobs.push((
                Slot::Base(k),
                what,
                format!("{base_link}_{}", s.name),
                vertices,
            ));
        }
    }
    for (p, part) in model.parts().iter().enumerate() {
        for (k, c) in part.colliders().iter().enumerate() {
            if let Shape::ConvexMesh {
                vertices,
                source: None,
            } = &c.shape
            {
                let what = format!("part {:?} collider {k}", part.name());
                jobs.push((
                    Slot::Part(p, k),
                    what,
                    format!("{}_{k}", part.name()),
                    vertices,
                ));
            }
        }
    }
    let Some(first) = jobs.first() else {
        return Ok(BTreeMap::new());
    };
    let Some(mesh_dir) = &options.mesh_dir else {
        return Err(Error::MeshWithoutSource {
            what: first.1.clone(),
        });
    };
    let write_dir = match urdf_dir {
        Some(dir) if mesh_dir.is_relative() => dir.join(mesh_dir),
        _ => mesh_dir.clone(),
    };
    let texts = jobs
        .iter()
        .map(|(_, what, _, vertices)| hull_obj(vertices, what))
        .collect::<Result<Vec<_>, _>>()?;
    std::fs::create_dir_all(&write_dir).map_err(|e| io_error(&write_dir, &e))?;
    let mut used = BTreeSet::new();
    let mut uris = BTreeMap::new();
    for ((slot, _, stem, _), text) in jobs.iter().zip(texts) {
        let stem = sanitized(stem);
        let mut file = format!("{stem}.obj");
        let mut n = 2;
        while !used.insert(file.clone()) {
            file = format!("{stem}_{n}.obj");
            n += 1;
        }
        let path = write_dir.join(&file);
        std::fs::write(&path, text).map_err(|e| io_error(&path, &e))?;
        let uri = mesh_dir.join(&file);
        let uri = uri.to_str().ok_or_else(|| Error::Io {
            path: uri.clone(),
            message: "the mesh path is not valid UTF-8".into(),
        })?;
        uris.insert(*slot, uri.to_string());
    }
    Ok(uris)
}

/// The OBJ text of the convex hull of `vertices` (outward, counter-clockwise faces).
fn hull_obj(vertices: &[Point3<f64>], what: &str) -> Result<String, Error> {
    let points: Vec<_> = vertices.iter().map(convert::point).collect();
    let (hull, faces) = catch_unwind(AssertUnwindSafe(|| {
        parry3d_f64::transformation::try_convex_hull(&points)
    }))
    .ok()
    .and_then(Result::ok)
    .ok_or_else(|| Error::DegenerateMesh {
        what: what.to_string(),
        reason: "convex hull construction failed".into(),
    })?;
    let mut out = String::from("# Convex hull written by kinscene's URDF export\n");
    for p in hull.iter().map(convert::from_vector) {
        // parry's hull vertices are copies of input points.
        let _ = writeln!(out, "v {} {} {}", number(p.x), number(p.y), number(p.z));
    }
    for f in &faces {
        let _ = writeln!(out, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    Ok(out)
}

/// A file stem from a name: ASCII letters, digits, `-` and `_` kept, anything else `_`, at
/// most 80 characters.
fn sanitized(name: &str) -> String {
    name.chars()
        .take(80)
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

fn io_error(path: &Path, e: &std::io::Error) -> Error {
    Error::Io {
        path: PathBuf::from(path),
        message: e.to_string(),
    }
}
