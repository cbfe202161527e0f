//! An independent re-checker of motion plans under the grasp contact rule, and tests that use it.
//!
//! The rule: only the gripper's contact shapes (the collision elements `finger_left` and
//! `finger_right` of link `robotiq_2f_140`) may touch the grasped part (the moved joint's part
//! and its descendants), and only from the pre-grasp configuration through the manipulation to
//! the post-grasp configuration. Every other robot shape never touches anything (base map
//! shapes, any part, the grasped part included), in any phase; the fingers never touch
//! anything else, and touch nothing at all in the free (OMPL) phases. While the fingers may
//! touch the grasped part, they must not penetrate its *front* (its collision shapes that do not
//! strictly contain the handle's grasp point) by more than [`MAX_FRONT_DEPTH`]. The robot never
//! touches itself: shapes on links that move relative to each other touch only where the
//! robot's SRDF has a `disable_collisions` element for their links (read here by text search).
//!
//! Nothing here shares code with the planner's collision checking: the robot's collision
//! geometry is parsed from the URDF with urdf-rs and built as parry shapes by this file (fixed
//! joints composed here), the scene's shapes are converted to parry here, and distances and
//! penetration depths come from `parry3d_f64::query` directly. Two lower layers are used as
//! they are, each tested on its own: Pinocchio's forward kinematics of the arm (through the
//! planner's Pinocchio model of the robot, tests/kinematics) and the scene tree's forward
//! kinematics (`kinscene::scene::forward_kinematics`, tests/scene).

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use kinscene::kinematics::pinocchio::{
    Data, JointIndex, Model, forward_kinematics as arm_fk, joint_placement,
};
use kinscene::motion::timing::TimedPath;
use kinscene::planner::{HierarchicalPlanner, MotionOutcome, MotionPlan, StepMotion};
use kinscene::scene::{
    Handle, Joint, Limits, PartSpec, SceneData, SceneModel, SceneModelBuilder, Shape, State,
    forward_kinematics as scene_fk,
};
use kinscene::task::{Problem, Termination};
use nalgebra::{DVector, Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::query;
use parry3d_f64::shape::{Ball, Capsule, ConvexPolyhedron, Cuboid, Cylinder, Shape as ParryShape};

/// Largest allowed penetration (m) of a finger into the grasped part's front.
pub(super) const MAX_FRONT_DEPTH: f64 = 1e-3;
/// Largest arm joint change (rad or m) between two samples.
const ARM_STEP: f64 = 0.005;
/// Largest base translation (m) between two samples.
const BASE_STEP: f64 = 0.005;
/// Largest base yaw change (rad) between two samples.
const YAW_STEP: f64 = 0.005;
/// Largest change of the moved scene joint (rad or m) between two manipulation samples.
const SCENE_STEP: f64 = 0.005;
/// Distances below this (m) count as touching: parry returns 0 for touching or overlapping
/// shapes; the tolerance only keeps round-off from hiding an exact touch.
const TOUCH: f64 = 1e-9;
/// The robot's URDF, read by this file (not through `RobotModel`).
const ROBOT_URDF: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/robots/kinova_gen3_mobile.urdf"
);
/// The robot's SRDF, read by this file (its `disable_collisions` pairs, by text search).
const ROBOT_SRDF: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/robots/kinova_gen3_mobile.srdf"
);
/// The link and collision names of the gripper's contact shapes.
const FINGER_LINK: &str = "robotiq_2f_140";
const FINGERS: [&str; 2] = ["finger_left", "finger_right"];

// ---------------------------------------------------------------------------------------------
// Verdicts

/// What a sample did wrong.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Breach {
    /// A robot shape that must not touch the body does (parry distance, m, below [`TOUCH`]).
    Touch {
        /// The distance (m).
        distance: f64,
    },
    /// A finger penetrates the grasped part's front by more than [`MAX_FRONT_DEPTH`].
    FrontPenetration {
        /// The penetration depth (m).
        depth: f64,
    },
    /// Two robot shapes closer than [`RobotGeometry::grasp_self_clearance`] while grasping.
    SelfClearance {
        /// The distance (m).
        distance: f64,
    },
}

/// The phases of a step, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Phase {
    /// Driving, arm stowed (free).
    Base,
    /// Stowed to the grasp: free up to the pre-grasp configuration, contact from it on.
    Approach,
    /// Along the handle trajectory (contact).
    Manipulation,
    /// Back to stowed: contact up to the post-grasp configuration, free after it.
    Retreat,
}

impl fmt::Display for Phase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Phase::Base => "base",
            Phase::Approach => "approach",
            Phase::Manipulation => "manipulation",
            Phase::Retreat => "retreat",
        })
    }
}

/// The first sample of a plan that breaks the contact rule.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Violation {
    /// Index of the step in the plan.
    pub step: usize,
    /// The phase.
    pub phase: Phase,
    /// Position along the phase's waypoints: waypoint index plus the fraction of the segment.
    pub at: f64,
    /// Whether the sample lies in the contact part of the step (pre-grasp to post-grasp).
    pub contact_phase: bool,
    /// The sampled configuration: base `[x, y, yaw]` in the base phase, else the arm's joints.
    pub config: Vec<f64>,
    /// The moved scene joint's value at the sample.
    pub scene_value: f64,
    /// The robot shape, `link/collision` (unnamed collisions as `link/#index`).
    pub robot_shape: String,
    /// The body touched: a base map shape's name or a part's name.
    pub body: String,
    /// What happened.
    pub breach: Breach,
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let config: Vec<String> = self.config.iter().map(|v| format!("{v:.4}")).collect();
        write!(
            f,
            "step {} {} at waypoint {:.3} ({} part; config [{}], scene joint at {:.4}): ",
            self.step,
            self.phase,
            self.at,
            if self.contact_phase {
                "contact"
            } else {
                "free"
            },
            config.join(", "),
            self.scene_value,
        )?;
        match self.breach {
            Breach::Touch { distance } => write!(
                f,
                "robot shape {} touches {} (distance {distance:.3e} m)",
                self.robot_shape, self.body
            ),
            Breach::FrontPenetration { depth } => write!(
                f,
                "finger {} penetrates the front of {} by {:.2} mm (at most {:.2} mm allowed)",
                self.robot_shape,
                self.body,
                depth * 1e3,
                MAX_FRONT_DEPTH * 1e3
            ),
            Breach::SelfClearance { distance } => write!(
                f,
                "robot shapes {} and {} are {:.2} mm apart while grasping (closer than the \
                 robot's grasp_self_clearance)",
                self.robot_shape,
                self.body,
                distance * 1e3,
            ),
        }
    }
}

/// What a passing plan looked like.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Report {
    /// Samples checked, all phases of all steps.
    pub samples: usize,
    /// Of them, samples in contact parts.
    pub contact_samples: usize,
    /// Smallest distance (m) between a robot shape and a body it must not touch.
    pub min_clearance: f64,
    /// Where: `robot shape vs body (step, phase)`.
    pub min_clearance_between: String,
    /// Deepest penetration (m) of a finger into the grasped part's front (0 if none).
    pub max_front_depth: f64,
    /// Smallest distance (m) between two robot shapes that must not touch, exact where it is
    /// below [`SELF_EXACT`] (that value otherwise), in the phases under the grasp rule
    /// (pre-grasp to post-grasp) and in the free ones.
    pub min_self_clearance: [f64; 2],
    /// Where, for each: `shape vs shape (step, phase)`.
    pub min_self_clearance_between: [String; 2],
}

/// The self-distance below which [`Report::min_self_clearance`] is exact (m).
const SELF_EXACT: f64 = 0.05;

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} samples ({} in contact parts); min clearance {:.4} m ({}); deepest finger in a \
             front {:.2} mm; min self-clearance grasping {:.4} m ({}), free {:.4} m ({})",
            self.samples,
            self.contact_samples,
            self.min_clearance,
            self.min_clearance_between,
            self.max_front_depth * 1e3,
            self.min_self_clearance[0],
            self.min_self_clearance_between[0],
            self.min_self_clearance[1],
            self.min_self_clearance_between[1],
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Geometry, converted to parry by this file

/// A nalgebra isometry as a parry pose.
fn to_pose(iso: &Isometry3<f64>) -> Pose {
    let q = iso.rotation.quaternion();
    let t = iso.translation.vector;
    Pose::from_parts(
        Vector::new(t.x, t.y, t.z),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

/// parry's distance of two placed shapes; two boxes by parry's GJK, as the crate computes
/// them, since parry 0.31's box–box distance can be far off near contact (the crate's
/// `two_boxes_near_contact_get_gjk_s_distance` has a pair where it gives 0.158 m for 2.5e-5 m).
fn distance(pa: &Pose, a: &dyn ParryShape, pb: &Pose, b: &dyn ParryShape) -> f64 {
    match (a.as_cuboid(), b.as_cuboid()) {
        (Some(ca), Some(cb)) => {
            query::details::distance_support_map_support_map(&pa.inv_mul(pb), ca, cb)
        }
        _ => {
            query::distance(pa, a, pb, b)
                .expect("parry supports the pair")
                .distance
        }
    }
}

fn to_vector(p: &Point3<f64>) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// A parry shape with the pose of the parry frame in the frame of the shape's description
/// (parry's cylinder runs along y, URDF's and the scene's along z) and a bounding sphere in that
/// description frame.
struct Solid {
    shape: Box<dyn ParryShape>,
    /// Description frame from parry frame.
    fix: Isometry3<f64>,
    center: Point3<f64>,
    radius: f64,
}

impl Solid {
    fn new(shape: Box<dyn ParryShape>, fix: Isometry3<f64>) -> Solid {
        let s = shape.compute_local_bounding_sphere();
        let c = s.center();
        Solid {
            fix,
            center: fix * Point3::new(c.x, c.y, c.z),
            radius: s.radius(),
            shape,
        }
    }

    fn cuboid(half: Vector3<f64>) -> Solid {
        Solid::new(
            Box::new(Cuboid::new(Vector::new(half.x, half.y, half.z))),
            Isometry3::identity(),
        )
    }

    /// A cylinder along z.
    fn cylinder(radius: f64, length: f64) -> Solid {
        // Rotating parry's y axis onto z: a quarter turn about x.
        let fix = Isometry3::rotation(Vector3::x() * std::f64::consts::FRAC_PI_2);
        Solid::new(Box::new(Cylinder::new(length / 2.0, radius)), fix)
    }

    /// A capsule along z whose central segment is `length` long.
    fn capsule(radius: f64, length: f64) -> Solid {
        Solid::new(
            Box::new(Capsule::new_z(length / 2.0, radius)),
            Isometry3::identity(),
        )
    }

    fn ball(radius: f64) -> Solid {
        Solid::new(Box::new(Ball::new(radius)), Isometry3::identity())
    }

    /// The scene's shapes.
    fn of_scene(shape: &Shape) -> Solid {
        match shape {
            Shape::Cuboid { half_extents } => Solid::cuboid(*half_extents),
            Shape::Cylinder { radius, length } => Solid::cylinder(*radius, *length),
            Shape::Sphere { radius } => Solid::ball(*radius),
            Shape::Capsule { radius, length } => Solid::capsule(*radius, *length),
            Shape::ConvexMesh { vertices, .. } => {
                let points: Vec<Vector> = vertices.iter().map(to_vector).collect();
                let hull = ConvexPolyhedron::from_convex_hull(&points)
                    .expect("a scene mesh spans a volume");
                Solid::new(Box::new(hull), Isometry3::identity())
            }
            other => panic!("the re-checker does not know the scene shape {other:?}"),
        }
    }
}

/// What a robot shape moves with.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Anchor {
    /// The mobile base (the URDF root link and everything fixed to it).
    Base,
    /// The child link of this Pinocchio joint (the link's frame is the joint's frame).
    Joint(JointIndex),
}

/// One collision element of the robot.
struct RobotShape {
    name: String,
    /// The URDF link carrying it.
    link: String,
    contact: bool,
    anchor: Anchor,
    anchor_from_shape: Isometry3<f64>,
    solid: Solid,
}

/// The URDF's `<origin>`: translation, then fixed-axis roll-pitch-yaw
/// `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
fn urdf_pose(pose: &urdf_rs::Pose) -> Isometry3<f64> {
    let [x, y, z] = pose.xyz.0;
    let [roll, pitch, yaw] = pose.rpy.0;
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(roll, pitch, yaw),
    )
}

/// Where this file reads a robot's collision geometry: its URDF, the package roots of its mesh
/// URIs, the movable joints the planner holds at a value (composed here as fixed joints at
/// that value), and which collision elements are the gripper's contact shapes.
pub(super) struct RobotGeometry {
    /// The URDF file.
    pub urdf: PathBuf,
    /// `package://NAME/rest` resolves to `packages[NAME]/rest`.
    pub packages: Vec<(String, PathBuf)>,
    /// Movable joints that are not arm joints, with their values (rad or m).
    pub frozen: Vec<(String, f64)>,
    /// Whether the collision element `label` (its name, else `#index`) of `link` is contact
    /// geometry.
    pub contact: fn(&str, &str) -> bool,
    /// The robot's SRDF: its `disable_collisions` link pairs are the pairs that may touch;
    /// every other pair of shapes on links that move relative to each other must not. `None`:
    /// self-contact is not re-checked.
    pub srdf: Option<PathBuf>,
    /// The least distance (m) two robot shapes that must not touch keep while grasping (the
    /// straight approach from the pre-grasp, the manipulation, the straight retreat to the
    /// post-grasp); 0: only touching is a breach.
    pub grasp_self_clearance: f64,
}

impl RobotGeometry {
    /// The shipped robot, `robots/kinova_gen3_mobile.urdf`: primitives only, nothing frozen,
    /// the fingers of the Robotiq gripper as the contact shapes.
    pub(super) fn gen3() -> RobotGeometry {
        RobotGeometry {
            urdf: PathBuf::from(ROBOT_URDF),
            packages: Vec::new(),
            frozen: Vec::new(),
            contact: |link, label| link == FINGER_LINK && FINGERS.contains(&label),
            srdf: Some(PathBuf::from(ROBOT_SRDF)),
            // The planner's checked states keep half the placement's self-margin (5 mm at
            // most, capped by half the Gen3 stow's 20.9 mm): 2.5 mm. This file samples
            // more densely than the planner checks, so it may find a little less between
            // them; 2 mm is what it asks.
            grasp_self_clearance: 0.002,
        }
    }

    /// The file a mesh URI names.
    fn mesh_path(&self, uri: &str) -> PathBuf {
        if let Some(rest) = uri.strip_prefix("package://") {
            let (name, rest) = rest.split_once('/').expect("package://NAME/path");
            let root = self
                .packages
                .iter()
                .find(|(n, _)| n == name)
                .unwrap_or_else(|| panic!("no package path for {name:?}"));
            return root.1.join(rest);
        }
        let path = Path::new(uri.strip_prefix("file://").unwrap_or(uri));
        match self.urdf.parent() {
            Some(dir) if path.is_relative() => dir.join(path),
            _ => path.to_path_buf(),
        }
    }

    /// One convex hull per sub-mesh of the mesh file `uri` (mesh-loader reads it; parry builds
    /// the hulls), scaled per axis.
    fn mesh_hulls(&self, uri: &str, scale: [f64; 3]) -> Vec<Solid> {
        let path = self.mesh_path(uri);
        let scene = mesh_loader::Loader::default()
            .load(&path)
            .unwrap_or_else(|e| panic!("mesh {path:?}: {e}"));
        scene
            .meshes
            .iter()
            .filter(|m| m.vertices.len() >= 4)
            .filter_map(|m| {
                let points: Vec<Vector> = m
                    .vertices
                    .iter()
                    .map(|v| {
                        Vector::new(
                            f64::from(v[0]) * scale[0],
                            f64::from(v[1]) * scale[1],
                            f64::from(v[2]) * scale[2],
                        )
                    })
                    .collect();
                ConvexPolyhedron::from_convex_hull(&points)
                    .map(|hull| Solid::new(Box::new(hull), Isometry3::identity()))
            })
            .collect()
    }
}

/// A URDF joint's motion at value `q`: a rotation about its axis (revolute, continuous) or a
/// translation along it (prismatic), in the joint frame.
fn joint_motion(joint: &urdf_rs::Joint, q: f64) -> Isometry3<f64> {
    let [x, y, z] = joint.axis.xyz.0;
    let axis = Vector3::new(x, y, z).normalize();
    match joint.joint_type {
        urdf_rs::JointType::Prismatic => Isometry3::translation(axis.x * q, axis.y * q, axis.z * q),
        _ => Isometry3::rotation(axis * q),
    }
}

/// The pairs of robot shapes (indices into `robot`) that must not touch: on links that move
/// relative to each other (different anchors), and not exempt by a `disable_collisions`
/// element of the geometry's SRDF (read here by text search, either link order). Empty
/// without an SRDF.
fn self_pairs(robot: &[RobotShape], geometry: &RobotGeometry) -> Vec<(usize, usize)> {
    let Some(srdf) = &geometry.srdf else {
        return Vec::new();
    };
    let text = std::fs::read_to_string(srdf).expect("the SRDF is readable");
    let attribute = |element: &str, name: &str| -> Option<String> {
        let start = element.find(&format!("{name}=\""))? + name.len() + 2;
        let len = element[start..].find('"')?;
        Some(element[start..start + len].to_owned())
    };
    let exempt: Vec<(String, String)> = text
        .split("<disable_collisions")
        .skip(1)
        .filter_map(|rest| {
            let element = &rest[..rest.find('>')?];
            Some((attribute(element, "link1")?, attribute(element, "link2")?))
        })
        .collect();
    let exempt_pair = |a: &str, b: &str| {
        exempt
            .iter()
            .any(|(x, y)| (x == a && y == b) || (x == b && y == a))
    };
    let mut pairs = Vec::new();
    for i in 0..robot.len() {
        for j in i + 1..robot.len() {
            let (a, b) = (&robot[i], &robot[j]);
            if a.anchor != b.anchor && !exempt_pair(&a.link, &b.link) {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

/// The robot's collision shapes, from its URDF: each anchored to the base or to the Pinocchio
/// joint whose child link carries it (through fixed and frozen joints).
fn robot_shapes(pin: &Model, geometry: &RobotGeometry) -> Vec<RobotShape> {
    let urdf = urdf_rs::read_file(&geometry.urdf).expect("the robot's URDF parses");
    // The root: the one link that is no joint's child. It is the mobile base.
    let roots: Vec<&urdf_rs::Link> = urdf
        .links
        .iter()
        .filter(|l| !urdf.joints.iter().any(|j| j.child.link == l.name))
        .collect();
    assert_eq!(roots.len(), 1, "the robot URDF is a tree with one root");
    let mut out = Vec::new();
    let mut moving = 0;
    // Depth-first from the root: (link, anchor, anchor_from_link).
    let mut todo = vec![(roots[0].name.clone(), Anchor::Base, Isometry3::identity())];
    while let Some((name, anchor, anchor_from_link)) = todo.pop() {
        let link = urdf
            .links
            .iter()
            .find(|l| l.name == name)
            .expect("every joint's child is a link");
        for (i, c) in link.collision.iter().enumerate() {
            let solids = match &c.geometry {
                urdf_rs::Geometry::Box { size } => {
                    vec![Solid::cuboid(Vector3::new(size[0], size[1], size[2]) / 2.0)]
                }
                urdf_rs::Geometry::Cylinder { radius, length } => {
                    vec![Solid::cylinder(*radius, *length)]
                }
                urdf_rs::Geometry::Capsule { radius, length } => {
                    vec![Solid::capsule(*radius, *length)]
                }
                urdf_rs::Geometry::Sphere { radius } => vec![Solid::ball(*radius)],
                urdf_rs::Geometry::Mesh { filename, scale } => {
                    let scale = scale.map_or([1.0; 3], |s| s.0);
                    geometry.mesh_hulls(filename, scale)
                }
            };
            let label = c.name.clone().unwrap_or_else(|| format!("#{i}"));
            let contact = (geometry.contact)(&link.name, &label);
            let several = solids.len() > 1;
            for (m, solid) in solids.into_iter().enumerate() {
                let name = if several {
                    format!("{}/{label}.{m}", link.name)
                } else {
                    format!("{}/{label}", link.name)
                };
                out.push(RobotShape {
                    name,
                    link: link.name.clone(),
                    contact,
                    anchor,
                    anchor_from_shape: anchor_from_link * urdf_pose(&c.origin),
                    solid,
                });
            }
        }
        for joint in urdf.joints.iter().filter(|j| j.parent.link == name) {
            let child = joint.child.link.clone();
            let frozen = geometry.frozen.iter().find(|(n, _)| *n == joint.name);
            match (&joint.joint_type, frozen) {
                (urdf_rs::JointType::Fixed, _) => {
                    todo.push((child, anchor, anchor_from_link * urdf_pose(&joint.origin)));
                }
                (
                    urdf_rs::JointType::Revolute
                    | urdf_rs::JointType::Continuous
                    | urdf_rs::JointType::Prismatic,
                    Some(&(_, value)),
                ) => {
                    let at = urdf_pose(&joint.origin) * joint_motion(joint, value);
                    todo.push((child, anchor, anchor_from_link * at));
                }
                (
                    urdf_rs::JointType::Revolute
                    | urdf_rs::JointType::Continuous
                    | urdf_rs::JointType::Prismatic,
                    None,
                ) => {
                    let index = pin
                        .joint_index(&joint.name)
                        .unwrap_or_else(|| panic!("arm joint {:?} in Pinocchio", joint.name));
                    moving += 1;
                    todo.push((child, Anchor::Joint(index), Isometry3::identity()));
                }
                (other, _) => panic!("joint {:?}: unexpected type {other:?}", joint.name),
            }
        }
    }
    assert_eq!(
        moving + 1,
        pin.njoints(),
        "every Pinocchio joint (besides the universe) is a URDF joint"
    );
    assert!(out.iter().any(|s| s.contact), "contact shapes found");
    out
}

/// `world_from_base` of a base pose `[x, y, yaw]`: the yaw about z, then the translation in the
/// floor plane.
fn world_from_base(base: &[f64]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(base[0], base[1], 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), base[2]),
    )
}

/// One scene collider.
struct SceneBody {
    /// Base map shape or part name.
    name: String,
    /// `None` for a base map shape.
    part: Option<usize>,
    /// World (base shape) or part frame (part collider) from the shape frame.
    from_shape: Isometry3<f64>,
    solid: Solid,
}

fn scene_bodies(model: &SceneModel) -> Vec<SceneBody> {
    let mut out: Vec<SceneBody> = model
        .base()
        .shapes
        .iter()
        .map(|s| SceneBody {
            name: s.name.clone(),
            part: None,
            from_shape: s.world_from_shape,
            solid: Solid::of_scene(&s.shape),
        })
        .collect();
    for (k, part) in model.parts().iter().enumerate() {
        for c in part.colliders() {
            out.push(SceneBody {
                name: part.name().to_owned(),
                part: Some(k),
                from_shape: c.part_from_shape,
                solid: Solid::of_scene(&c.shape),
            });
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// The checker

/// One sampled robot configuration, world poses of the parry frames and bounding spheres.
struct Placed {
    poses: Vec<Pose>,
    centers: Vec<Point3<f64>>,
}

/// Where a sample is.
struct Sample<'s> {
    step: usize,
    phase: Phase,
    at: f64,
    contact: bool,
    config: &'s [f64],
    scene_value: f64,
}

impl<'s> Sample<'s> {
    fn new(
        step: usize,
        phase: Phase,
        at: f64,
        contact: bool,
        config: &'s [f64],
        scene_value: f64,
    ) -> Sample<'s> {
        Sample {
            step,
            phase,
            at,
            contact,
            config,
            scene_value,
        }
    }
}

struct Checker<'a> {
    model: &'a SceneModel,
    pin: &'a Model,
    data: Data,
    robot: Vec<RobotShape>,
    /// The robot shape pairs that must not touch each other (see [`self_pairs`]).
    self_pairs: Vec<(usize, usize)>,
    /// [`RobotGeometry::grasp_self_clearance`].
    grasp_self_clearance: f64,
    bodies: Vec<SceneBody>,
    scene: SceneData,
    /// Per body, for the current step: whether it belongs to the grasped part.
    grasped: Vec<bool>,
    /// Per body, for the current step: whether it is part of the grasped part's front.
    front: Vec<bool>,
    /// World poses and bounding-sphere centres of the bodies at the current scene state.
    body_poses: Vec<Pose>,
    body_centers: Vec<Point3<f64>>,
    /// Joint placements in the base frame for `arm` (Pinocchio's root frame is the base).
    arm: Option<Vec<f64>>,
    base_from_joint: Vec<Isometry3<f64>>,
    report: Report,
}

impl<'a> Checker<'a> {
    fn new(
        planner: &'a HierarchicalPlanner,
        model: &'a SceneModel,
        geometry: &RobotGeometry,
    ) -> Checker<'a> {
        let pin = planner.robot().pinocchio();
        let bodies = scene_bodies(model);
        let n = bodies.len();
        let robot = robot_shapes(pin, geometry);
        Checker {
            model,
            pin,
            data: Data::new(pin).expect("Pinocchio data"),
            self_pairs: self_pairs(&robot, geometry),
            grasp_self_clearance: geometry.grasp_self_clearance,
            robot,
            bodies,
            scene: SceneData::new(model),
            grasped: vec![false; n],
            front: vec![false; n],
            body_poses: Vec::new(),
            body_centers: Vec::new(),
            arm: None,
            base_from_joint: Vec::new(),
            report: Report {
                samples: 0,
                contact_samples: 0,
                min_clearance: f64::INFINITY,
                min_clearance_between: String::new(),
                min_self_clearance: [SELF_EXACT; 2],
                min_self_clearance_between: Default::default(),
                max_front_depth: 0.0,
            },
        }
    }

    /// Scene forward kinematics at `state`, and the bodies' world poses.
    fn set_scene(&mut self, state: &State) {
        scene_fk(self.model, &mut self.scene, state).expect("scene forward kinematics");
        let parts = self.scene.world_from_parts();
        self.body_poses.clear();
        self.body_centers.clear();
        for b in &self.bodies {
            let world_from_shape = match b.part {
                None => b.from_shape,
                Some(k) => parts[k] * b.from_shape,
            };
            self.body_poses
                .push(to_pose(&(world_from_shape * b.solid.fix)));
            self.body_centers.push(world_from_shape * b.solid.center);
        }
    }

    /// The grasped part and its front for a step grasping `handle` of the part moved by
    /// `joint`, with the scene set to the step's start state.
    fn set_grasp(&mut self, joint: &str, handle: &str) {
        let joint = self.model.joint_id(joint).expect("the step's joint");
        let moved = &self.model.parts()[joint.part().index()];
        let handle = self.model.handle_id(handle).expect("the step's handle");
        let h = self.model.handle(handle).expect("handle");
        let p = self.scene.world_from_parts()[handle.part().index()] * h.position;
        let p = to_vector(&p);
        for (i, b) in self.bodies.iter().enumerate() {
            let grasped = b
                .part
                .is_some_and(|k| moved.subtree_contains(self.model.parts()[k].id()));
            self.grasped[i] = grasped;
            self.front[i] = grasped && {
                let proj = b.solid.shape.project_point(&self.body_poses[i], p, false);
                // Strictly inside: inside, and not on the boundary.
                let strictly = proj.is_inside && (proj.point - p).length() > TOUCH;
                !strictly
            };
        }
    }

    /// World poses of the robot's shapes at `base` and `arm`.
    fn place(&mut self, base: &[f64], arm: &[f64]) -> Placed {
        if self.arm.as_deref() != Some(arm) {
            let q = DVector::from_column_slice(arm);
            arm_fk(self.pin, &mut self.data, &q).expect("Pinocchio forward kinematics");
            self.base_from_joint = (0..self.pin.njoints())
                .map(|j| joint_placement(self.pin, &self.data, JointIndex(j)).expect("placement"))
                .collect();
            self.arm = Some(arm.to_vec());
        }
        let world_from_base = world_from_base(base);
        let mut poses = Vec::with_capacity(self.robot.len());
        let mut centers = Vec::with_capacity(self.robot.len());
        for r in &self.robot {
            let base_from_anchor = match r.anchor {
                Anchor::Base => Isometry3::identity(),
                Anchor::Joint(j) => self.base_from_joint[j.0],
            };
            let world_from_shape = world_from_base * base_from_anchor * r.anchor_from_shape;
            poses.push(to_pose(&(world_from_shape * r.solid.fix)));
            centers.push(world_from_shape * r.solid.center);
        }
        Placed { poses, centers }
    }

    /// Checks one sample against the rule.
    fn check(&mut self, placed: &Placed, s: &Sample<'_>) -> Result<(), Violation> {
        self.report.samples += 1;
        if s.contact {
            self.report.contact_samples += 1;
        }
        let violation_with = |r: &RobotShape, body: &str, breach: Breach| Violation {
            step: s.step,
            phase: s.phase,
            at: s.at,
            contact_phase: s.contact,
            config: s.config.to_vec(),
            scene_value: s.scene_value,
            robot_shape: r.name.clone(),
            body: body.to_owned(),
            breach,
        };
        let violation =
            |r: &RobotShape, b: &SceneBody, breach: Breach| violation_with(r, &b.name, breach);
        // The robot against itself: no pair the SRDF does not exempt may touch.
        for &(i, j) in &self.self_pairs {
            let (a, b) = (&self.robot[i], &self.robot[j]);
            let gap =
                (placed.centers[i] - placed.centers[j]).norm() - a.solid.radius - b.solid.radius;
            let phase = usize::from(!s.contact);
            let wanted = if s.contact {
                self.grasp_self_clearance
            } else {
                0.0
            };
            if gap >= TOUCH.max(wanted) && gap >= self.report.min_self_clearance[phase] {
                continue;
            }
            let d = distance(
                &placed.poses[i],
                a.solid.shape.as_ref(),
                &placed.poses[j],
                b.solid.shape.as_ref(),
            );
            if d < TOUCH {
                return Err(violation_with(a, &b.name, Breach::Touch { distance: d }));
            }
            let wanted = self.grasp_self_clearance;
            if s.contact && d < wanted {
                return Err(violation_with(
                    a,
                    &b.name,
                    Breach::SelfClearance { distance: d },
                ));
            }
            if d < self.report.min_self_clearance[phase] {
                self.report.min_self_clearance[phase] = d;
                self.report.min_self_clearance_between[phase] =
                    format!("{} vs {} (step {}, {})", a.name, b.name, s.step, s.phase);
            }
        }
        for (ri, r) in self.robot.iter().enumerate() {
            for (bi, b) in self.bodies.iter().enumerate() {
                // Broad phase: the gap between the bounding spheres bounds the distance below.
                let gap = (placed.centers[ri] - self.body_centers[bi]).norm()
                    - r.solid.radius
                    - b.solid.radius;
                let may_touch = r.contact && s.contact && self.grasped[bi];
                if may_touch {
                    if !self.front[bi] || gap > 0.0 {
                        continue;
                    }
                    let c = query::contact(
                        &placed.poses[ri],
                        r.solid.shape.as_ref(),
                        &self.body_poses[bi],
                        b.solid.shape.as_ref(),
                        0.0,
                    )
                    .expect("parry supports the pair");
                    let depth = c.map_or(0.0, |c| (-c.dist).max(0.0));
                    self.report.max_front_depth = self.report.max_front_depth.max(depth);
                    if depth > MAX_FRONT_DEPTH {
                        return Err(violation(r, b, Breach::FrontPenetration { depth }));
                    }
                    continue;
                }
                // The exact distance only where it could touch or beat the smallest clearance.
                if gap >= TOUCH && gap >= self.report.min_clearance {
                    continue;
                }
                let d = distance(
                    &placed.poses[ri],
                    r.solid.shape.as_ref(),
                    &self.body_poses[bi],
                    b.solid.shape.as_ref(),
                );
                if d < TOUCH {
                    return Err(violation(r, b, Breach::Touch { distance: d }));
                }
                if d < self.report.min_clearance {
                    self.report.min_clearance = d;
                    self.report.min_clearance_between =
                        format!("{} vs {} (step {}, {})", r.name, b.name, s.step, s.phase);
                }
            }
        }
        Ok(())
    }
}

/// Dense samples of a polyline: every waypoint and `n` equal steps per segment, with `n` from
/// `steps(a, b)` (at least 1). Yields `(waypoint index + fraction, configuration)`.
/// The executed trajectory of a timed phase, sampled in time (its `sample(t)`, blended corners
/// included) with consecutive samples `close` (a predicate on both) (halving the time step where they
/// are not), each with its position along the waypoints: `j + f` between waypoints `j` and
/// `j + 1`, from the waypoints' times.
fn samples(
    path: &TimedPath,
    close: impl Fn((f64, &[f64]), (f64, &[f64])) -> bool,
) -> Vec<(f64, Vec<f64>)> {
    samples_of(&path.times, path.duration, &|t| path.sample(t), close)
}

/// [`samples`] of the state `sample(t)` of a trajectory reaching its waypoints at `times` and
/// lasting `duration` (several timed paths in step, sampled at the same times).
fn samples_of(
    times: &[f64],
    duration: f64,
    sample: &dyn Fn(f64) -> Vec<f64>,
    close: impl Fn((f64, &[f64]), (f64, &[f64])) -> bool,
) -> Vec<(f64, Vec<f64>)> {
    let at = |t: f64| {
        let k = times.len().saturating_sub(1);
        if k == 0 {
            return 0.0;
        }
        let j = times.partition_point(|&x| x <= t).clamp(1, k) - 1;
        let span = times[j + 1] - times[j];
        let f = if span > 0.0 {
            ((t - times[j]) / span).clamp(0.0, 1.0)
        } else {
            1.0
        };
        j as f64 + f
    };
    let mut out = vec![(0.0, sample(0.0))];
    let (mut t, mut dt) = (0.0, 1e-2);
    while t < duration {
        let mut next = (t + dt).min(duration);
        let mut q = sample(next);
        let last = out.len() - 1;
        while !close((out[last].0, &out[last].1), (at(next), &q)) && next - t > 1e-7 {
            dt /= 2.0;
            next = (t + dt).min(duration);
            q = sample(next);
        }
        t = next;
        out.push((at(t), q));
        dt *= 1.5;
    }
    out
}

/// Where `q` is along the piecewise-linear `waypoints`: `j + f` for its projection onto the
/// nearest segment `j` at fraction `f`.
fn along(waypoints: &[Vec<f64>], q: &[f64]) -> f64 {
    let mut best = (f64::INFINITY, 0.0);
    for (j, w) in waypoints.windows(2).enumerate() {
        let seg = DVector::from_iterator(q.len(), w[1].iter().zip(&w[0]).map(|(b, a)| b - a));
        let rel = DVector::from_iterator(q.len(), q.iter().zip(&w[0]).map(|(x, a)| x - a));
        let f = if seg.norm_squared() > 0.0 {
            (rel.dot(&seg) / seg.norm_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (rel - seg * f).norm();
        if d < best.0 {
            best = (d, j as f64 + f);
        }
    }
    best.1
}

fn max_change(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (y - x).abs())
        .fold(0.0, f64::max)
}

fn arm_close((_, a): (f64, &[f64]), (_, b): (f64, &[f64])) -> bool {
    max_change(a, b) <= ARM_STEP
}

fn base_close((_, a): (f64, &[f64]), (_, b): (f64, &[f64])) -> bool {
    (b[0] - a[0]).hypot(b[1] - a[1]) <= BASE_STEP && (b[2] - a[2]).abs() <= YAW_STEP
}

/// The pre-grasp index of a step's approach: from it to the end of the approach, contact is
/// allowed.
fn pregrasp(step: &StepMotion) -> usize {
    step.pregrasp
}

/// The post-grasp index of a step's retreat: up to it, contact is allowed.
fn postgrasp(step: &StepMotion) -> usize {
    step.postgrasp
}

/// Re-checks every phase of every step of `plan`, from `start`, densely (arm: at most
/// [`ARM_STEP`] per joint between samples; base: [`BASE_STEP`] and [`YAW_STEP`]; manipulation
/// also [`SCENE_STEP`] of the moved joint) under the contact rule of this module. A whole-body
/// manipulation (`manipulation_base`) is sampled with the base: its timed base path at the
/// arm's times (base samples also within [`BASE_STEP`] and [`YAW_STEP`]), the approach at the
/// step's `base` and the retreat at the last base pose. The first offending sample is the
/// `Err`.
pub(super) fn recheck(
    planner: &HierarchicalPlanner,
    model: &SceneModel,
    start: &State,
    plan: &MotionPlan,
) -> Result<Report, Violation> {
    recheck_robot(&RobotGeometry::gen3(), planner, model, start, plan)
}

/// [`recheck`] for the robot whose geometry `geometry` describes (the planner's robot).
pub(super) fn recheck_robot(
    geometry: &RobotGeometry,
    planner: &HierarchicalPlanner,
    model: &SceneModel,
    start: &State,
    plan: &MotionPlan,
) -> Result<Report, Violation> {
    let mut c = Checker::new(planner, model, geometry);
    let stow: Vec<f64> = planner.stow().iter().copied().collect();
    let mut state = start.clone();
    for (index, step) in plan.steps.iter().enumerate() {
        let joint = model.joint_id(&step.joint).expect("the step's joint");
        state
            .set(model, joint, step.from)
            .expect("the step's start value");
        c.set_scene(&state);
        c.set_grasp(&step.joint, &step.handle);
        // Base: the arm stowed, free.
        for (at, b) in samples(&step.base_path, base_close) {
            let placed = c.place(&b, &stow);
            c.check(
                &placed,
                &Sample::new(index, Phase::Base, at, false, &b, step.from),
            )?;
        }
        // Approach: free up to the pre-grasp configuration, contact from it on.
        let pre = pregrasp(step) as f64;
        for (at, q) in samples(&step.approach, arm_close) {
            let placed = c.place(&step.base, &q);
            c.check(
                &placed,
                &Sample::new(index, Phase::Approach, at, at >= pre, &q, step.from),
            )?;
        }
        // Manipulation: the arm and the scene joint interpolated together, contact; a
        // whole-body manipulation moves the base too (its timed path sampled at the arm's
        // times, as base and arm were timed in step).
        let k = step.manipulation.positions.len().saturating_sub(1).max(1) as f64;
        // The part follows the grasp: the scene joint where the robot's progress along the
        // waypoints puts it (the sample projected onto the nearest waypoint segment of the
        // joint path: base pose and arm for a whole-body manipulation, else the arm).
        let per_waypoint = (step.to - step.from).abs() / k;
        let fixed = step.base.to_vec();
        let moving = step.manipulation_base.as_ref();
        let waypoints: Vec<Vec<f64>> = (0..step.manipulation.positions.len())
            .map(|j| {
                let base = moving.map_or(&fixed, |b| &b.positions[j]);
                base.iter()
                    .chain(&step.manipulation.positions[j])
                    .copied()
                    .collect()
            })
            .collect();
        let state_at = |t: f64| -> Vec<f64> {
            let base = moving.map_or_else(|| fixed.clone(), |b| b.sample(t));
            base.into_iter()
                .chain(step.manipulation.sample(t))
                .collect()
        };
        let progress = |p: &[f64]| along(&waypoints, p);
        let manipulation = &step.manipulation;
        for (_, p) in samples_of(
            &manipulation.times,
            manipulation.duration,
            &state_at,
            |a, b| {
                arm_close((a.0, &a.1[3..]), (b.0, &b.1[3..]))
                    && base_close((a.0, &a.1[..3]), (b.0, &b.1[..3]))
                    && (progress(b.1) - progress(a.1)).abs() * per_waypoint <= SCENE_STEP
            },
        ) {
            let at = progress(&p);
            let value = step.from + (step.to - step.from) * at / k;
            state.set_unchecked(joint, value);
            c.set_scene(&state);
            let placed = c.place(&p[..3], &p[3..]);
            c.check(
                &placed,
                &Sample::new(index, Phase::Manipulation, at, true, &p[3..], value),
            )?;
        }
        // Retreat: contact up to the post-grasp configuration, free after it.
        state.set(model, joint, step.to).expect("the step's target");
        c.set_scene(&state);
        let post = postgrasp(step) as f64;
        // At the manipulation's last base pose (where a whole-body manipulation left it).
        let end = moving.map_or(fixed.clone(), |b| {
            b.positions[b.positions.len() - 1].clone()
        });
        for (at, q) in samples(&step.retreat, arm_close) {
            let placed = c.place(&end, &q);
            c.check(
                &placed,
                &Sample::new(index, Phase::Retreat, at, at <= post, &q, step.to),
            )?;
        }
    }
    Ok(c.report)
}

// ---------------------------------------------------------------------------------------------
// Tests

/// Plans `problem` with the shipped robot and default settings (120 s budget); panics unless
/// solved.
pub(super) fn solve(model: &SceneModel, problem: &Problem) -> (HierarchicalPlanner, MotionPlan) {
    solve_with(super::planner(), model, problem)
}

/// [`solve`] with `planner`.
pub(super) fn solve_with(
    planner: HierarchicalPlanner,
    model: &SceneModel,
    problem: &Problem,
) -> (HierarchicalPlanner, MotionPlan) {
    let result = planner
        .plan(
            model,
            problem,
            &Termination::after(Duration::from_secs(120)),
        )
        .expect("valid input");
    let MotionOutcome::Solved(plan) = result.outcome else {
        panic!("expected a plan, got {:?}", result.outcome);
    };
    (planner, plan)
}

/// The drawer problem of `tests/planner/mod.rs` (counter with the drawer handle at 0.75 m,
/// drawer out by at least 0.25 m, start base [-0.9, 0, 0]), planned once for the tests that
/// share it.
fn drawer() -> &'static (SceneModel, Problem, HierarchicalPlanner, MotionPlan) {
    static PLAN: OnceLock<(SceneModel, Problem, HierarchicalPlanner, MotionPlan)> = OnceLock::new();
    PLAN.get_or_init(|| {
        let model = super::counter_with_drawer(0.75);
        let problem = super::problem(
            &model,
            "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-0.9, 0.0, 0.0]\n",
        );
        let started = Instant::now();
        let (planner, plan) = solve(&model, &problem);
        eprintln!(
            "drawer: planned in {:.1} s",
            started.elapsed().as_secs_f64()
        );
        (model, problem, planner, plan)
    })
}

/// The robot shape names of the URDF (for the corrupted plans' verdicts).
fn robot_shape_names(planner: &HierarchicalPlanner) -> Vec<String> {
    robot_shapes(planner.robot().pinocchio(), &RobotGeometry::gen3())
        .into_iter()
        .map(|s| s.name)
        .collect()
}

#[test]
fn the_robot_geometry_read_here_is_the_urdf_s() {
    // Expected values from robots/kinova_gen3_mobile.urdf: 12 collision elements (chassis, the
    // Gen3 base cylinder, 7 link capsules, the gripper body and the two fingers), the fingers
    // being the only contact shapes, and at the neutral arm the left finger's box centre is at
    // flange (0.08, 0, 0.17), i.e. 0.03 m behind the tool frame along its z (tool 0.20 m along
    // the flange z), which we check against Pinocchio's tool frame (a different path through
    // the model: the tool frame is a frame of the last joint, composed by the planner's URDF
    // loader).
    let planner = super::planner();
    let pin = planner.robot().pinocchio();
    let shapes = robot_shapes(pin, &RobotGeometry::gen3());
    assert_eq!(shapes.len(), 12);
    let contact: Vec<&str> = shapes
        .iter()
        .filter(|s| s.contact)
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(
        contact,
        ["robotiq_2f_140/finger_left", "robotiq_2f_140/finger_right"]
    );
    assert!(
        shapes
            .iter()
            .any(|s| s.name == "base_link/chassis" && s.anchor == Anchor::Base)
    );
    let q = planner.stow();
    let mut data = Data::new(pin).unwrap();
    arm_fk(pin, &mut data, &q).unwrap();
    let tool =
        kinscene::kinematics::pinocchio::frame_placement(pin, &data, planner.robot().tool_frame())
            .unwrap();
    let finger = shapes.iter().find(|s| s.contact).unwrap();
    let Anchor::Joint(j) = finger.anchor else {
        panic!("the finger moves with the arm");
    };
    let base_from_finger = joint_placement(pin, &data, j).unwrap() * finger.anchor_from_shape;
    let tool_from_finger = tool.inverse() * base_from_finger;
    let t = tool_from_finger.translation.vector;
    assert!((t - Vector3::new(0.08, 0.0, -0.03)).norm() < 1e-9, "{t:?}");
}

#[test]
fn the_drawer_plan_keeps_the_contact_rule() {
    // The drawer of tests/planner/mod.rs (drawer_slide >= 0.25 from base [-0.9, 0, 0]), which
    // the planner solves in the end-to-end test there; the expectation is the rule itself: no
    // violation anywhere, at 5 mm / 0.005 rad sampling.
    let (model, problem, planner, plan) = drawer();
    let started = Instant::now();
    let report = recheck(planner, model, &problem.start, plan).unwrap_or_else(|v| panic!("{v}"));
    eprintln!(
        "drawer: rechecked in {:.2} s: {report}",
        started.elapsed().as_secs_f64()
    );
    assert!(
        report.samples > 100 && report.contact_samples > 0,
        "{report}"
    );
    assert!(report.min_clearance > 0.0);
}

/// A counter like [`super::counter_with_drawer`]'s (x in [0, 0.6], y in [-1, 1], 0.9 m high)
/// with a cabinet door in front of it instead of the drawer: 0.45 m wide (y in [-0.225, 0.225]
/// closed), 0.7 m tall (z in [0.15, 0.85], centred at 0.5), 0.02 m thick (x in [-0.03, -0.01] closed, 1 cm in
/// front of the counter as the drawer's front), hinged about the vertical line through its
/// outer front edge at y = -0.225. A positive angle swings the free edge (y = +0.225) out into
/// the room (-x). The handle is a vertical bar, a box 0.035 m proud of the door's face, 0.012 m
/// wide and 0.16 m tall, its centre 0.04 m from the free edge at the door's mid-height (z = 0.5, as
/// the drawer's handle sits on its front's centre); its grasp point is the bar's centre, its
/// normal outward (-x when closed).
pub(super) fn counter_with_door() -> SceneModel {
    counter_with_door_of(0.45, 2.0)
}

/// [`counter_with_door`]'s counter and door, the door `width` wide (y in
/// [-width/2, width/2] closed, hinged at y = -width/2, the handle bar's centre 0.04 m from the
/// free edge) and opening to `upper` rad.
pub(crate) fn counter_with_door_of(width: f64, upper: f64) -> SceneModel {
    let half = width / 2.0;
    let mut b = SceneModelBuilder::new();
    b.add_base_shape(kinscene::scene::BaseShape::new(
        "counter",
        Shape::box_size(Vector3::new(0.6, 2.0, 0.9)),
        Isometry3::translation(0.3, 0.0, 0.45),
    ));
    // The part frame is the hinge frame: x out of the counter's front (the door's outer face is
    // x = 0), y along the door towards the free edge, z up; the door's centre height 0.5.
    b.add_part(
        PartSpec::on_base(
            "door",
            Joint::revolute(
                "door_hinge",
                Point3::new(-0.03, -half, 0.5),
                Vector3::z(),
                Limits::new(0.0, upper),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.02, width, 0.7)),
            Isometry3::translation(0.01, half, 0.0),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.035, 0.012, 0.16)),
            Isometry3::translation(-0.0175, width - 0.04, 0.0),
        )
        .with_handle(Handle::new(
            "door_handle",
            Point3::new(-0.0175, width - 0.04, 0.0),
            -Vector3::x(),
        )),
    );
    b.build().expect("the test scene is valid")
}

#[test]
fn a_cabinet_door_plan_keeps_the_contact_rule() {
    // The door above opened to at least 1.5 rad from base [-0.9, 0, 0]; at 1.5 rad the free edge
    // is 0.45 m out into the room (x about -0.48), the robot's start pose 0.2 m further. The
    // expectation is the rule itself. The front of the door is its panel (the bar contains the
    // grasp point, so it is not front).
    let started = Instant::now();
    let model = counter_with_door();
    let problem = super::problem(
        &model,
        "[goal]\ndoor_hinge = { min = 1.5 }\n[robot]\nbase = [-0.9, 0.0, 0.0]\n",
    );
    let (planner, plan) = solve(&model, &problem);
    let planned = started.elapsed();
    // The planner may open the door in more than one step (the task lattice offers
    // intermediate angles); each step moves the door, the last one to at least 1.5 rad.
    assert!(plan.steps.iter().all(|s| s.joint == "door_hinge"));
    assert!(plan.steps.last().is_some_and(|s| s.to >= 1.5));
    let report = recheck(&planner, &model, &problem.start, &plan).unwrap_or_else(|v| panic!("{v}"));
    eprintln!(
        "door: planned in {:.1} s, rechecked in {:.2} s: {report}",
        planned.as_secs_f64(),
        (started.elapsed() - planned).as_secs_f64()
    );
    assert!(report.contact_samples > 0);
}

#[test]
fn corrupted_drawer_plans_are_rejected() {
    let (model, problem, planner, plan) = drawer();
    let names = robot_shape_names(planner);

    // (i) The whole base motion 0.15 m further towards the counter (+x): the planner's placement
    // keeps the robot out of the counter and the drawer's sweep with little to spare (the arm
    // reaches a handle 0.05 m in front of a 0.9 m high counter), so some robot shape must touch
    // something, or a finger must press into the drawer's front while it grasps. The expected
    // verdict names one of the URDF's shapes.
    let mut shifted = plan.clone();
    for step in &mut shifted.steps {
        step.base[0] += 0.15;
        for p in &mut step.base_path.positions {
            p[0] += 0.15;
        }
    }
    let v = recheck(planner, model, &problem.start, &shifted)
        .expect_err("a base 0.15 m closer to the counter touches it");
    eprintln!("shifted base: {v}");
    assert!(names.contains(&v.robot_shape), "{v}");
    assert!(["counter", "drawer"].contains(&v.body.as_str()), "{v}");

    // (ii) The base path's last pose 0.5 m inside the counter (its front face is x = 0, so the
    // chassis centre at x = 0.5): in the base phase the robot (arm stowed) must touch the
    // counter, or the drawer in front of it, on the changed last segment at the latest.
    let mut inside = plan.clone();
    let last = inside.steps[0].base_path.positions.last_mut().unwrap();
    last[0] = 0.5;
    let v = recheck(planner, model, &problem.start, &inside)
        .expect_err("a base pose inside the counter touches it");
    eprintln!("base inside the counter: {v}");
    assert_eq!((v.step, v.phase), (0, Phase::Base), "{v}");
    assert!(["counter", "drawer"].contains(&v.body.as_str()), "{v}");
    assert!(matches!(v.breach, Breach::Touch { .. }), "{v}");
    assert!(names.contains(&v.robot_shape), "{v}");
    let n = inside.steps[0].base_path.positions.len() as f64;
    assert!(v.at > n - 2.0, "only the last segment changed: {v}");

    // (iii), re-checking with another grasped part, is skipped: the drawer scene has one part.

    // (iv) The approach starting from a configuration where the robot folds into itself: the
    // first such configuration of a seeded draw within the joint limits, found with the
    // crate's own self-collision check (the generator; the verdict is the re-checker's own
    // FK, SRDF reading and parry distances). The re-check must name two robot shapes.
    use kinscene::kinematics::robot::{RobotCollision, RobotConfig};
    use rand::{Rng, SeedableRng};
    let robot = planner.robot();
    let collision = RobotCollision::new(robot).expect("the robot's collision model");
    let (lower, upper) = robot.arm_bounds();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let folded = (0..10_000)
        .map(|_| {
            DVector::from_fn(robot.dof(), |i, _| {
                rng.random_range(lower[i].max(-3.2)..=upper[i].min(3.2))
            })
        })
        .find(|arm| {
            let config = RobotConfig {
                base: plan.steps[0].base,
                arm: arm.clone(),
            };
            let poses = robot.link_poses(&config).expect("poses");
            collision.self_collision(&poses).is_some()
        })
        .expect("some configuration folds the arm into the robot");
    // The approach re-timed through its waypoints with the first one replaced (a timed path
    // samples its own profile, so its waypoints alone cannot be edited).
    let mut corrupted = plan.clone();
    let approach = &mut corrupted.steps[0].approach;
    let mut waypoints = approach.positions.clone();
    waypoints[0] = folded.as_slice().to_vec();
    let joints = robot.arm_joints();
    let vmax: Vec<f64> = joints.iter().map(|j| j.max_velocity).collect();
    let amax: Vec<f64> = joints.iter().map(|j| j.max_acceleration).collect();
    *approach = kinscene::motion::timing::time_parameterise(&waypoints, &vmax, &amax, None)
        .expect("the corrupted approach times");
    let v = recheck(planner, model, &problem.start, &corrupted)
        .expect_err("an approach from a self-colliding configuration");
    eprintln!("self-colliding approach: {v}");
    assert!(names.contains(&v.robot_shape), "{v}");
    assert!(names.contains(&v.body), "the robot touches itself: {v}");
    assert!(matches!(v.breach, Breach::Touch { .. }), "{v}");
}

#[test]
fn blended_timing_executes_faster_and_keeps_the_contact_rule() {
    // The drawer plan with the default settings (corners blended where the blend passes the
    // checks) against the same problem planned with every phase stopping at its corners
    // (`blend: None`). The arm phases are OMPL paths with corners, so blending shortens them;
    // the blended plan passes the independent re-check (the drawer test above re-checks it),
    // which samples the executed trajectory in time, blends included.
    let (model, problem, _, blended) = drawer();
    assert!(
        blended
            .steps
            .iter()
            .any(|s| !s.approach.is_exact() || !s.retreat.is_exact() || !s.manipulation.is_exact()),
        "no phase was blended"
    );
    let stopping = HierarchicalPlanner::new(
        kinscene::kinematics::robot::RobotModel::kinova_gen3_mobile(),
        kinscene::planner::PlannerSettings {
            blend: None,
            ..kinscene::planner::PlannerSettings::default()
        },
    )
    .unwrap();
    let exact = match stopping
        .plan(
            model,
            problem,
            &Termination::after(Duration::from_secs(120)),
        )
        .unwrap()
        .outcome
    {
        MotionOutcome::Solved(plan) => plan,
        other => panic!("expected a plan, got {other:?}"),
    };
    assert!(exact.steps.iter().all(|s| s.approach.is_exact()
        && s.manipulation.is_exact()
        && s.retreat.is_exact()
        && s.base_path.is_exact()));
    // Same seeds, same geometry: the paths agree, only their timing differs.
    assert_eq!(
        exact.steps[0].approach.positions,
        blended.steps[0].approach.positions
    );
    let arm = |p: &MotionPlan| p.steps.iter().map(|s| s.timing.arm()).sum::<f64>();
    eprintln!(
        "drawer: arm time {:.2} s stopping at corners, {:.2} s blended",
        arm(&exact),
        arm(blended)
    );
    assert!(arm(blended) < arm(&exact));
}

/// The value of `name="…"` in one XML tag written on one line.
fn xml_attribute(tag: &str, name: &str) -> String {
    let key = format!("{name}=\"");
    let start = tag.find(&key).expect("attribute present") + key.len();
    let end = start + tag[start..].find('"').expect("closing quote");
    tag[start..end].to_string()
}

/// The shipped Gen3's self-collision verdicts against a check built here from its SRDF and
/// URDF: the disabled pairs read from `robots/kinova_gen3_mobile.srdf` by a line scan (not the
/// crate's SRDF parser), the shapes from the URDF with urdf-rs, placed by Pinocchio's joint
/// placements and tested with parry directly: a configuration collides when two shapes on
/// different rigid bodies touch and the SRDF does not disable the pair of their URDF links. Over 1 500 random
/// configurations within the limits the two verdicts never disagree, and both sides see
/// collisions (so the comparison has something to disagree about).
#[test]
fn self_collision_verdicts_agree_with_an_srdf_check() {
    use kinscene::kinematics::robot::{RobotCollision, RobotConfig, RobotModel};
    use rand::{Rng, SeedableRng};

    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let pin = robot.pinocchio();
    let shapes = robot_shapes(pin, &RobotGeometry::gen3());
    let srdf = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/robots/kinova_gen3_mobile.srdf"
    ))
    .unwrap();
    let disabled: Vec<(String, String)> = srdf
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("<disable_collisions"))
        .map(|l| (xml_attribute(l, "link1"), xml_attribute(l, "link2")))
        .collect();
    assert_eq!(disabled.len(), 9);
    // Each shape's URDF link (its name is `link/collision`).
    let links: Vec<String> = shapes
        .iter()
        .map(|s| s.name.split('/').next().unwrap().to_string())
        .collect();
    let exempt = |a: &str, b: &str| {
        disabled
            .iter()
            .any(|(x, y)| (x == a && y == b) || (x == b && y == a))
    };
    let (lower, upper) = robot.arm_bounds();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
    let mut data = Data::new(pin).unwrap();
    let (mut ours_hits, mut theirs_hits, mut disagreements) = (0, 0, Vec::new());
    let samples = 1500;
    for _ in 0..samples {
        let arm = DVector::from_fn(robot.dof(), |i, _| {
            let (lo, hi) = (
                lower[i].max(-std::f64::consts::PI),
                upper[i].min(std::f64::consts::PI),
            );
            rng.random_range(lo..=hi)
        });
        let ours = collision
            .self_collision(
                &robot
                    .link_poses(&RobotConfig {
                        base: [0.0; 3],
                        arm: arm.clone(),
                    })
                    .unwrap(),
            )
            .is_some();
        arm_fk(pin, &mut data, &arm).unwrap();
        let place = |s: &RobotShape| {
            let base_from_anchor = match s.anchor {
                Anchor::Base => Isometry3::identity(),
                Anchor::Joint(j) => joint_placement(pin, &data, j).unwrap(),
            };
            to_pose(&(base_from_anchor * s.anchor_from_shape * s.solid.fix))
        };
        let poses: Vec<Pose> = shapes.iter().map(place).collect();
        let mut theirs = false;
        'pairs: for a in 0..shapes.len() {
            for b in a + 1..shapes.len() {
                if shapes[a].anchor == shapes[b].anchor || exempt(&links[a], &links[b]) {
                    continue;
                }
                let d = distance(
                    &poses[a],
                    shapes[a].solid.shape.as_ref(),
                    &poses[b],
                    shapes[b].solid.shape.as_ref(),
                );
                // Touching (distance 0) counts, as in the crate's predicate.
                if d <= 0.0 {
                    theirs = true;
                    break 'pairs;
                }
            }
        }
        ours_hits += usize::from(ours);
        theirs_hits += usize::from(theirs);
        if ours != theirs {
            disagreements.push((arm.as_slice().to_vec(), ours));
        }
    }
    assert!(
        disagreements.is_empty(),
        "{} of {samples} disagree, e.g. {:?}",
        disagreements.len(),
        disagreements.first()
    );
    assert!(
        ours_hits > 0 && theirs_hits > 0,
        "{ours_hits} / {theirs_hits}"
    );
}
