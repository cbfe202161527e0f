//! The URDF's link tree: indices and checks that it is a tree, the arm found in it, and the
//! links the options name checked against it.

use std::collections::HashMap;

use nalgebra::Isometry3;

use super::Parsed;
use super::approach::approach_rotation;
use super::base::BaseLink;
use super::joint::is_movable;
use super::walk::Walk;
use crate::kinematics::robot::{RobotError, RobotImportOptions, RobotLink};
use crate::scene::urdf::ImportOptions;
use crate::scene::urdf::mesh::MeshCache;

/// Link and joint indices of the URDF tree.
pub(super) struct Tree {
    /// Link name → index in `robot.links`.
    pub(super) links: HashMap<String, usize>,
    /// Per link: the joint (index in `robot.joints`) whose child it is.
    pub(super) parent_joint: Vec<Option<usize>>,
    /// Per link: joints whose parent it is, in document order.
    pub(super) child_joints: Vec<Vec<usize>>,
    /// The joints' (parent, child) link indices.
    pub(super) ends: Vec<(usize, usize)>,
    /// The root link.
    pub(super) root: usize,
}

impl Tree {
    pub(super) fn new(robot: &urdf_rs::Robot) -> Result<Tree, RobotError> {
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

    pub(super) fn parse(
        &self,
        robot: &urdf_rs::Robot,
        options: &RobotImportOptions,
    ) -> Result<Parsed, RobotError> {
        let (base, tool, arm) = self.arm(robot, options)?;
        let base_link = base.link;
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
                sources: Vec::new(),
            }],
            contact: options.contact_links.as_deref(),
            owner: vec![None; robot.links.len()],
            base_from_arm_root: Isometry3::identity(),
            frozen_values: &options.frozen,
            frozen: Vec::new(),
        };
        walk.visit(base_link, base.base_from_link)?;
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
    /// The base link ([`Tree::base_link`]), the tool link and the arm: the movable joints on
    /// the path from the base (or the arm root) to the tool, as indices in `robot.joints`.
    fn arm(
        &self,
        robot: &urdf_rs::Robot,
        options: &RobotImportOptions,
    ) -> Result<(BaseLink, usize, Vec<usize>), RobotError> {
        // A planar or floating joint, or an x/y/yaw chain, out of the root (a `world`/`odom`
        // link) is the base's implicit planar motion: skip it.
        let base = self.base_link(robot);
        let base_link = base.link;
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
        Ok((base, tool, arm))
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
