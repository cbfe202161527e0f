//! Grasp frames along the handle trajectory of one joint change (the paper's Eq. (3)–(5)).

use nalgebra::{
    Isometry3, Matrix3, Point3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3,
};

use super::PlacementError;
use crate::kinematics::ik::IkTarget;
use crate::scene::motion::grasp_trajectory;
use crate::scene::{HandleId, JointId, SceneData, SceneModel, State, joint_axis};

/// How the tool's rotation about the approach axis is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GraspRotation {
    /// Free: the IK target is [`IkTarget::PositionAxis`] (tool origin at the grasp point, tool
    /// +z along the approach direction, any rotation about it). The default: the handles of
    /// the scene model carry a point and a normal only, and the extra freedom lets the arm
    /// reach more waypoints.
    #[default]
    Free,
    /// Fixed by the rule of [`GraspFrame::world_from_tool`]; the IK target is
    /// [`IkTarget::Pose`]. Use it when the gripper must keep a known orientation on the
    /// handle (e.g. fingers across a bar).
    Fixed,
}

/// The tool frame wanted at one waypoint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GraspFrame {
    /// The grasp point (m, world frame): the tool origin goes here.
    pub position: Point3<f64>,
    /// The approach direction (world frame): the tool's +z axis, `−normal` (pointing into the
    /// part's surface).
    pub approach: Unit<Vector3<f64>>,
    /// The full tool pose of [`GraspRotation::Fixed`]: origin at `position`, +z = `approach`,
    /// +x = the *reference direction* projected onto the plane normal to `approach` (and
    /// normalised), +y = z × x. The reference direction is chosen once per trajectory, from
    /// the first waypoint: the joint's world axis `u` if `|u · a₀| < 0.9`, else world +z if
    /// `|z · a₀| < 0.9`, else world +x. For a revolute joint `u · aₖ` is the same at every
    /// waypoint (the normal turns about `u`) and for a prismatic one `aₖ` is constant, so the
    /// projection never degenerates and the frame turns continuously with the part. (A door
    /// hinged about a vertical axis thus gets tool +x along the hinge axis, vertical; a drawer
    /// pulled along its normal gets tool +x vertical, world +z.)
    pub world_from_tool: Isometry3<f64>,
}

impl GraspFrame {
    /// The IK target for a base at `world_from_base`, in the base frame (the IK's root frame).
    pub fn ik_target(&self, world_from_base: &Isometry3<f64>, rotation: GraspRotation) -> IkTarget {
        let base_from_world = world_from_base.inverse();
        match rotation {
            GraspRotation::Free => IkTarget::PositionAxis {
                position: base_from_world * self.position,
                axis: Unit::new_normalize(base_from_world * self.approach.into_inner()),
            },
            GraspRotation::Fixed => IkTarget::Pose(base_from_world * self.world_from_tool),
        }
    }
}

/// One joint change and the grasp frames along it.
#[derive(Debug, Clone, PartialEq)]
pub struct JointMotion {
    /// The joint that moves.
    pub joint: JointId,
    /// The handle grasped (on the joint's part or a descendant).
    pub handle: HandleId,
    /// The joint's value at the start (its value in the given state).
    pub from: f64,
    /// The joint's value at the end.
    pub to: f64,
    /// The joint's value at each waypoint: `from + (k / K)(to − from)`, `k = 0..=K`.
    pub values: Vec<f64>,
    /// The grasp frame at each waypoint (`K + 1`).
    pub grasps: Vec<GraspFrame>,
}

impl JointMotion {
    /// The grasp frames while `joint` goes from its value in `state` to `to` in `steps` equal
    /// steps: positions and normals from
    /// [`grasp_trajectory`](crate::scene::motion::grasp_trajectory), orientations as documented
    /// on [`GraspFrame`].
    ///
    /// # Errors
    /// [`PlacementError::Scene`] for foreign ids, a state not sized for the model, a value
    /// outside the joint's limits, a handle that does not move with the joint, or `steps` out
    /// of range.
    pub fn new(
        model: &SceneModel,
        state: &State,
        joint: JointId,
        handle: HandleId,
        to: f64,
        steps: usize,
    ) -> Result<JointMotion, PlacementError> {
        state.check_len(model)?;
        let from = state.value(joint).ok_or(crate::scene::Error::UnknownId {
            kind: crate::scene::ElementKind::Joint,
            index: joint.index(),
        })?;
        let mut data = SceneData::new(model);
        let poses = grasp_trajectory(model, &mut data, state, handle, joint, from, to, steps)?;
        // `data` holds the FK at `from`; the axis depends on the ancestors only.
        let axis = joint_axis(model, &data, joint)?.direction;
        let a0 = -poses[0].normal.into_inner();
        let reference = [axis.into_inner(), Vector3::z(), Vector3::x()]
            .into_iter()
            .find(|r| r.dot(&a0).abs() < 0.9)
            .unwrap_or_else(Vector3::y);
        let grasps = poses
            .iter()
            .map(|p| grasp_frame(p.position, -p.normal, &reference))
            .collect();
        let values = (0..=steps)
            .map(|k| from + (k as f64 / steps as f64) * (to - from))
            .collect();
        Ok(JointMotion {
            joint,
            handle,
            from,
            to,
            values,
            grasps,
        })
    }

    /// Number of waypoints, `K + 1`.
    pub fn len(&self) -> usize {
        self.grasps.len()
    }

    /// Always false (a motion has at least two waypoints).
    pub fn is_empty(&self) -> bool {
        self.grasps.is_empty()
    }

    /// The scene state at waypoint `k`: `state` with the joint at [`JointMotion::values`]`[k]`.
    pub fn state_at(&self, state: &State, k: usize) -> State {
        let mut s = state.clone();
        s.set_unchecked(self.joint, self.values[k]);
        s
    }
}

/// The grasp frame at `position` with tool +z = `approach` and +x from `reference` (falling
/// back to world x, then y, should the projection be shorter than 1e-6).
fn grasp_frame(
    position: Point3<f64>,
    approach: Unit<Vector3<f64>>,
    reference: &Vector3<f64>,
) -> GraspFrame {
    let z = approach.into_inner();
    let x = [*reference, Vector3::x(), Vector3::y()]
        .iter()
        .map(|r| r - z * r.dot(&z))
        .find(|p| p.norm() > 1e-6)
        .unwrap_or_else(Vector3::x)
        .normalize();
    let y = z.cross(&x);
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, y, z]));
    GraspFrame {
        position,
        approach,
        world_from_tool: Isometry3::from_parts(
            Translation3::from(position.coords),
            UnitQuaternion::from_rotation_matrix(&rotation),
        ),
    }
}
