//! Parsing a robot URDF (urdf-rs) into arm joints, merged links and fixed frames.

use std::collections::HashMap;

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use urdf_rs::{Geometry, JointType};

use super::model::check_positive_limit;
use super::{
    ArmJoint, ArmJointKind, DEFAULT_PRISMATIC_ACCELERATION, DEFAULT_REVOLUTE_ACCELERATION,
    FrozenJoint, RobotError, RobotImportOptions, RobotLink,
};
use crate::scene::urdf::ImportOptions;
use crate::scene::urdf::mesh::MeshCache;
use crate::scene::{Collider, MeshSource, Shape};

/// Deepest element nesting accepted: urdf-rs recurses once per level, so absurdly deep input
/// would overflow the stack (an abort, not an error). A URDF needs 5 levels.
const MAX_DEPTH: usize = 64;

/// The robot as read from URDF, before the Pinocchio model is built.
#[derive(Debug)]
pub(super) struct Parsed {
    pub name: String,
    pub joints: Vec<ArmJoint>,
    pub links: Vec<RobotLink>,
    pub base_from_arm_root: Isometry3<f64>,
    pub last_from_tool: Isometry3<f64>,
    pub frozen: Vec<FrozenJoint>,
}

/// Parses and checks a robot URDF (see the module docs of `robot` for the conventions).
pub(super) fn parse(text: &str, options: &RobotImportOptions) -> Result<Parsed, RobotError> {
    let depth = nesting_depth(text);
    if depth > MAX_DEPTH {
        return Err(RobotError::Xml {
            message: format!("elements nest {depth} levels deep (at most {MAX_DEPTH} accepted)"),
        });
    }
    let robot = urdf_rs::read_from_string(text).map_err(|e| RobotError::Xml {
        message: e.to_string(),
    })?;
    Tree::new(&robot)?.parse(&robot, options)
}

/// Link and joint indices of the URDF tree.
struct Tree {
    /// Link name → index in `robot.links`.
    links: HashMap<String, usize>,
    /// Per link: the joint (index in `robot.joints`) whose child it is.
    parent_joint: Vec<Option<usize>>,
    /// Per link: joints whose parent it is, in document order.
    child_joints: Vec<Vec<usize>>,
    /// The joints' (parent, child) link indices.
    ends: Vec<(usize, usize)>,
    /// The root link.
    root: usize,
}

impl Tree {
    fn new(robot: &urdf_rs::Robot) -> Result<Tree, RobotError> {
        let mut links = HashMap::new();
        for (i, link) in robot.links.iter().enumerate() {
            if links.insert(link.name.clone(), i).is_some() {
                return Err(RobotError::DuplicateName {
                    what: "link",
                    name: link.name.clone(),
                });
            }
        }
        let mut joint_names = HashMap::new();
        let mut parent_joint = vec![None; robot.links.len()];
        let mut child_joints = vec![Vec::new(); robot.links.len()];
        let mut ends = Vec::with_capacity(robot.joints.len());
        for (j, joint) in robot.joints.iter().enumerate() {
            if joint_names.insert(joint.name.as_str(), j).is_some() {
                return Err(RobotError::DuplicateName {
                    what: "joint",
                    name: joint.name.clone(),
                });
            }
            let find = |role: &'static str, link: &str| {
                links
                    .get(link)
                    .copied()
                    .ok_or_else(|| RobotError::UnknownLink {
                        joint: joint.name.clone(),
                        role,
                        link: link.to_owned(),
                    })
            };
            let parent = find("parent", &joint.parent.link)?;
            let child = find("child", &joint.child.link)?;
            if let Some(other) = parent_joint[child] {
                let other: &urdf_rs::Joint = &robot.joints[other];
                return Err(RobotError::NotATree {
                    reason: format!(
                        "link {:?} is the child of joints {:?} and {:?}",
                        joint.child.link, other.name, joint.name
                    ),
                });
            }
            parent_joint[child] = Some(j);
            child_joints[parent].push(j);
            ends.push((parent, child));
        }
        let roots: Vec<usize> = (0..robot.links.len())
            .filter(|&l| parent_joint[l].is_none())
            .collect();
        let root = match roots.as_slice() {
            [root] => *root,
            [] => {
                return Err(RobotError::NotATree {
                    reason: if robot.links.is_empty() {
                        "there are no links".into()
                    } else {
                        "every link has a parent (the joints form a cycle)".into()
                    },
                });
            }
            several => {
                let names: Vec<&str> = several
                    .iter()
                    .map(|&l| robot.links[l].name.as_str())
                    .collect();
                return Err(RobotError::NotATree {
                    reason: format!("several root links {names:?}"),
                });
            }
        };
        let tree = Tree {
            links,
            parent_joint,
            child_joints,
            ends,
            root,
        };
        // Every link must be reachable from the root (otherwise there is a cycle).
        let mut seen = vec![false; robot.links.len()];
        let mut stack = vec![root];
        while let Some(l) = stack.pop() {
            seen[l] = true;
            stack.extend(tree.child_joints[l].iter().map(|&j| tree.ends[j].1));
        }
        if let Some(l) = seen.iter().position(|s| !s) {
            return Err(RobotError::NotATree {
                reason: format!("link {:?} lies on a cycle", robot.links[l].name),
            });
        }
        Ok(tree)
    }

    fn parse(
        &self,
        robot: &urdf_rs::Robot,
        options: &RobotImportOptions,
    ) -> Result<Parsed, RobotError> {
        let (base_link, tool, arm) = self.arm(robot, options)?;
        let mesh_options = ImportOptions {
            package_paths: options.package_paths.clone(),
            base_dir: options.base_dir.clone(),
            ..ImportOptions::default()
        };
        let mut walk = Walk {
            meshes: MeshCache::new(&mesh_options),
            robot,
            tree: self,
            arm: &arm,
            joints: Vec::with_capacity(arm.len()),
            links: vec![RobotLink {
                name: robot.links[base_link].name.clone(),
                colliders: Vec::new(),
                contact: Vec::new(),
                merged: Vec::new(),
            }],
            contact: options.contact_links.as_deref(),
            owner: vec![None; robot.links.len()],
            base_from_arm_root: Isometry3::identity(),
            frozen_values: &options.frozen,
            frozen: Vec::new(),
        };
        walk.visit(base_link)?;
        self.check_named_links(robot, options, &arm, &walk)?;
        let (owner, last_from_link) = walk.owner[tool].ok_or_else(|| RobotError::NotATree {
            reason: format!("tool link {:?} is not below the base", options.tool_link),
        })?;
        debug_assert_eq!(owner, arm.len());
        let last_from_tool = last_from_link * approach_rotation(options)?;
        Ok(Parsed {
            name: robot.name.clone(),
            joints: walk.joints,
            links: walk.links,
            base_from_arm_root: walk.base_from_arm_root,
            last_from_tool,
            frozen: walk.frozen,
        })
    }
}

impl Tree {
    /// The base link (the root, or the root's child through a planar or floating joint), the
    /// tool link and the arm: the movable joints on the path from the base (or the arm root)
    /// to the tool, as indices in `robot.joints`.
    fn arm(
        &self,
        robot: &urdf_rs::Robot,
        options: &RobotImportOptions,
    ) -> Result<(usize, usize, Vec<usize>), RobotError> {
        // A planar or floating joint out of the root (a `world`/`odom` link) is the base's
        // implicit planar motion: skip it.
        let base_link = match self.child_joints[self.root].as_slice() {
            [j] if matches!(
                robot.joints[*j].joint_type,
                JointType::Planar | JointType::Floating
            ) =>
            {
                self.ends[*j].1
            }
            _ => self.root,
        };
        let tool =
            *self
                .links
                .get(&options.tool_link)
                .ok_or_else(|| RobotError::MissingToolLink {
                    link: options.tool_link.clone(),
                })?;
        // The path base → tool; its movable joints are the arm.
        let mut path = Vec::new();
        let mut at = tool;
        while at != base_link {
            let Some(j) = self.parent_joint[at] else {
                // The tool is the skipped root link: no movable joint.
                return Err(RobotError::NoMovableJoint {
                    base: robot.links[base_link].name.clone(),
                });
            };
            path.push(j);
            at = self.ends[j].0;
        }
        path.reverse();
        // The arm starts below the arm root: drop the path's joints above it.
        if let Some(root) = &options.arm_root {
            let invalid = |reason: &str| RobotError::InvalidArmRoot {
                link: root.clone(),
                reason: reason.to_owned(),
            };
            let &link = self
                .links
                .get(root)
                .ok_or_else(|| invalid("no such link"))?;
            if link != base_link {
                let k = path
                    .iter()
                    .position(|&j| self.ends[j].1 == link)
                    .ok_or_else(|| {
                        invalid("not on the path from the base link to the tool link")
                    })?;
                path.drain(..=k);
            }
        }
        let arm: Vec<usize> = path
            .iter()
            .copied()
            .filter(|&j| is_movable(&robot.joints[j].joint_type))
            .collect();
        if arm.is_empty() {
            return Err(RobotError::NoMovableJoint {
                base: robot.links[base_link].name.clone(),
            });
        }
        Ok((base_link, tool, arm))
    }

    /// The frozen joints and contact links the options name exist where they must: a frozen
    /// joint is a movable joint off the arm, a contact link is rigidly attached below the last
    /// arm joint.
    fn check_named_links(
        &self,
        robot: &urdf_rs::Robot,
        options: &RobotImportOptions,
        arm: &[usize],
        walk: &Walk<'_>,
    ) -> Result<(), RobotError> {
        if let Some(name) = options
            .frozen
            .keys()
            .find(|name| !walk.frozen.iter().any(|f| &&f.name == name))
        {
            let reason = if arm.iter().any(|&j| &robot.joints[j].name == name) {
                "an arm joint, not frozen"
            } else {
                "no movable joint off the arm has this name"
            };
            return Err(RobotError::InvalidFrozen {
                joint: name.clone(),
                reason: reason.to_owned(),
            });
        }
        for name in options.contact_links.iter().flatten() {
            let owner = self.links.get(name).map(|&l| walk.owner[l]);
            let reason = match owner {
                None => "no such link",
                Some(None) => "not below the base link",
                Some(Some((o, _))) if o != arm.len() => {
                    "not rigidly attached below the last arm joint (it does not move with the tool)"
                }
                Some(Some(_)) => continue,
            };
            return Err(RobotError::InvalidContactLink {
                link: name.clone(),
                reason: reason.to_owned(),
            });
        }
        Ok(())
    }
}

/// The depth-first walk from the base link that assigns every link to its owning robot link.
struct Walk<'a> {
    robot: &'a urdf_rs::Robot,
    tree: &'a Tree,
    /// The arm joints (indices in `robot.joints`), root to tip.
    arm: &'a [usize],
    joints: Vec<ArmJoint>,
    links: Vec<RobotLink>,
    /// Per URDF link: (robot link index, robot link frame from URDF link frame).
    owner: Vec<Option<(usize, Isometry3<f64>)>>,
    base_from_arm_root: Isometry3<f64>,
    /// [`RobotImportOptions::contact_links`].
    contact: Option<&'a [String]>,
    /// Collision meshes, each file loaded once (the scene importer's loader).
    meshes: MeshCache<'a>,
    /// [`RobotImportOptions::frozen`].
    frozen_values: &'a std::collections::BTreeMap<String, f64>,
    /// The frozen joints met so far.
    frozen: Vec<FrozenJoint>,
}

impl Walk<'_> {
    /// Visits `base` and everything below it, parents before children (joint order of the
    /// document among siblings).
    fn visit(&mut self, base: usize) -> Result<(), RobotError> {
        self.owner[base] = Some((0, Isometry3::identity()));
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
            for shape in shapes {
                owner_link
                    .colliders
                    .push(Collider::new(shape, owner_from_link * pose));
                owner_link.contact.push(contact);
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

/// The tool frame in the tool link's frame: a rotation taking +z onto
/// [`RobotImportOptions::tool_approach`] (the identity without one).
fn approach_rotation(options: &RobotImportOptions) -> Result<Isometry3<f64>, RobotError> {
    let Some(axis) = options.tool_approach else {
        return Ok(Isometry3::identity());
    };
    let invalid = || RobotError::InvalidToolApproach { axis };
    let axis = Vector3::from(axis);
    if !axis.iter().all(|c| c.is_finite()) {
        return Err(invalid());
    }
    let axis = axis.try_normalize(1e-12).ok_or_else(invalid)?;
    // rotation_between has no unique answer for the opposite direction: a half turn about x.
    let rotation = UnitQuaternion::rotation_between(&Vector3::z(), &axis).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    Ok(Isometry3::from_parts(Translation3::identity(), rotation))
}

fn is_movable(kind: &JointType) -> bool {
    matches!(
        kind,
        JointType::Revolute | JointType::Continuous | JointType::Prismatic
    )
}

/// An actuated joint from its URDF element (`parent_from_joint` = the given origin). The
/// velocity and acceleration limits are checked only if `actuated` (not for frozen gripper
/// joints, which only need an axis and limits).
fn arm_joint(
    joint: &urdf_rs::Joint,
    origin: Isometry3<f64>,
    actuated: bool,
) -> Result<ArmJoint, RobotError> {
    let name = &joint.name;
    let axis = Vector3::from(*joint.axis.xyz);
    let invalid_axis = || RobotError::InvalidAxis {
        joint: name.clone(),
        axis: *joint.axis.xyz,
    };
    if !axis.iter().all(|c| c.is_finite()) {
        return Err(invalid_axis());
    }
    let axis = Unit::try_new(axis, 1e-12).ok_or_else(invalid_axis)?;
    let limit = &joint.limit;
    let (kind, lower, upper, default_acceleration) = match joint.joint_type {
        JointType::Continuous => (
            ArmJointKind::Continuous,
            f64::NEG_INFINITY,
            f64::INFINITY,
            DEFAULT_REVOLUTE_ACCELERATION,
        ),
        JointType::Prismatic => (
            ArmJointKind::Prismatic,
            limit.lower,
            limit.upper,
            DEFAULT_PRISMATIC_ACCELERATION,
        ),
        _ => (
            ArmJointKind::Revolute,
            limit.lower,
            limit.upper,
            DEFAULT_REVOLUTE_ACCELERATION,
        ),
    };
    if lower.is_nan() || upper.is_nan() || lower > upper {
        return Err(RobotError::InvalidLimits {
            joint: name.clone(),
            lower,
            upper,
        });
    }
    if actuated {
        check_positive_limit(name, "velocity", limit.velocity)?;
    }
    // URDF 1.2 acceleration limits; absent ones read as +∞ and take the default.
    let max_acceleration = if limit.acceleration == f64::INFINITY || !actuated {
        default_acceleration
    } else {
        check_positive_limit(name, "acceleration", limit.acceleration)?;
        limit.acceleration
    };
    Ok(ArmJoint {
        name: name.clone(),
        kind,
        parent_from_joint: origin,
        axis,
        lower,
        upper,
        max_velocity: limit.velocity,
        max_acceleration,
    })
}

/// A URDF `<origin xyz rpy>` as `parent_from_child`, rpy fixed-axis `Rz(y)·Ry(p)·Rx(r)`.
fn origin(pose: &urdf_rs::Pose, what: impl Fn() -> String) -> Result<Isometry3<f64>, RobotError> {
    if !pose
        .xyz
        .iter()
        .chain(pose.rpy.iter())
        .all(|c| c.is_finite())
    {
        return Err(RobotError::NonFinite { what: what() });
    }
    Ok(Isometry3::from_parts(
        Translation3::new(pose.xyz[0], pose.xyz[1], pose.xyz[2]),
        UnitQuaternion::from_euler_angles(pose.rpy[0], pose.rpy[1], pose.rpy[2]),
    ))
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

/// An upper bound on the element nesting depth of `text` (comments, CDATA sections,
/// processing instructions and declarations skipped; exact on well-formed XML).
fn nesting_depth(text: &str) -> usize {
    let b = text.as_bytes();
    let (mut depth, mut max) = (0usize, 0usize);
    let mut i = 0;
    while let Some(k) = b[i..].iter().position(|&c| c == b'<') {
        let lt = i + k;
        let rest = &b[lt..];
        let skip_to = |pattern: &[u8], from: usize| {
            b[from.min(b.len())..]
                .windows(pattern.len())
                .position(|w| w == pattern)
                .map_or(b.len(), |p| from + p + pattern.len())
        };
        i = if rest.starts_with(b"<!--") {
            skip_to(b"-->", lt + 4)
        } else if rest.starts_with(b"<![CDATA[") {
            skip_to(b"]]>", lt + 9)
        } else if rest.starts_with(b"<?") {
            skip_to(b"?>", lt + 2)
        } else if rest.starts_with(b"<!") {
            skip_to(b">", lt + 2)
        } else if rest.starts_with(b"</") {
            depth = depth.saturating_sub(1);
            skip_to(b">", lt + 2)
        } else {
            // A start tag: find its end, skipping quoted attribute values.
            let mut quote = None;
            let mut end = b.len();
            for (p, &c) in b.iter().enumerate().skip(lt + 1) {
                match (quote, c) {
                    (Some(q), _) if c == q => quote = None,
                    (Some(_), _) => {}
                    (None, b'"' | b'\'') => quote = Some(c),
                    (None, b'>') => {
                        end = p + 1;
                        break;
                    }
                    _ => {}
                }
            }
            let self_closing = end >= 2 && end <= b.len() && b[end - 2] == b'/';
            if !self_closing {
                depth += 1;
                max = max.max(depth);
            } else {
                max = max.max(depth + 1);
            }
            end
        };
        if i >= b.len() {
            break;
        }
    }
    max
}

#[cfg(test)]
mod tests {
    use super::nesting_depth;

    #[test]
    fn nesting_depth_counts_elements_only() {
        let text = r#"<?xml version="1.0"?><!-- <a><b><c> -->
            <robot name="r>"><link name="a"><collision><geometry><box size="1 1 1"/></geometry>
            </collision></link><![CDATA[<x><y>]]></robot>"#;
        assert_eq!(nesting_depth(text), 5);
        assert_eq!(nesting_depth(&"<a>".repeat(1000)), 1000);
    }
}
