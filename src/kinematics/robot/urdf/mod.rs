//! Parsing a robot URDF (urdf-rs) into arm joints, merged links and fixed frames.

mod approach;
mod base;
mod depth;
mod joint;
mod tree;
mod walk;

use nalgebra::Isometry3;

use super::{ArmJoint, FrozenJoint, RobotError, RobotImportOptions, RobotLink};
use depth::{MAX_DEPTH, nesting_depth};
use tree::Tree;

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
