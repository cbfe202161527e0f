//! The walk down the URDF tree from the base link: each link merged into the robot link that
//! owns it, non-arm joints fixed or frozen, collision elements turned into colliders.

use nalgebra::{Isometry3, Vector3};
use urdf_rs::{Geometry, JointType};

use super::joint::{arm_joint, origin};
use super::tree::Tree;
use crate::kinematics::robot::{ArmJoint, FrozenJoint, RobotError, RobotLink};
use crate::scene::urdf::mesh::MeshCache;
use crate::scene::{Collider, MeshSource, Shape};

/// The depth-first walk from the base link that assigns every link to its owning robot link.
pub(super) struct Walk<'a> {
    pub(super) robot: &'a urdf_rs::Robot,
    pub(super) tree: &'a Tree,
    /// The arm joints (indices in `robot.joints`), root to tip.
    pub(super) arm: &'a [usize],
    pub(super) joints: Vec<ArmJoint>,
    pub(super) links: Vec<RobotLink>,
    /// Per URDF link: (robot link index, robot link frame from URDF link frame).
    pub(super) owner: Vec<Option<(usize, Isometry3<f64>)>>,
    pub(super) base_from_arm_root: Isometry3<f64>,
    /// [`RobotImportOptions::contact_links`].
    pub(super) contact: Option<&'a [String]>,
    /// Collision meshes, each file loaded once (the scene importer's loader).
    pub(super) meshes: MeshCache<'a>,
    /// [`RobotImportOptions::frozen`].
    pub(super) frozen_values: &'a std::collections::BTreeMap<String, f64>,
    /// The frozen joints met so far.
    pub(super) frozen: Vec<FrozenJoint>,
}

impl Walk<'_> {
    /// Visits `base` (its frame at `base_from_link` in the base frame) and everything below
    /// it, parents before children (joint order of the document among siblings).
    pub(super) fn visit(
        &mut self,
        base: usize,
        base_from_link: Isometry3<f64>,
    ) -> Result<(), RobotError> {
        self.owner[base] = Some((0, base_from_link));
        self.add_colliders(base)?;
        let mut stack: Vec<usize> = self.tree.child_joints[base].iter().rev().copied().collect();
        while let Some(j) = stack.pop() {
            let child = self.tree.ends[j].1;
            self.joint(j)?;
            stack.extend(self.tree.child_joints[child].iter().rev().copied());
            self.add_colliders(child)?;
        }
        Ok(())
    }

    /// Handles joint `j`: an arm joint starts a new robot link, any other joint merges its
    /// child into the owner of its parent.
    fn joint(&mut self, j: usize) -> Result<(), RobotError> {
        let joint = &self.robot.joints[j];
        let (parent, child) = self.tree.ends[j];
        let (owner, owner_from_parent) =
            self.owner[parent].expect("parents are visited before children");
        let origin = origin(&joint.origin, || format!("joint {:?} origin", joint.name))?;
        if let Some(k) = self.arm.iter().position(|&a| a == j) {
            let mut arm_joint = arm_joint(joint, origin, true)?;
            if k == 0 {
                self.base_from_arm_root = owner_from_parent;
            } else {
                arm_joint.parent_from_joint = owner_from_parent * origin;
            }
            self.joints.push(arm_joint);
            self.links.push(RobotLink {
                name: self.robot.links[child].name.clone(),
                colliders: Vec::new(),
                contact: Vec::new(),
                merged: Vec::new(),
                sources: Vec::new(),
            });
            self.owner[child] = Some((k + 1, Isometry3::identity()));
            return Ok(());
        }
        let parent_from_child = match joint.joint_type {
            JointType::Fixed => origin,
            JointType::Revolute | JointType::Continuous | JointType::Prismatic => {
                // Not an arm joint: frozen at its configured value, or 0 clamped into its
                // limits.
                let frozen = arm_joint(joint, origin, false)?;
                let value = match self.frozen_values.get(&joint.name) {
                    Some(&v) if v.is_finite() && (frozen.lower..=frozen.upper).contains(&v) => v,
                    Some(&v) => {
                        return Err(RobotError::InvalidFrozen {
                            joint: joint.name.clone(),
                            reason: format!(
                                "value {v} outside the limits [{}, {}]",
                                frozen.lower, frozen.upper
                            ),
                        });
                    }
                    None => 0.0_f64.clamp(frozen.lower, frozen.upper),
                };
                self.frozen.push(FrozenJoint {
                    name: joint.name.clone(),
                    value,
                });
                frozen.parent_from_child(value)
            }
            JointType::Planar | JointType::Floating | JointType::Spherical => {
                return Err(RobotError::UnsupportedJointType {
                    joint: joint.name.clone(),
                    kind: format!("{:?}", joint.joint_type).to_lowercase(),
                });
            }
        };
        self.owner[child] = Some((owner, owner_from_parent * parent_from_child));
        Ok(())
    }

    /// Converts the collision elements of URDF link `l` into colliders of its owner.
    fn add_colliders(&mut self, l: usize) -> Result<(), RobotError> {
        let link = &self.robot.links[l];
        let (owner, owner_from_link) = self.owner[l].expect("visited");
        if !link.collision.is_empty() {
            self.links[owner].merged.push(link.name.clone());
        }
        for (index, collision) in link.collision.iter().enumerate() {
            let pose = origin(&collision.origin, || {
                format!("link {:?} collision {index} origin", link.name)
            })?;
            let shapes = match &collision.geometry {
                Geometry::Mesh { filename, scale } => {
                    self.mesh(&link.name, index, filename, scale.as_ref())?
                }
                primitive => vec![shape(&link.name, index, primitive)?],
            };
            let contact = owner == self.arm.len() && self.is_contact(&link.name, collision);
            let owner_link = &mut self.links[owner];
            let source = owner_link.merged.len() - 1;
            for shape in shapes {
                owner_link
                    .colliders
                    .push(Collider::new(shape, owner_from_link * pose));
                owner_link.contact.push(contact);
                owner_link.sources.push(source);
            }
        }
        Ok(())
    }

    /// The convex hulls of a collision mesh, one per non-empty sub-mesh, as the scene importer
    /// makes them (`package://` and relative URIs resolved by the options).
    fn mesh(
        &mut self,
        link: &str,
        index: usize,
        filename: &str,
        scale: Option<&urdf_rs::Vec3>,
    ) -> Result<Vec<Shape>, RobotError> {
        let failed = |reason: String| RobotError::MeshCollision {
            link: link.to_owned(),
            filename: filename.to_owned(),
            reason,
        };
        let scale = scale.map_or(Vector3::repeat(1.0), |s| Vector3::new(s[0], s[1], s[2]));
        if !scale.iter().all(|c| c.is_finite()) {
            return Err(RobotError::NonFinite {
                what: format!("link {link:?} collision {index} mesh scale"),
            });
        }
        let meshes = self
            .meshes
            .load(link, filename, &scale)
            .map_err(|e| failed(e.to_string()))?;
        if meshes.is_empty() {
            return Err(failed("the file has no vertices".into()));
        }
        let several = meshes.len() > 1;
        meshes
            .into_iter()
            .enumerate()
            .map(|(i, vertices)| {
                let shape = Shape::ConvexMesh {
                    vertices,
                    source: Some(MeshSource {
                        uri: filename.to_owned(),
                        scale,
                    }),
                };
                let what = if several {
                    format!("sub-mesh {i}")
                } else {
                    "mesh".to_owned()
                };
                shape.validate(&what).map_err(|e| failed(e.to_string()))?;
                Ok(shape)
            })
            .collect()
    }

    /// Whether a collision element of URDF link `link` (owned by the last arm link) is contact
    /// geometry: listed in the options, or named by the convention of
    /// [`RobotImportOptions::contact_links`].
    fn is_contact(&self, link: &str, collision: &urdf_rs::Collision) -> bool {
        match self.contact {
            Some(list) => list.iter().any(|l| l == link),
            None => {
                let named = |s: &str| {
                    let s = s.to_ascii_lowercase();
                    s.contains("finger") || s.contains("pad")
                };
                named(link) || collision.name.as_deref().is_some_and(named)
            }
        }
    }
}

/// A collision primitive (meshes go through `Walk::mesh`).
fn shape(link: &str, index: usize, geometry: &Geometry) -> Result<Shape, RobotError> {
    let invalid = |reason: String| RobotError::InvalidShape {
        link: link.to_owned(),
        index,
        reason,
    };
    let positive = |what: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(invalid(format!("{what} must be finite and > 0, got {v}")))
        }
    };
    Ok(match geometry {
        Geometry::Box { size } => Shape::box_size(Vector3::new(
            positive("box size x", size[0])?,
            positive("box size y", size[1])?,
            positive("box size z", size[2])?,
        )),
        Geometry::Cylinder { radius, length } => Shape::Cylinder {
            radius: positive("cylinder radius", *radius)?,
            length: positive("cylinder length", *length)?,
        },
        Geometry::Capsule { radius, length } => Shape::Capsule {
            radius: positive("capsule radius", *radius)?,
            length: positive("capsule length", *length)?,
        },
        Geometry::Sphere { radius } => Shape::Sphere {
            radius: positive("sphere radius", *radius)?,
        },
        Geometry::Mesh { filename, .. } => {
            return Err(RobotError::MeshCollision {
                link: link.to_owned(),
                filename: filename.clone(),
                reason: "a mesh is not a primitive (meshes are loaded as convex hulls)".into(),
            });
        }
    })
}
