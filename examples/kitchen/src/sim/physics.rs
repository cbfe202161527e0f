//! The physics of the kitchen in rapier3d-f64: the static kitchen as fixed colliders, every part
//! a dynamic body on a multibody joint of its true kind, axis and limits, the robot's links as
//! kinematic bodies, and the compliant grasp that drags a part.
//!
//! **Joints.** Parts hang on rapier *multibody* joints (reduced coordinates): the joint is exact
//! by construction (no drift off the axis, no joint error to tune), its value is a generalised
//! coordinate read back directly, and teleporting is setting that coordinate. Impulse joints
//! would need stiff constraint softness to keep a door on its hinge while a 1.5 kN/m spring
//! drags it; multibodies do not. A part on the base hangs from its own fixed anchor body (one
//! small multibody per top-level part, so parts sleep independently); a nested part (the
//! dishwasher rack) hangs from its parent part's body. Each joint gets dry friction (rapier's
//! per-DoF `frictions`, MuJoCo's `frictionloss`) and viscous damping, so a part stays where it
//! is left. Gravity is on; parts whose joint chain is not gravity-neutral (a hinge about a
//! horizontal axis, a non-horizontal slide: the dishwasher door and its rack) carry a constant
//! lifting force equal to their weight — the balance springs of a dishwasher door.
//!
//! **Contacts.** Part–part and part–kitchen contacts are real, except between a part and its
//! joint parent and between colliders that already touch (within 1 mm) at the zero state,
//! which a contact filter ([`PairFilter`]) removes. The robot's colliders interact with
//! nothing (collision groups `none`): the robot's collisions are checked geometrically
//! (`RobotCollision`), so a robot that would touch something reports it instead of shoving.
//!
//! **Grasp.** An impulse joint from the gripper link (kinematic) to the part at the grasp point:
//! three linear position motors towards 0 (springs, force-based), the rotation free (a
//! compliant wrist). Its stretch is the distance between the two anchors.

use std::collections::BTreeSet;

use kinscene::scene::Collider as SceneCollider;
use kinscene::scene::{JointKind, Parent, SceneModel, Shape};
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rapier3d_f64::math::{Pose, Rotation, Vector};
use rapier3d_f64::parry::query::contact;
use rapier3d_f64::parry::shape::SharedShape;
use rapier3d_f64::prelude::{
    ActiveHooks, ColliderBuilder, ColliderHandle, GenericJointBuilder, ImpulseJointHandle,
    InteractionGroups, JointAxesMask, JointAxis, MotorModel, MultibodyJointHandle,
    PairFilterContext, PhysicsHooks, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle, SolverFlags,
};

use super::SimError;
use super::sensors::{Owner, Placed};

/// Physics time step (s): 120 Hz.
pub(super) const DT: f64 = 1.0 / 120.0;
/// Density of cabinet fronts and drawer boxes (kg/m³): melamine-faced chipboard.
const DENSITY: f64 = 650.0;
/// Wall thickness (m) of a box collider counted as a hollow shell (a drawer box, a basket): a
/// box whose solid volume exceeds its surface times this is weighed as that shell.
const SHELL_WALL: f64 = 0.012;
/// Dry friction of a slide (N) and of a hinge (N·m).
const SLIDE_FRICTION: f64 = 4.0;
const HINGE_FRICTION: f64 = 0.6;
/// Viscous damping of a slide (N·s/m) and of a hinge (N·m·s/rad).
const SLIDE_DAMPING: f64 = 10.0;
const HINGE_DAMPING: f64 = 0.8;
/// Colliders closer than this (m) at the zero state never get contacts.
const TOUCH_DISTANCE: f64 = 1e-3;
/// A joint axis counts as vertical (a hinge) or horizontal (a slide) within this cosine.
const NEUTRAL_COSINE: f64 = 1e-3;
/// The grasp spring: stiffness (N/m) and damping (N·s/m) per linear axis.
const GRASP_STIFFNESS: f64 = 1500.0;
const GRASP_DAMPING: f64 = 120.0;
/// A contact between the moving part and something else counts as a collision when its
/// deepest point penetrates more than this (m) ...
const PENETRATION: f64 = 2e-3;
/// ... or the contact pushes with more than this force (N).
const CONTACT_FORCE: f64 = 5.0;

/// One part's body and joint.
pub(super) struct PartBody {
    /// The dynamic body (its pose is the part frame).
    pub body: RigidBodyHandle,
    joint: MultibodyJointHandle,
    kind: JointKind,
    /// The part's colliders.
    pub colliders: Vec<ColliderHandle>,
}

/// The grasp joint.
pub(super) struct GraspJoint {
    handle: ImpulseJointHandle,
    /// Index of the grasped part.
    pub part: usize,
    /// Anchor on the gripper link, in its frame.
    anchor_link: Vector,
    /// Anchor on the part, in the part frame.
    pub anchor_part: Point3<f64>,
    /// The tool frame in the part frame at the grasp (the rigid grasp's orientation).
    pub part_from_tool: Isometry3<f64>,
}

/// An unordered pair of colliders, as their (index, generation) parts, smaller first.
type PairKey = ((u32, u32), (u32, u32));

/// Pairs of colliders that never get contacts.
pub(super) struct PairFilter {
    excluded: BTreeSet<PairKey>,
}

fn pair_key(a: ColliderHandle, b: ColliderHandle) -> PairKey {
    let (a, b) = (a.into_raw_parts(), b.into_raw_parts());
    if a <= b { (a, b) } else { (b, a) }
}

impl PhysicsHooks for PairFilter {
    fn filter_contact_pair(&self, context: &PairFilterContext) -> Option<SolverFlags> {
        if self
            .excluded
            .contains(&pair_key(context.collider1, context.collider2))
        {
            None
        } else {
            Some(SolverFlags::COMPUTE_RIGID_IMPULSES)
        }
    }
}

/// A contact of the moving part found by [`Physics::moving_contact`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Hit {
    /// The moving part (index) whose collider is in contact.
    pub part: usize,
    /// What it touches.
    pub other: Owner,
    /// Index of the base shape when `other` is the kitchen.
    pub base_shape: Option<usize>,
    /// Penetration depth (m, positive inside).
    pub depth: f64,
    /// Contact force (N).
    pub force: f64,
}

/// The rapier world and the handles of everything in it.
pub(super) struct Physics {
    world: PhysicsWorld,
    filter: PairFilter,
    /// Per part (model order).
    pub parts: Vec<PartBody>,
    /// Who owns each collider, in insertion order; for base shapes also the shape index.
    owners: Vec<(ColliderHandle, Owner, Option<usize>)>,
    /// Per robot link (model order), its kinematic body.
    pub links: Vec<RigidBodyHandle>,
    /// The current grasp, if any.
    pub grasp: Option<GraspJoint>,
}

/// nalgebra → glam pose.
pub(super) fn to_pose(iso: &Isometry3<f64>) -> Pose {
    let t = iso.translation.vector;
    let q = iso.rotation.quaternion();
    Pose::from_parts(
        Vector::new(t.x, t.y, t.z),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

/// glam → nalgebra pose.
pub(super) fn from_pose(pose: &Pose) -> Isometry3<f64> {
    let t = pose.translation;
    let r = pose.rotation;
    Isometry3::from_parts(
        Translation3::new(t.x, t.y, t.z),
        UnitQuaternion::new_normalize(Quaternion::new(r.w, r.x, r.y, r.z)),
    )
}

fn to_vector(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn to_point(v: Vector) -> Point3<f64> {
    Point3::new(v.x, v.y, v.z)
}

/// A scene shape as a parry shape and the pose of parry's frame in the shape frame (the
/// library's conversion, the shapes its collision checks use).
fn parry_shape(shape: &Shape, what: &str) -> Result<(SharedShape, Isometry3<f64>), SimError> {
    kinscene::scene::collision::parry_shape(shape)
        .map_err(|e| SimError::Setup(format!("{what}: {e}")))
}

/// The density (kg/m³) that gives a collider a furniture-like mass: solid chipboard for thin
/// slabs, a hollow shell of [`SHELL_WALL`] for bulky boxes (drawer boxes, the rack).
fn density(shape: &Shape) -> f64 {
    match shape {
        Shape::Cuboid { half_extents: h } => {
            let volume = 8.0 * h.x * h.y * h.z;
            let area = 8.0 * (h.x * h.y + h.y * h.z + h.x * h.z);
            DENSITY * (area * SHELL_WALL / volume).min(1.0)
        }
        _ => DENSITY,
    }
}

impl Physics {
    /// Builds the world from the ground truth at its zero state, and one kinematic body per
    /// robot link with the link's colliders (`links`: the robot's links, each a list of
    /// colliders in the link frame).
    pub(super) fn new(
        truth: &SceneModel,
        robot_links: &[Vec<SceneCollider>],
    ) -> Result<Physics, SimError> {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -9.81);
        world.integration_parameters.dt = DT;
        let mut owners = Vec::new();

        // The static kitchen.
        let kitchen = world.insert_body(RigidBodyBuilder::fixed());
        for (k, s) in truth.base().shapes.iter().enumerate() {
            let (shape, shape_from_parry) = parry_shape(&s.shape, &s.name)?;
            let collider = ColliderBuilder::new(shape)
                .position(to_pose(&(s.world_from_shape * shape_from_parry)))
                .active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS);
            let handle = world.insert_collider(collider, Some(kitchen));
            owners.push((handle, Owner::Base, Some(k)));
        }

        // The parts, in model order (parents first), at value 0 of every joint.
        let world_from_parts = truth
            .world_from_parts(&truth.zero_state())
            .map_err(|e| SimError::Setup(format!("forward kinematics of the truth: {e}")))?;
        let mut parts: Vec<PartBody> = Vec::with_capacity(truth.parts().len());
        for (k, part) in truth.parts().iter().enumerate() {
            let joint = &truth.joints()[k];
            let body =
                world.insert_body(RigidBodyBuilder::dynamic().pose(to_pose(&world_from_parts[k])));
            let mut colliders = Vec::with_capacity(part.colliders().len());
            for (c, collider) in part.colliders().iter().enumerate() {
                let what = format!("part {} collider {c}", part.name());
                let (shape, shape_from_parry) = parry_shape(&collider.shape, &what)?;
                let builder = ColliderBuilder::new(shape)
                    .position(to_pose(&(collider.part_from_shape * shape_from_parry)))
                    .density(density(&collider.shape))
                    .friction(0.3)
                    .active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS);
                let handle = world.insert_collider(builder, Some(body));
                colliders.push(handle);
                owners.push((handle, Owner::Part(k), None));
            }
            let parent = match part.parent() {
                Parent::Base => world.insert_body(RigidBodyBuilder::fixed()),
                Parent::Part(p) => parts[p.index()].body,
            };
            let axis = to_vector(&joint.axis);
            let frame = Pose::from_rotation(Rotation::from_rotation_arc(Vector::X, axis));
            let (locked, free) = match joint.kind {
                JointKind::Revolute => (JointAxesMask::LOCKED_REVOLUTE_AXES, JointAxis::AngX),
                JointKind::Prismatic => (JointAxesMask::LOCKED_PRISMATIC_AXES, JointAxis::LinX),
            };
            let data = GenericJointBuilder::new(locked)
                .local_frame1(to_pose(&joint.parent_from_joint) * frame)
                .local_frame2(frame)
                .limits(free, [joint.limits.lower, joint.limits.upper])
                .contacts_enabled(false)
                .build();
            let handle = world
                .insert_multibody_joint(parent, body, data)
                .ok_or_else(|| {
                    SimError::Setup(format!("joint {}: invalid multibody", joint.name))
                })?;
            parts.push(PartBody {
                body,
                joint: handle,
                kind: joint.kind,
                colliders,
            });
        }

        // Friction and damping per joint (after every joint is in: the DoF indices are final).
        for p in &parts {
            let (friction, damping) = match p.kind {
                JointKind::Revolute => (HINGE_FRICTION, HINGE_DAMPING),
                JointKind::Prismatic => (SLIDE_FRICTION, SLIDE_DAMPING),
            };
            let (mb, link) = world
                .multibody_joints
                .get_mut(p.joint)
                .ok_or_else(|| SimError::Setup("a multibody joint vanished".into()))?;
            let dof = mb
                .link(link)
                .map(|l| l.assembly_id())
                .ok_or_else(|| SimError::Setup("a multibody link vanished".into()))?;
            mb.frictions_mut()[dof] = friction;
            mb.damping_mut()[dof] = damping;
        }

        // Balance springs where gravity would move a joint.
        let neutral: Vec<bool> = truth
            .joints()
            .iter()
            .zip(&world_from_parts)
            .zip(truth.parts())
            .map(|((j, _), part)| {
                let world_from_parent = match part.parent() {
                    Parent::Base => Isometry3::identity(),
                    Parent::Part(p) => world_from_parts[p.index()],
                };
                let u = world_from_parent * j.parent_from_joint * j.axis;
                match j.kind {
                    JointKind::Revolute => u.z.abs() >= 1.0 - NEUTRAL_COSINE,
                    JointKind::Prismatic => u.z.abs() <= NEUTRAL_COSINE,
                }
            })
            .collect();
        for (k, part) in truth.parts().iter().enumerate() {
            let mut balanced = !neutral[k];
            let mut up = part.parent();
            while let Parent::Part(p) = up {
                balanced |= !neutral[p.index()];
                up = truth.parts()[p.index()].parent();
            }
            if balanced {
                let colliders = &world.colliders;
                if let Some(rb) = world.bodies.get_mut(parts[k].body) {
                    rb.recompute_mass_properties_from_colliders(colliders);
                    let weight = rb.mass() * 9.81;
                    rb.add_force(Vector::new(0.0, 0.0, weight), true);
                }
            }
        }

        // The robot's links: kinematic, interacting with nothing.
        let mut links = Vec::with_capacity(robot_links.len());
        for (l, colliders) in robot_links.iter().enumerate() {
            let body = world.insert_body(RigidBodyBuilder::kinematic_position_based());
            for (c, collider) in colliders.iter().enumerate() {
                let what = format!("robot link {l} collider {c}");
                let (shape, shape_from_parry) = parry_shape(&collider.shape, &what)?;
                let builder = ColliderBuilder::new(shape)
                    .position(to_pose(&(collider.part_from_shape * shape_from_parry)))
                    .collision_groups(InteractionGroups::none())
                    .solver_groups(InteractionGroups::none());
                let handle = world.insert_collider(builder, Some(body));
                owners.push((handle, Owner::Robot, None));
            }
            links.push(body);
        }

        let mut physics = Physics {
            world,
            filter: PairFilter {
                excluded: BTreeSet::new(),
            },
            parts,
            owners,
            links,
            grasp: None,
        };
        physics.filter.excluded = physics.excluded_pairs(truth)?;
        physics.set_values(truth.zero_state().as_slice());
        Ok(physics)
    }

    /// The collider pairs without contacts: a part and its joint parent, and every pair of a
    /// part collider and another part's or the kitchen's collider that touch at the current
    /// (zero) state.
    fn excluded_pairs(&self, truth: &SceneModel) -> Result<BTreeSet<PairKey>, SimError> {
        let mut out = BTreeSet::new();
        let placed: Vec<(ColliderHandle, Owner, Pose, SharedShape)> = self
            .owners
            .iter()
            .filter(|(_, owner, _)| *owner != Owner::Robot)
            .filter_map(|(h, owner, _)| {
                let c = self.world.colliders.get(*h)?;
                Some((
                    *h,
                    *owner,
                    self.collider_pose(*h)?,
                    c.shared_shape().clone(),
                ))
            })
            .collect();
        for (i, (ha, oa, pa, sa)) in placed.iter().enumerate() {
            for (hb, ob, pb, sb) in &placed[i + 1..] {
                let (a, b) = match (oa, ob) {
                    (Owner::Part(a), Owner::Part(b)) if a == b => continue,
                    (Owner::Part(a), Owner::Part(b)) => (Some(*a), Some(*b)),
                    (Owner::Part(a), _) => (Some(*a), None),
                    (_, Owner::Part(b)) => (None, Some(*b)),
                    _ => continue,
                };
                let parent_of = |x: Option<usize>| -> Option<usize> {
                    match truth.parts().get(x?)?.parent() {
                        Parent::Part(p) => Some(p.index()),
                        Parent::Base => None,
                    }
                };
                let family =
                    (a.is_some() && b.is_some()) && (parent_of(a) == b || parent_of(b) == a);
                let touching = || -> Result<bool, SimError> {
                    let d = rapier3d_f64::parry::query::distance(pa, sa.as_ref(), pb, sb.as_ref())
                        .map_err(|_| SimError::Setup("unsupported distance query".into()))?;
                    Ok(d.distance <= TOUCH_DISTANCE)
                };
                if family || touching()? {
                    out.insert(pair_key(*ha, *hb));
                }
            }
        }
        Ok(out)
    }

    /// The world pose of a collider (from its body's current pose, so it is up to date after a
    /// teleport even before the next step).
    fn collider_pose(&self, handle: ColliderHandle) -> Option<Pose> {
        let c = self.world.colliders.get(handle)?;
        match (c.parent(), c.position_wrt_parent()) {
            (Some(body), Some(local)) => Some(*self.world.bodies.get(body)?.position() * *local),
            _ => Some(*c.position()),
        }
    }

    /// Every collider now, with its owner.
    pub(super) fn placed(&self) -> Vec<Placed> {
        self.owners
            .iter()
            .filter_map(|(h, owner, _)| {
                let c = self.world.colliders.get(*h)?;
                Some(Placed {
                    shape: c.shared_shape().clone(),
                    pose: self.collider_pose(*h)?,
                    owner: *owner,
                })
            })
            .collect()
    }

    /// The joint values (one per part, model order): the multibody coordinates.
    pub(super) fn values(&self) -> Vec<f64> {
        (0..self.parts.len()).map(|k| self.value(k)).collect()
    }

    /// The joint value of part `k` (NaN for a part the physics lost or an index out of range).
    pub(super) fn value(&self, k: usize) -> f64 {
        let Some(p) = self.parts.get(k) else {
            return f64::NAN;
        };
        self.world
            .multibody_joints
            .get(p.joint)
            .and_then(|(mb, link)| mb.link(link))
            .map(|l| {
                let coords = l.joint.coords();
                match p.kind {
                    JointKind::Revolute => coords[3],
                    JointKind::Prismatic => coords[0],
                }
            })
            .unwrap_or(f64::NAN)
    }

    /// The world pose of part `k` (its frame).
    pub(super) fn world_from_part(&self, k: usize) -> Option<Isometry3<f64>> {
        let p = self.parts.get(k)?;
        Some(from_pose(self.world.bodies.get(p.body)?.position()))
    }

    /// Teleports the parts to joint values `q` (model order), at rest.
    pub(super) fn set_values(&mut self, q: &[f64]) {
        let current = self.values();
        for (k, p) in self.parts.iter().enumerate() {
            let (Some(target), Some(now)) = (q.get(k), current.get(k)) else {
                continue;
            };
            let Some((mb, link)) = self.world.multibody_joints.get_mut(p.joint) else {
                continue;
            };
            let Some(dof) = mb.link(link).map(|l| l.assembly_id()) else {
                continue;
            };
            let mut disp = vec![0.0; mb.ndofs()];
            disp[dof] = target - now;
            mb.apply_displacements(&disp);
        }
        for p in &self.parts {
            if let Some((mb, _)) = self.world.multibody_joints.get_mut(p.joint) {
                mb.generalized_velocity_mut().fill(0.0);
                mb.forward_kinematics(&self.world.bodies, false);
                mb.update_rigid_bodies(&mut self.world.bodies, true);
            }
        }
        for p in &self.parts {
            let Some(rb) = self.world.bodies.get_mut(p.body) else {
                continue;
            };
            rb.set_linvel(Vector::ZERO, true);
            rb.set_angvel(Vector::ZERO, true);
            // The multibody moved the body without flagging its colliders: a sleeping part's
            // colliders stayed where they were, and the next step's narrow phase found
            // contacts at the old place (a drawer teleported shut still "stood out" 16 cm
            // and kicked a door). Place them and flag them modified.
            let world_from_body = *rb.position();
            for &c in &p.colliders {
                if let Some(co) = self.world.colliders.get_mut(c) {
                    if let Some(local) = co.position_wrt_parent().copied() {
                        co.set_position(world_from_body * local);
                    }
                }
            }
        }
    }

    /// Places the robot's link bodies at `poses` now (teleport).
    pub(super) fn place_links(&mut self, poses: &[Isometry3<f64>]) {
        for (body, pose) in self.links.iter().zip(poses) {
            if let Some(rb) = self.world.bodies.get_mut(*body) {
                rb.set_position(to_pose(pose), false);
            }
        }
    }

    /// Sets where the robot's link bodies are at the end of the next step.
    pub(super) fn move_links(&mut self, poses: &[Isometry3<f64>]) {
        for (body, pose) in self.links.iter().zip(poses) {
            if let Some(rb) = self.world.bodies.get_mut(*body) {
                rb.set_next_kinematic_position(to_pose(pose));
            }
        }
    }

    /// One physics step of [`DT`].
    pub(super) fn step(&mut self) {
        self.world.step_with_events(&self.filter, &());
    }

    /// Attaches part `part` to the gripper link body (`link`) with the grasp spring at the world
    /// point `at`, the tool at `world_from_tool`.
    pub(super) fn attach(
        &mut self,
        link: usize,
        part: usize,
        at: &Point3<f64>,
        world_from_tool: &Isometry3<f64>,
    ) -> Result<(), SimError> {
        self.detach();
        let (Some(&gripper), Some(p)) = (self.links.get(link), self.parts.get(part)) else {
            return Err(SimError::Setup("grasp: unknown link or part".into()));
        };
        let body = p.body;
        let world_from_link = self
            .world
            .bodies
            .get(gripper)
            .map(|rb| from_pose(rb.position()))
            .ok_or_else(|| SimError::Setup("grasp: no gripper body".into()))?;
        let world_from_part = self
            .world_from_part(part)
            .ok_or_else(|| SimError::Setup("grasp: no part body".into()))?;
        let anchor_link = world_from_link.inverse_transform_point(at);
        let anchor_part = world_from_part.inverse_transform_point(at);
        let mut builder = GenericJointBuilder::new(JointAxesMask::empty())
            .local_anchor1(to_vector(&anchor_link.coords))
            .local_anchor2(to_vector(&anchor_part.coords))
            .contacts_enabled(false);
        for axis in [JointAxis::LinX, JointAxis::LinY, JointAxis::LinZ] {
            builder = builder
                .motor_position(axis, 0.0, GRASP_STIFFNESS, GRASP_DAMPING)
                .motor_model(axis, MotorModel::ForceBased);
        }
        let handle = self
            .world
            .insert_impulse_joint(gripper, body, builder.build());
        self.grasp = Some(GraspJoint {
            handle,
            part,
            anchor_link: to_vector(&anchor_link.coords),
            anchor_part,
            part_from_tool: world_from_part.inverse() * world_from_tool,
        });
        Ok(())
    }

    /// Removes the grasp joint (opens the gripper).
    pub(super) fn detach(&mut self) {
        if let Some(g) = self.grasp.take() {
            self.world.remove_impulse_joint(g.handle);
        }
    }

    /// The grasp point on the part now (world), if something is grasped.
    pub(super) fn grasp_point(&self) -> Option<Point3<f64>> {
        let g = self.grasp.as_ref()?;
        Some(self.world_from_part(g.part)? * g.anchor_part)
    }

    /// The spring's stretch (m): distance between the gripper's and the part's anchor.
    pub(super) fn stretch(&self, link: usize) -> Option<f64> {
        let g = self.grasp.as_ref()?;
        let rb = self.world.bodies.get(*self.links.get(link)?)?;
        let on_gripper = to_point(rb.position().transform_point(g.anchor_link));
        Some((on_gripper - self.grasp_point()?).norm())
    }

    /// The first contact (in collider order) of a collider of the parts `moving` with a
    /// collider outside them that penetrates deeper than [`PENETRATION`] or pushes harder
    /// than [`CONTACT_FORCE`] in the last step.
    pub(super) fn moving_contact(&self, moving: &[usize]) -> Option<Hit> {
        let owner_of = |h: ColliderHandle| {
            self.owners
                .iter()
                .find(|(c, _, _)| *c == h)
                .map(|(_, o, s)| (*o, *s))
        };
        for &k in moving {
            let Some(p) = self.parts.get(k) else { continue };
            for &c in &p.colliders {
                for pair in self.world.narrow_phase.contact_pairs_with(c) {
                    if !pair.has_any_active_contact() {
                        continue;
                    }
                    let other = if pair.collider1 == c {
                        pair.collider2
                    } else {
                        pair.collider1
                    };
                    let Some((owner, shape)) = owner_of(other) else {
                        continue;
                    };
                    if matches!(owner, Owner::Part(o) if moving.contains(&o)) {
                        continue;
                    }
                    // A manifold's depth may be stale (rapier recycles a pair's contacts while
                    // its relative pose drifts less than 5 cm), so the depth is parry's exact
                    // contact query at the colliders' poses now.
                    let depth = self.exact_depth(c, other);
                    let force = pair.total_impulse_magnitude() / DT;
                    if depth > PENETRATION || force > CONTACT_FORCE {
                        return Some(Hit {
                            part: k,
                            other: owner,
                            base_shape: shape,
                            depth,
                            force,
                        });
                    }
                }
            }
        }
        None
    }

    /// The largest distance (m) between a part collider's pose as the engine holds it (the
    /// narrow phase's) and its body's pose times its offset (tests).
    #[cfg(test)]
    pub(super) fn collider_lag(&self) -> f64 {
        let mut worst: f64 = 0.0;
        for p in &self.parts {
            for &c in &p.colliders {
                let (Some(co), Some(from_body)) =
                    (self.world.colliders.get(c), self.collider_pose(c))
                else {
                    continue;
                };
                worst = worst.max((co.position().translation - from_body.translation).length());
            }
        }
        worst
    }

    /// Penetration depth (m, 0 if apart) of colliders `a` and `b` at their poses now (parry's
    /// exact contact query).
    fn exact_depth(&self, a: ColliderHandle, b: ColliderHandle) -> f64 {
        let (Some(ca), Some(cb)) = (self.world.colliders.get(a), self.world.colliders.get(b))
        else {
            return 0.0;
        };
        contact(ca.position(), ca.shape(), cb.position(), cb.shape(), 0.0)
            .ok()
            .flatten()
            .map_or(0.0, |c| (-c.dist).max(0.0))
    }
}
