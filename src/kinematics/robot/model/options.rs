//! The options of a URDF import: tool link, contact geometry, mesh paths, arm root, approach
//! axis and frozen joint values.

use std::collections::BTreeMap;
use std::path::PathBuf;

#[cfg(doc)]
use super::RobotModel;

/// Import options of [`RobotModel::from_urdf_str_with`].
#[derive(Debug, Clone, PartialEq)]
pub struct RobotImportOptions {
    /// Name of the link whose frame is the tool frame (TCP). Default `"tool_frame"`.
    pub tool_link: String,
    /// The URDF links whose collision elements are the gripper's contact geometry: the only
    /// shapes allowed to touch a grasped part, and only while grasping. Each must be rigidly
    /// attached below the last arm joint (it moves with the tool).
    ///
    /// `None` (the default) applies the naming convention: a collision element below the last
    /// arm joint is contact geometry when the name of its URDF link or of the `<collision>`
    /// element contains `finger` or `pad` (ASCII case-insensitive), as in the usual gripper
    /// descriptions (`panda_leftfinger`, `left_inner_finger_pad`, `gripper_finger_link`).
    /// `Some(vec![])` declares a robot without contact geometry: then no shape may touch a
    /// grasped part.
    pub contact_links: Option<Vec<String>>,
    /// Package roots for mesh URIs: `package://NAME/rest` resolves to
    /// `package_paths[NAME]/rest`. Default empty.
    pub package_paths: BTreeMap<String, PathBuf>,
    /// Directory that relative mesh paths resolve against. `None`: the current directory;
    /// [`RobotModel::from_urdf_file_with`] uses the file's directory when this is `None`.
    pub base_dir: Option<PathBuf>,
    /// The link the arm starts at. `None` (the default): the base link, so every movable joint
    /// on the path from the base to the tool link is an arm joint. With a link on that path,
    /// the movable joints above it (a torso lift, say) are frozen like the joints off the
    /// path ([`RobotImportOptions::frozen`]).
    pub arm_root: Option<String>,
    /// The approach direction in the tool link's frame, when it is not the link's +z (a hand
    /// whose fingers point along its x, say): the tool frame is then the tool link's frame
    /// turned so that its +z is this direction. Default `None`.
    pub tool_approach: Option<[f64; 3]>,
    /// Values (rad or m) of movable joints that are not arm joints: a head, wheels, a second
    /// arm, fingers, joints above [`RobotImportOptions::arm_root`]. Such a joint is frozen at
    /// its value here, or at 0 clamped into its limits, and its links stay in the collision
    /// model at that value. Default empty.
    pub frozen: BTreeMap<String, f64>,
}

impl Default for RobotImportOptions {
    fn default() -> Self {
        RobotImportOptions {
            tool_link: "tool_frame".to_owned(),
            contact_links: None,
            package_paths: BTreeMap::new(),
            base_dir: None,
            arm_root: None,
            tool_approach: None,
            frozen: BTreeMap::new(),
        }
    }
}
