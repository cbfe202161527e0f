//! URDF import: the link tree becomes the base map, the parts and their joints.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use nalgebra::{Isometry3, Point3, Vector3};
use urdf_rs::{JointType, Link, Robot};

use super::mesh::MeshCache;
use super::numbers::{canonical_axis, isometry_from_origin};
use super::{HANDLE_SUFFIX, ImportOptions, scan, tree};
use crate::scene::validate::check_finite;
use crate::scene::{
    Error, Handle, Joint, JointKind, Limits, PartSpec, SceneModel, SceneModelBuilder,
};

/// Deepest element nesting accepted. A scene URDF needs 5 levels (robot, link, collision,
/// geometry, mesh); deeper documents are rejected before urdf-rs, whose recursive parser
/// could overflow the stack on them.
const MAX_XML_DEPTH: usize = 64;

/// Reads a scene URDF file (see the [module docs](super) for the conventions). Relative mesh
/// paths resolve against `options.base_dir`, or the file's directory if that is `None`.
///
/// # Errors
/// [`Error::Io`] if the file cannot be read (or is not UTF-8); otherwise as [`read_str`].
pub fn read_file(path: impl AsRef<Path>, options: &ImportOptions) -> Result<SceneModel, Error> {
    let path = path.as_ref();
    let xml = std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    if options.base_dir.is_some() {
        return read_str(&xml, options);
    }
    let options = ImportOptions {
        base_dir: Some(path.parent().unwrap_or(Path::new("")).to_path_buf()),
        ..options.clone()
    };
    read_str(&xml, &options)
}

impl SceneModel {
    /// Reads a scene URDF file with the default [`ImportOptions`]: [`read_file`], relative mesh
    /// paths resolved against the file's directory. For `package://` URIs, use [`read_file`]
    /// with [`ImportOptions::package_paths`].
    ///
    /// # Errors
    /// As [`read_file`].
    pub fn from_urdf_file(path: impl AsRef<Path>) -> Result<SceneModel, Error> {
        read_file(path, &ImportOptions::default())
    }
}

/// Reads a scene URDF document (see the [module docs](super) for the conventions). Relative
/// mesh paths resolve against `options.base_dir` (the current directory if `None`).
///
/// # Errors
/// The first problem found, naming the element: [`Error::UrdfParse`] for malformed XML or a
/// document urdf-rs rejects; the tree errors of the module docs ([`Error::DuplicateLink`],
/// [`Error::DuplicateName`], [`Error::UnsupportedJointType`], [`Error::MissingLink`],
/// [`Error::SeveralParents`], [`Error::NoRoot`], [`Error::SeveralRoots`], [`Error::Cycle`]);
/// [`Error::MissingLimits`]; [`Error::HandleOnBase`]; [`Error::NonFinite`] /
/// [`Error::OutOfRange`] for an origin, and shape errors ([`Error::NonPositive`],
/// [`Error::DegenerateMesh`], ...) naming the link and collision element; the mesh errors
/// ([`Error::MeshNotFound`], [`Error::MeshUnreadable`], [`Error::UnsupportedMeshFormat`],
/// [`Error::UnsupportedMeshUri`], [`Error::UnknownPackage`]); then any error of
/// [`SceneModelBuilder::build`] (for example [`Error::ZeroAxis`] or [`Error::InvalidLimits`]
/// naming the URDF joint).
pub fn read_str(xml: &str, options: &ImportOptions) -> Result<SceneModel, Error> {
    let scan = scan::scan(xml);
    if scan.max_depth > MAX_XML_DEPTH {
        return Err(Error::UrdfParse {
            message: format!(
                "elements nested {} levels deep (at most {MAX_XML_DEPTH} accepted)",
                scan.max_depth
            ),
        });
    }
    let robot = catch_unwind(AssertUnwindSafe(|| urdf_rs::read_from_string(xml)))
        .map_err(|_| Error::UrdfParse {
            message: "the URDF parser panicked".into(),
        })?
        .map_err(|e| Error::UrdfParse {
            message: e.to_string(),
        })?;
    let tree = tree::resolve(&robot)?;
    let mut importer = Importer {
        robot: &robot,
        tree: &tree,
        options,
        has_limit: scan.joint_has_limit,
        meshes: MeshCache::new(options),
        builder: SceneModelBuilder::new(),
    };
    importer.walk()?;
    let mut builder = importer.builder;
    builder.base.name = Some(robot.links[tree.root].name.clone());
    builder.base.nav = options.nav;
    builder.build()
}

/// What a link's geometry and handles attach to.
#[derive(Debug, Clone, Copy)]
pub(super) enum Owner {
    /// The static base map (world frame).
    Base,
    /// The part at this index of `builder.parts`.
    Part(usize),
}

/// A link to visit, with its place in the scene.
pub(super) struct Visit {
    pub link: usize,
    pub owner: Owner,
    /// `owner_from_link`; `None` is the identity (kept exact: no composition).
    pub owner_from_link: Option<Isometry3<f64>>,
    /// Whether the link hangs on a fixed joint (a handle if its name ends in the suffix).
    pub fixed: bool,
    /// For the child of a movable joint: its part, created when the visit is popped (so
    /// parts are created in depth-first pre-order, siblings in document order).
    pub part: Option<PartSpec>,
}

/// The state of one import.
pub(super) struct Importer<'a> {
    pub robot: &'a Robot,
    pub tree: &'a tree::LinkTree,
    pub options: &'a ImportOptions,
    pub has_limit: Vec<bool>,
    pub meshes: MeshCache<'a>,
    pub builder: SceneModelBuilder,
}

impl Importer<'_> {
    /// Visits the links depth first from the root, children in document order, so parts are
    /// created in the pre-order the scene builder numbers them in.
    fn walk(&mut self) -> Result<(), Error> {
        let mut stack = vec![Visit {
            link: self.tree.root,
            owner: Owner::Base,
            owner_from_link: None,
            fixed: false,
            part: None,
        }];
        while let Some(mut visit) = stack.pop() {
            if let Some(spec) = visit.part.take() {
                self.builder.parts.push(spec);
                visit.owner = Owner::Part(self.builder.parts.len() - 1);
            }
            let link = &self.robot.links[visit.link];
            if visit.fixed && link.name.ends_with(HANDLE_SUFFIX) {
                self.add_handle(link, &visit)?;
            }
            self.add_collisions(link, &visit)?;
            for &j in self.tree.children[visit.link].iter().rev() {
                stack.push(self.child_visit(j, &visit)?);
            }
        }
        Ok(())
    }

    /// The visit of joint `j`'s child, with the child's part for a movable joint.
    fn child_visit(&self, j: usize, parent: &Visit) -> Result<Visit, Error> {
        let joint = &self.robot.joints[j];
        let origin = &joint.origin;
        check_finite(origin.xyz.iter().chain(origin.rpy.iter()).copied(), || {
            format!("URDF joint {:?} origin", joint.name)
        })?;
        let owner_from_joint = compose(
            parent.owner_from_link.as_ref(),
            isometry_from_origin(&origin.xyz, &origin.rpy),
        );
        let child = self.tree.child[j];
        let kind = match joint.joint_type {
            JointType::Fixed => {
                return Ok(Visit {
                    link: child,
                    owner: parent.owner,
                    owner_from_link: Some(owner_from_joint),
                    fixed: true,
                    part: None,
                });
            }
            JointType::Prismatic => JointKind::Prismatic,
            // Planar, floating and spherical were rejected by the tree check.
            _ => JointKind::Revolute,
        };
        let continuous = joint.joint_type == JointType::Continuous;
        let limits = if continuous {
            self.options.continuous_limits
        } else {
            let present = self.has_limit.get(j).copied().unwrap_or(true);
            let (lower, upper) = (joint.limit.lower, joint.limit.upper);
            if !present || lower.is_infinite() || upper.is_infinite() {
                return Err(Error::MissingLimits {
                    joint: joint.name.clone(),
                    kind: format!("{:?}", joint.joint_type).to_lowercase(),
                });
            }
            Limits::new(lower, upper)
        };
        let axis = canonical_axis(&Vector3::from(*joint.axis.xyz));
        let parent_part = match parent.owner {
            Owner::Base => None,
            Owner::Part(k) => Some(self.builder.parts[k].name.clone()),
        };
        let mut spec = PartSpec {
            name: self.robot.links[child].name.clone(),
            parent: parent_part,
            joint: Joint::new(joint.name.clone(), kind, owner_from_joint, axis, limits),
            colliders: Vec::new(),
            handles: Vec::new(),
        };
        spec.joint.continuous = continuous;
        Ok(Visit {
            link: child,
            // Replaced by the part when the visit is popped.
            owner: parent.owner,
            owner_from_link: None,
            fixed: false,
            part: Some(spec),
        })
    }

    /// Records a `*_handle` link as a handle of the part it is fixed to.
    fn add_handle(&mut self, link: &Link, visit: &Visit) -> Result<(), Error> {
        let Owner::Part(k) = visit.owner else {
            return Err(Error::HandleOnBase {
                handle: link.name.clone(),
            });
        };
        let part_from_handle = visit.owner_from_link.unwrap_or_else(Isometry3::identity);
        self.builder.parts[k].handles.push(Handle::new(
            link.name.clone(),
            Point3::from(part_from_handle.translation.vector),
            part_from_handle.rotation * Vector3::x(),
        ));
        Ok(())
    }
}

/// `a · b`, with `None` as the identity (returns `b` exactly).
pub(super) fn compose(a: Option<&Isometry3<f64>>, b: Isometry3<f64>) -> Isometry3<f64> {
    match a {
        Some(a) => a * b,
        None => b,
    }
}
