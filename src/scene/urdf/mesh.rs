//! Mesh references on import: resolving `filename` URIs and loading STL, OBJ and COLLADA files
//! with mesh-loader.

use std::collections::HashMap;
use std::io;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use nalgebra::{Point3, Vector3};

use super::ImportOptions;
use crate::scene::Error;

/// File extensions (compared case-insensitively) of the supported mesh formats.
const EXTENSIONS: [&str; 3] = ["stl", "obj", "dae"];

/// The vertices (unscaled, metres as stored in the file) of each non-empty sub-mesh.
pub(crate) type SubMeshes = Vec<Vec<Point3<f64>>>;

/// Loads meshes for one import, each file once.
pub(crate) struct MeshCache<'a> {
    options: &'a ImportOptions,
    loaded: HashMap<PathBuf, SubMeshes>,
}

impl<'a> MeshCache<'a> {
    /// An empty cache resolving URIs with `options`.
    pub fn new(options: &'a ImportOptions) -> Self {
        MeshCache {
            options,
            loaded: HashMap::new(),
        }
    }

    /// The sub-meshes of the mesh `uri` referenced by a collision element of `link`, with
    /// every vertex multiplied component-wise by `scale`.
    ///
    /// # Errors
    /// [`Error::UnknownPackage`], [`Error::UnsupportedMeshUri`], [`Error::MeshNotFound`],
    /// [`Error::UnsupportedMeshFormat`] or [`Error::MeshUnreadable`], naming the link, the URI
    /// and (where resolved) the path.
    pub fn load(
        &mut self,
        link: &str,
        uri: &str,
        scale: &Vector3<f64>,
    ) -> Result<SubMeshes, Error> {
        let path = resolve(link, uri, self.options)?;
        if !self.loaded.contains_key(&path) {
            let meshes = read(link, uri, &path)?;
            self.loaded.insert(path.clone(), meshes);
        }
        let meshes = self.loaded.get(&path).map(Vec::as_slice).unwrap_or(&[]);
        Ok(meshes
            .iter()
            .map(|m| {
                m.iter()
                    .map(|p| Point3::from(p.coords.component_mul(scale)))
                    .collect()
            })
            .collect())
    }
}

/// Where the mesh `uri` is: `package://NAME/rest` in the package map, `file://path` as the
/// path, any other scheme unsupported, a plain path relative to the base directory.
pub(super) fn resolve(link: &str, uri: &str, options: &ImportOptions) -> Result<PathBuf, Error> {
    if let Some(rest) = uri.strip_prefix("package://") {
        let (package, relative) = rest.split_once('/').unwrap_or((rest, ""));
        let root = options
            .package_paths
            .get(package)
            .ok_or_else(|| Error::UnknownPackage {
                link: link.to_string(),
                uri: uri.to_string(),
                package: package.to_string(),
            })?;
        Ok(root.join(relative))
    } else if let Some(path) = uri.strip_prefix("file://") {
        Ok(PathBuf::from(path))
    } else if uri.contains("://") {
        Err(Error::UnsupportedMeshUri {
            link: link.to_string(),
            uri: uri.to_string(),
        })
    } else {
        Ok(match &options.base_dir {
            Some(dir) => dir.join(uri),
            None => PathBuf::from(uri),
        })
    }
}

/// Reads and parses one mesh file.
fn read(link: &str, uri: &str, path: &Path) -> Result<SubMeshes, Error> {
    let unreadable = |message: String| Error::MeshUnreadable {
        link: link.to_string(),
        uri: uri.to_string(),
        path: path.to_path_buf(),
        message,
    };
    let unsupported = || Error::UnsupportedMeshFormat {
        link: link.to_string(),
        uri: uri.to_string(),
        path: path.to_path_buf(),
    };
    match std::fs::metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            return Err(Error::MeshNotFound {
                link: link.to_string(),
                uri: uri.to_string(),
                path: path.to_path_buf(),
            });
        }
        Err(e) => return Err(unreadable(e.to_string())),
        // Devices and pipes could block or never end.
        Ok(m) if !m.is_file() => return Err(unreadable("not a regular file".into())),
        Ok(_) => {}
    }
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !extension.is_some_and(|e| EXTENSIONS.contains(&e.as_str())) {
        return Err(unsupported());
    }
    let bytes = std::fs::read(path).map_err(|e| unreadable(e.to_string()))?;
    let loader = mesh_loader::Loader::default().custom_reader(read_regular_file);
    // mesh-loader is not documented to be panic-free on malformed input; keep a panic from
    // escaping the importer.
    let scene = catch_unwind(AssertUnwindSafe(|| loader.load_from_slice(&bytes, path)))
        .map_err(|_| unreadable("the mesh parser panicked".into()))?
        .map_err(|e| {
            if e.kind() == io::ErrorKind::Unsupported {
                unsupported()
            } else {
                unreadable(e.to_string())
            }
        })?;
    Ok(scene
        .meshes
        .iter()
        .filter(|m| !m.vertices.is_empty())
        .map(|m| {
            m.vertices
                .iter()
                .map(|v| Point3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2])))
                .collect()
        })
        .collect())
}

/// The reader mesh-loader uses for files a mesh references (OBJ material libraries): regular
/// files only.
fn read_regular_file(path: &Path) -> io::Result<Vec<u8>> {
    if std::fs::metadata(path)?.is_file() {
        std::fs::read(path)
    } else {
        Err(io::Error::other("not a regular file"))
    }
}
