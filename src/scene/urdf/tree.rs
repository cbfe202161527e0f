//! The link tree of a URDF document: unique names, supported joint types, existing links, one
//! parent per link, exactly one root, no cycles.

use std::collections::{BTreeMap, BTreeSet};

use urdf_rs::{JointType, Robot};

use crate::scene::{ElementKind, Error};

/// The validated tree structure of a URDF robot (indices into `robot.links` and
/// `robot.joints`).
#[derive(Debug)]
pub(super) struct LinkTree {
    /// The root link: the static base.
    pub root: usize,
    /// For each link, the joints whose parent it is, in document order.
    pub children: Vec<Vec<usize>>,
    /// For each joint, its child link.
    pub child: Vec<usize>,
}

/// Validates the tree of `robot`.
///
/// Checks, in this order: link names unique ([`Error::DuplicateLink`]); joint names unique
/// ([`Error::DuplicateName`]); joint types ([`Error::UnsupportedJointType`] for `planar`,
/// `floating`, `spherical`); links named by joints exist ([`Error::MissingLink`]); no link is
/// the child of two joints ([`Error::SeveralParents`]); one root ([`Error::NoRoot`] without
/// links, [`Error::SeveralRoots`]); every link reachable from the root ([`Error::Cycle`] with
/// the links of a cycle otherwise).
pub(super) fn resolve(robot: &Robot) -> Result<LinkTree, Error> {
    let mut index = BTreeMap::new();
    for (k, link) in robot.links.iter().enumerate() {
        if index.insert(link.name.as_str(), k).is_some() {
            return Err(Error::DuplicateLink {
                name: link.name.clone(),
            });
        }
    }
    let mut joint_names = BTreeSet::new();
    for joint in &robot.joints {
        if !joint_names.insert(joint.name.as_str()) {
            return Err(Error::DuplicateName {
                kind: ElementKind::Joint,
                name: joint.name.clone(),
            });
        }
    }
    for joint in &robot.joints {
        if let JointType::Planar | JointType::Floating | JointType::Spherical = joint.joint_type {
            return Err(Error::UnsupportedJointType {
                joint: joint.name.clone(),
                kind: format!("{:?}", joint.joint_type).to_lowercase(),
            });
        }
    }
    let n = robot.links.len();
    let mut children = vec![Vec::new(); n];
    let mut child = Vec::with_capacity(robot.joints.len());
    let mut parent_joints: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (j, joint) in robot.joints.iter().enumerate() {
        let lookup = |role: &str, link: &str| {
            index.get(link).copied().ok_or_else(|| Error::MissingLink {
                joint: joint.name.clone(),
                role: role.to_string(),
                link: link.to_string(),
            })
        };
        let p = lookup("parent", &joint.parent.link)?;
        let c = lookup("child", &joint.child.link)?;
        children[p].push(j);
        child.push(c);
        parent_joints[c].push(j);
    }
    if let Some((link, joints)) = parent_joints.iter().enumerate().find(|(_, j)| j.len() > 1) {
        return Err(Error::SeveralParents {
            link: robot.links[link].name.clone(),
            joints: joints
                .iter()
                .map(|&j| robot.joints[j].name.clone())
                .collect(),
        });
    }
    // From here on every link has at most one parent joint.
    let parent_link = |link: usize| -> Option<usize> {
        let joint = &robot.joints[*parent_joints[link].first()?];
        index.get(joint.parent.link.as_str()).copied()
    };
    let roots: Vec<usize> = (0..n).filter(|&k| parent_joints[k].is_empty()).collect();
    let root = match roots.as_slice() {
        [root] => *root,
        [] if n == 0 => {
            return Err(Error::NoRoot {
                robot: robot.name.clone(),
            });
        }
        [] => return Err(cycle_from(robot, 0, &parent_link)),
        _ => {
            return Err(Error::SeveralRoots {
                links: roots.iter().map(|&k| robot.links[k].name.clone()).collect(),
            });
        }
    };
    // Links not reachable from the root lie on or hang below a cycle.
    let mut reached = vec![false; n];
    let mut stack = vec![root];
    while let Some(link) = stack.pop() {
        if !std::mem::replace(&mut reached[link], true) {
            stack.extend(children[link].iter().map(|&j| child[j]));
        }
    }
    if let Some(unreached) = reached.iter().position(|r| !r) {
        return Err(cycle_from(robot, unreached, &parent_link));
    }
    Ok(LinkTree {
        root,
        children,
        child,
    })
}

/// The cycle reached by following parent links from `start` (every link on the way has
/// exactly one parent), as [`Error::Cycle`] with link names in parent order.
fn cycle_from(robot: &Robot, start: usize, parent_link: &dyn Fn(usize) -> Option<usize>) -> Error {
    let mut chain = Vec::new();
    let mut seen = vec![false; robot.links.len()];
    let mut link = Some(start);
    while let Some(k) = link {
        if seen[k] {
            let from = chain.iter().position(|&c| c == k).unwrap_or(0);
            return Error::Cycle {
                parts: chain[from..]
                    .iter()
                    .map(|&c: &usize| robot.links[c].name.clone())
                    .collect(),
            };
        }
        seen[k] = true;
        chain.push(k);
        link = parent_link(k);
    }
    // Unreachable for the callers' inputs (a parentless link would be a root); report the
    // chain walked.
    Error::Cycle {
        parts: chain.iter().map(|&c| robot.links[c].name.clone()).collect(),
    }
}
