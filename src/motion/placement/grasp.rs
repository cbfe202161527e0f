//! Grasp frames along the handle trajectory of one joint change (the paper's Eq. (3)–(5)).

use nalgebra::{
    Isometry3, Matrix3, Point3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3,
};

use super::PlacementError;
use crate::kinematics::ik::IkTarget;
use crate::scene::motion::grasp_trajectory;
use crate::scene::{
    HandleId, JointId, SceneData, SceneModel, State, forward_kinematics, joint_axis,
};

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
    /// The same frame moved `distance` (m) out along the handle's outward normal (against the
    /// approach), orientation kept.
    pub fn out_by(&self, distance: f64) -> GraspFrame {
        let shift = -self.approach.into_inner() * distance;
        let mut frame = *self;
        frame.position += shift;
        frame.world_from_tool.translation.vector += shift;
        frame
    }

    /// The IK target for a base at `world_from_base`, in the base frame (the IK's root frame).
    pub fn ik_target(&self, world_from_base: &Isometry3<f64>, rotation: GraspRotation) -> IkTarget {
        self.ik_target_in_cone(world_from_base, rotation, 0.0)
    }

    /// [`ik_target`](Self::ik_target) with the tool axis allowed within `half_angle` (rad) of
    /// the approach direction when the rotation is free ([`IkTarget::PositionCone`]; 0: the
    /// exact axis).
    pub fn ik_target_in_cone(
        &self,
        world_from_base: &Isometry3<f64>,
        rotation: GraspRotation,
        half_angle: f64,
    ) -> IkTarget {
        let base_from_world = world_from_base.inverse();
        let position = base_from_world * self.position;
        let axis = Unit::new_normalize(base_from_world * self.approach.into_inner());
        match rotation {
            GraspRotation::Free if half_angle > 0.0 => IkTarget::PositionCone {
                position,
                axis,
                half_angle,
            },
            GraspRotation::Free => IkTarget::PositionAxis { position, axis },
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
    /// The joint's value at each waypoint: `from + (k / K)(to − from)`, `k = 0..=K` (and
    /// `from` / `to` at the straight approach / retreat waypoints, see
    /// [`JointMotion::with_approach`]).
    pub values: Vec<f64>,
    /// The grasp frame at each waypoint (`K + 1`, plus `2 · approach` straight ones).
    pub grasps: Vec<GraspFrame>,
    /// Waypoints of the straight approach before the handle trajectory and, as many, of the
    /// straight retreat after it (0: none). The handle trajectory is
    /// [`JointMotion::trajectory`].
    pub approach: usize,
    /// The angle (rad) by which every grasp frame is turned about the handle's bar axis
    /// ([`handle_bar_axis`](crate::scene::collision::handle_bar_axis)) away from the approach
    /// along the inward normal: 0 for the grasp along the normal
    /// ([`JointMotion::turned_about_bar`]).
    pub grasp_angle: f64,
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
            approach: 0,
            grasp_angle: 0.0,
        })
    }

    /// The same motion grasped from another side of a bar handle: every grasp frame's approach
    /// turned by `angle` (rad) about the bar's long axis `bar` (a unit vector in the handle's
    /// part frame, as [`handle_bar_axis`](crate::scene::collision::handle_bar_axis) gives it),
    /// carried to the world by the part's pose at that waypoint's joint value. The approach
    /// direction then stays perpendicular to the bar and turns rigidly with the part, as the
    /// normal does; the grasp points are unchanged. The full tool pose
    /// ([`GraspFrame::world_from_tool`]) of a turned grasp has +x along the bar: the fingers
    /// (which close along tool x) lie beside each other along the bar, so that neither dips
    /// towards the part's front as the approach tilts; a turned grasp is planned with that
    /// pose ([`GraspRotation::Fixed`]) whatever the settings say. Apply it before
    /// [`with_standoff`](Self::with_standoff) and [`with_approach`](Self::with_approach), so
    /// that the stand-off and the straight approach and retreat run along the turned
    /// direction. Angles add up in [`JointMotion::grasp_angle`].
    ///
    /// # Errors
    /// [`PlacementError::Scene`] if `state` is not the state the motion was made from (its
    /// size) or the motion's ids are foreign to `model`.
    pub fn turned_about_bar(
        mut self,
        model: &SceneModel,
        state: &State,
        bar: &Unit<Vector3<f64>>,
        angle: f64,
    ) -> Result<JointMotion, PlacementError> {
        if angle == 0.0 {
            return Ok(self);
        }
        let mut data = SceneData::new(model);
        let part = self.handle.part();
        for (g, v) in self.grasps.iter_mut().zip(&self.values) {
            let mut s = state.clone();
            s.set(model, self.joint, *v)?;
            forward_kinematics(model, &mut data, &s)?;
            let world_from_part =
                data.world_from_part(part)
                    .ok_or(crate::scene::Error::UnknownId {
                        kind: crate::scene::ElementKind::Part,
                        index: part.index(),
                    })?;
            let axis = Unit::new_normalize(world_from_part.rotation * bar.into_inner());
            g.approach = UnitQuaternion::from_axis_angle(&axis, angle) * g.approach;
            let z = g.approach.into_inner();
            let x = (axis.into_inner() - z * axis.dot(&z)).normalize();
            let rotation =
                Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, z.cross(&x), z]));
            g.world_from_tool.rotation = UnitQuaternion::from_rotation_matrix(&rotation);
        }
        self.grasp_angle += angle;
        Ok(self)
    }

    /// The same motion with a straight approach and retreat of `steps` waypoints each, along
    /// the handle's normal over `distance` (m): before the first grasp frame the tool comes in
    /// from `distance` out along the first frame's outward normal (the *pre-grasp* frame
    /// first), with the joint at `from`; after the last it backs out the same way along the
    /// last frame's normal to the *post-grasp* frame, with the joint at `to`. Orientations are
    /// the end frames'. `steps = 0` or `distance = 0` leaves the motion as it is; a motion
    /// that has an approach already gets a second one outside it.
    pub fn with_approach(mut self, distance: f64, steps: usize) -> JointMotion {
        if steps == 0 || distance <= 0.0 {
            return self;
        }
        let out = |g: &GraspFrame, i: usize| g.out_by(distance * i as f64 / steps as f64);
        let (first, last) = (self.grasps[0], self.grasps[self.grasps.len() - 1]);
        let before = (1..=steps).rev().map(|i| out(&first, i));
        let after = (1..=steps).map(|i| out(&last, i));
        self.grasps = before
            .chain(self.grasps.iter().copied())
            .chain(after)
            .collect();
        self.values = std::iter::repeat_n(self.from, steps)
            .chain(self.values.iter().copied())
            .chain(std::iter::repeat_n(self.to, steps))
            .collect();
        self.approach += steps;
        self
    }

    /// The index range of the handle trajectory's `K + 1` waypoints in
    /// [`JointMotion::grasps`] (and in a placement's `arm`): after the straight approach,
    /// before the straight retreat.
    pub fn trajectory(&self) -> std::ops::RangeInclusive<usize> {
        self.approach..=self.grasps.len() - 1 - self.approach
    }

    /// The same motion with every grasp point moved `standoff` (m) out along the handle's
    /// outward normal (against the approach): a point rigidly attached to the part, so the
    /// shifted trajectory is Eq. (3)–(5) of that point. The tool then stops short of the
    /// handle's grasp point, so that fingertips reaching past the tool origin stay out of the
    /// part's front.
    pub fn with_standoff(mut self, standoff: f64) -> JointMotion {
        for g in &mut self.grasps {
            *g = g.out_by(standoff);
        }
        self
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
