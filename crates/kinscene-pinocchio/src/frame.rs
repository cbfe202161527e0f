//! Frames: indices, kinds, and the reference frames of Jacobians.

use nalgebra::Isometry3;

use crate::JointIndex;

/// Index of a frame in a [`crate::Model`] (Pinocchio's `FrameIndex`). Frame 0 is the universe
/// frame; every joint owns a frame of its name; [`crate::ModelBuilder::add_frame`] adds more.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FrameIndex(pub usize);

impl FrameIndex {
    /// The universe (world) frame.
    pub const UNIVERSE: FrameIndex = FrameIndex(0);
}

/// What a frame marks (Pinocchio's `FrameType`, restricted to the kinds this crate creates or
/// reads from URDF).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FrameKind {
    /// The frame of a joint (`JOINT`), created with the joint.
    Joint,
    /// An operational frame (`OP_FRAME`): a tool point, a grasp frame, a handle.
    Operational,
    /// The frame of a fixed joint (`FIXED_JOINT`), e.g. a URDF `fixed` joint merged into its
    /// parent link. The universe frame is of this kind too.
    FixedJoint,
    /// The frame of a URDF link (`BODY`), in models built by [`crate::Model::from_urdf_str`];
    /// find one with [`crate::Model::link_frame`].
    Body,
}

/// What a [`crate::Model`] knows about one of its frames.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Unique name.
    pub name: String,
    /// The joint the frame is rigidly attached to.
    pub parent_joint: JointIndex,
    /// Placement of the frame in its joint's frame.
    pub joint_from_frame: Isometry3<f64>,
    /// Kind.
    pub kind: FrameKind,
}

/// In which frame a Jacobian's velocities are expressed (Pinocchio's `ReferenceFrame`).
///
/// A frame Jacobian `J` (6 × nv) maps joint velocities `v` to a spatial velocity `J v` of the
/// frame, stacked as **linear velocity (rows 0–2, m/s) then angular velocity (rows 3–5,
/// rad/s)**, as Pinocchio does. The three choices differ in which point's linear velocity is
/// given and in which axes both parts are written:
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReferenceFrame {
    /// Body twist: the velocity of the frame's origin and the angular velocity, both in the
    /// frame's own axes (`LOCAL`). `[v; ω] = (world_from_frame⁻¹ · d/dt world_from_frame)^∨`.
    Local,
    /// Spatial twist: angular velocity in world axes, and the linear velocity of the point of
    /// the moving body that is momentarily at the world origin, in world axes (`WORLD`).
    /// `[v; ω] = (d/dt world_from_frame · world_from_frame⁻¹)^∨`.
    World,
    /// The frame origin's velocity and the angular velocity, both in world axes
    /// (`LOCAL_WORLD_ALIGNED`): `v = d/dt p_world`, `ω` as in [`ReferenceFrame::World`].
    LocalWorldAligned,
}

impl ReferenceFrame {
    /// All three, for loops in tests and benches.
    pub const ALL: [ReferenceFrame; 3] = [
        ReferenceFrame::Local,
        ReferenceFrame::World,
        ReferenceFrame::LocalWorldAligned,
    ];

    pub(crate) fn raw(self) -> std::ffi::c_int {
        match self {
            ReferenceFrame::Local => crate::ffi::LOCAL,
            ReferenceFrame::World => crate::ffi::WORLD,
            ReferenceFrame::LocalWorldAligned => crate::ffi::LOCAL_WORLD_ALIGNED,
        }
    }
}
