//! Robot collision checking with parry: self-collision with allowed pairs, and robot against
//! scene (base map and articulated parts) with a clearance margin.
//!
//! The robot's collision geometry is compiled into parry shapes once, with the scene layer's
//! own shape compiler (so robot and scene shapes are the same parry shapes placed the same
//! way). Every query first compares bounding volumes — a sphere per robot link, world-aligned
//! boxes for the whole robot and every scene shape — and computes exact parry distances only
//! for shape pairs that can be within the distance of interest.
//!
//! **Predicate.** Two shapes *touch* when their exact separation distance is `<= 0` (touching
//! or overlapping); a robot link *collides with the scene* when some shape of it is within
//! `margin` of some scene shape (`distance <= margin`), so `margin = 0` makes touching a
//! collision, as in [`crate::scene::collision::CollisionSettings`].
//!
//! **Floor.** The base links' shapes may touch scene shapes lying at or below the floor (top
//! at most [`GROUND_TOP`]): wheels stand on the floor. Arm links keep the margin from it.
//!
//! **Grasp contact rule.** While the robot holds a handle, only the gripper's contact shapes
//! (fingers and pads, [`RobotLink::contact`](super::RobotLink::contact)) may touch the grasped
//! part and its descendants; every other shape keeps the margin from every body, the grasped
//! part included ([`Exempt::Grasp`]). Away from the handle nothing is exempt
//! ([`Exempt::Nothing`]).

mod link;
mod motion;

use nalgebra::{Isometry3, Point3, Vector3};

use super::{RobotConfig, RobotError, RobotModel};
use crate::scene::collision::Body;
use crate::scene::collision::geometry::{CompiledShape, Placed, WorldBox};
use crate::scene::{BaseShapeId, PartId, SceneData, SceneModel};

pub(crate) use link::PlacedScene;
pub use motion::{ContactWalk, SceneAt, SpeedBound, WALK_CONTACT, WalkBase, WalkOutcome};

/// Highest top (m, world z) of a scene shape that counts as the floor the base drives on: the
/// base links' shapes (wheels, casters) may touch such shapes; every other robot shape keeps
/// the margin from them. The floor's top is z = 0 by the scene convention; 1 mm absorbs
/// round-off in a floor slab's pose.
pub const GROUND_TOP: f64 = 1e-3;

/// Which scene bodies some robot shapes may touch in [`RobotCollision::scene_collision`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exempt<'a> {
    /// Nothing: every robot shape keeps the margin from every scene body.
    Nothing,
    /// The grasp contact rule: the gripper's contact shapes may touch these parts (the grasped
    /// part and its descendants) and are checked against everything else; every other shape
    /// keeps the margin from every body, these parts included.
    Grasp(&'a [PartId]),
    /// These parts are not checked at all, for any robot shape. For callers that model the
    /// grasp contact themselves (a simulator's compliant grasp); a planner uses
    /// [`Exempt::Grasp`].
    Parts(&'a [PartId]),
}

impl<'a> Exempt<'a> {
    /// The parts not checked at all and the parts only the contact shapes may touch.
    pub(crate) fn split(self) -> (&'a [PartId], &'a [PartId]) {
        match self {
            Exempt::Nothing => (&[], &[]),
            Exempt::Grasp(parts) => (&[], parts),
            Exempt::Parts(parts) => (parts, &[]),
        }
    }
}

/// The scene's collision shapes at the part poses of `data`, with the body each belongs to and
/// its world pose: the base shapes (at the identity), then the shapes of every part not in
/// `ignore`.
pub(crate) fn scene_shapes<'m, 'd>(
    model: &'m SceneModel,
    data: &'d SceneData,
    ignore: &'d [PartId],
) -> impl Iterator<Item = (Body, &'m CompiledShape, Isometry3<f64>)> + 'd
where
    'm: 'd,
{
    let base = model
        .geometry
        .base
        .iter()
        .enumerate()
        .map(|(k, shape)| (Body::Base(BaseShapeId(k)), shape, Isometry3::identity()));
    let parts = model
        .geometry
        .parts
        .iter()
        .zip(data.world_from_parts())
        .enumerate()
        .filter(move |(p, _)| !ignore.contains(&PartId(*p)))
        .flat_map(|(p, (shapes, pose))| {
            shapes
                .iter()
                .map(move |shape| (Body::Part(PartId(p)), shape, *pose))
        });
    base.chain(parts)
}

/// The robot's compiled collision geometry and its self-collision pairs. Built once per robot
/// ([`RobotCollision::new`]); immutable, `Send + Sync`.
#[derive(Debug, Clone)]
pub struct RobotCollision {
    /// Per robot link, its shapes in the link frame.
    shapes: Vec<Vec<CompiledShape>>,
    /// Per robot link, per shape: contact geometry (fingers, pads).
    contact: Vec<Vec<bool>>,
    /// Per robot link, a sphere enclosing its shapes (link frame); `None` without shapes.
    spheres: Vec<Option<(Point3<f64>, f64)>>,
    /// Link pairs `(i, j)`, `i < j`, checked for self-collision.
    checked: Vec<(usize, usize)>,
    /// Link pairs `(i, j)`, `i < j`, exempt from self-collision checking.
    allowed: Vec<(usize, usize)>,
    /// Checked link pairs `(i, j)` of which some collider pairs are exempt
    /// ([`RobotModel::exempt_colliders`]): row-major flags, `true` for collider `a` of `i`
    /// and `b` of `j` exempt at `a · (colliders of j) + b`.
    masks: std::collections::BTreeMap<(usize, usize), Vec<bool>>,
    /// Links rigidly attached to the base.
    base_links: Vec<usize>,
}

impl RobotCollision {
    /// Compiles the robot's collision geometry and takes its self-collision exemptions:
    /// [`RobotModel::allowed_pairs`] when the robot has them (from an SRDF or computed by
    /// sampling); otherwise, a guess from a single pose: adjacent links (a link and the child
    /// of its joint) and every pair of links that touch at [`RobotModel::neutral`] (e.g. a
    /// wrist link and the next-but-one link of a compact wrist, whose simple shapes overlap by
    /// construction).
    ///
    /// # Errors
    /// [`RobotError::Collision`] if parry cannot compile a shape.
    pub fn new(robot: &RobotModel) -> Result<RobotCollision, RobotError> {
        let mut shapes = Vec::with_capacity(robot.links().len());
        for link in robot.links() {
            let mut compiled = Vec::with_capacity(link.colliders.len());
            for (k, collider) in link.colliders.iter().enumerate() {
                let what = format!("robot link {:?} collider {k}", link.name);
                compiled.push(
                    CompiledShape::new(&collider.shape, &collider.part_from_shape, &what).map_err(
                        |e| RobotError::Collision {
                            link: link.name.clone(),
                            message: e.to_string(),
                        },
                    )?,
                );
            }
            shapes.push(compiled);
        }
        let spheres = shapes.iter().map(|s| enclosing_sphere(s)).collect();
        let contact = robot
            .links()
            .iter()
            .map(|l| l.colliders_with_contact().map(|(_, c)| c).collect())
            .collect();
        let mut collision = RobotCollision {
            shapes,
            contact,
            spheres,
            checked: Vec::new(),
            allowed: Vec::new(),
            masks: std::collections::BTreeMap::new(),
            base_links: vec![0],
        };
        let n = robot.links().len();
        if let Some(pairs) = robot.allowed_pairs() {
            let listed: std::collections::BTreeSet<(usize, usize)> =
                pairs.iter().map(|p| (p.link1, p.link2)).collect();
            for e in robot.exempt_colliders() {
                let (a, b) = (
                    collision.shapes[e.link1].len(),
                    collision.shapes[e.link2].len(),
                );
                let mut mask = vec![false; a * b];
                for &(x, y) in &e.colliders {
                    if x < a && y < b {
                        mask[x * b + y] = true;
                    }
                }
                collision.masks.insert((e.link1, e.link2), mask);
            }
            for i in 0..n {
                for j in i + 1..n {
                    if collision.shapes[i].is_empty() || collision.shapes[j].is_empty() {
                        continue;
                    }
                    let all_masked = collision
                        .masks
                        .get(&(i, j))
                        .is_some_and(|m| m.iter().all(|x| *x));
                    if listed.contains(&(i, j)) || all_masked {
                        collision.allowed.push((i, j));
                    } else {
                        collision.checked.push((i, j));
                    }
                }
            }
            return Ok(collision);
        }
        let neutral = robot.link_poses(&RobotConfig {
            base: [0.0; 3],
            arm: robot.neutral(),
        })?;
        let placed = collision.place(&neutral);
        let (mut allowed, mut checked) = (Vec::new(), Vec::new());
        for i in 0..n {
            for j in i + 1..n {
                if collision.shapes[i].is_empty() || collision.shapes[j].is_empty() {
                    continue;
                }
                if j == i + 1 || min_distance(&placed[i], &placed[j], 0.0) <= 0.0 {
                    allowed.push((i, j));
                } else {
                    checked.push((i, j));
                }
            }
        }
        drop(placed);
        collision.allowed = allowed;
        collision.checked = checked;
        Ok(collision)
    }

    /// The link pairs `(i, j)`, `i < j`, exempt from self-collision checking (links without
    /// shapes are in no pair).
    pub fn allowed_pairs(&self) -> &[(usize, usize)] {
        &self.allowed
    }

    /// The first checked link pair `(i, j)`, `i < j` (in lexicographic order), whose shapes
    /// touch or overlap at `link_poses` (world from link, as [`RobotModel::link_poses`]
    /// returns), or `None`. Links without a pose (a shorter slice) are not checked.
    pub fn self_collision(&self, link_poses: &[Isometry3<f64>]) -> Option<(usize, usize)> {
        self.self_collision_within(link_poses, 0.0)
    }

    /// [`RobotCollision::self_collision`] with a clearance: the first checked link pair whose
    /// shapes come within `margin` (m; a negative or NaN margin counts as 0) of each other.
    /// For motions pulled tight against the robot itself (shortcuts), where a check at
    /// sampled states with no clearance could let the motion graze between the samples.
    pub fn self_collision_within(
        &self,
        link_poses: &[Isometry3<f64>],
        margin: f64,
    ) -> Option<(usize, usize)> {
        let margin = if margin > 0.0 { margin } else { 0.0 };
        let mut hit = None;
        self.pair_distances_within(link_poses, margin, &mut |i, j, d| {
            if d <= margin {
                hit = Some((i, j));
            }
            hit.is_none()
        });
        hit
    }

    /// The least distance (m) between the shapes of any checked link pair at `link_poses`,
    /// exact where it is at most `cap` (m; a negative or NaN cap counts as 0) and `cap`
    /// otherwise (`<= 0` when a pair touches). For a clearance a motion can keep: the
    /// clearance its end configurations already have.
    pub fn self_clearance(&self, link_poses: &[Isometry3<f64>], cap: f64) -> f64 {
        let cap = if cap > 0.0 { cap } else { 0.0 };
        let mut least = cap;
        self.pair_distances_within(link_poses, cap, &mut |_, _, d| {
            least = least.min(d);
            true
        });
        least
    }

    /// Calls `visit(i, j, d)` for the checked pairs `(i, j)` in order whose bounding spheres
    /// come within `cutoff` (m, `>= 0`), with their exact distance `d` where it is at most
    /// `cutoff` (a lower bound otherwise), until `visit` returns `false`.
    fn pair_distances_within(
        &self,
        link_poses: &[Isometry3<f64>],
        cutoff: f64,
        visit: &mut dyn FnMut(usize, usize, f64) -> bool,
    ) {
        let centers = self.world_spheres(link_poses);
        let mut placed: Vec<Option<Vec<Placed<'_>>>> = Vec::with_capacity(self.shapes.len());
        placed.resize_with(self.shapes.len(), || None);
        for &(i, j) in &self.checked {
            let (Some((ci, ri)), Some((cj, rj))) = (
                centers.get(i).copied().flatten(),
                centers.get(j).copied().flatten(),
            ) else {
                continue;
            };
            if (ci - cj).norm() - ri - rj > cutoff {
                continue;
            }
            for k in [i, j] {
                if placed[k].is_none() {
                    placed[k] = Some(self.place_link(k, &link_poses[k]));
                }
            }
            let (Some(a), Some(b)) = (&placed[i], &placed[j]) else {
                continue;
            };
            if !visit(i, j, self.pair_min_distance(i, j, a, b, cutoff)) {
                return;
            }
        }
    }

    /// The first robot link (lowest index) within `margin` (m, clearance required) of the
    /// scene, and the scene body it is closest to among those in reach: base map shapes of
    /// `model`, and its parts at the poses in `data` (which must hold
    /// [`crate::scene::forward_kinematics`] of `model`), with the exemptions of `exempt` (see
    /// [`Exempt`]). `None` if every link keeps more than `margin` from the scene.
    /// Links without a pose (a shorter slice) are not checked; a negative or NaN margin counts
    /// as 0.
    pub fn scene_collision(
        &self,
        link_poses: &[Isometry3<f64>],
        model: &SceneModel,
        data: &SceneData,
        exempt: Exempt<'_>,
        margin: f64,
    ) -> Option<(usize, Body)> {
        self.scene_contact(link_poses, model, data, exempt, margin)
            .map(|(l, _, body)| (l, body))
    }

    /// [`RobotCollision::scene_collision`] with the link's collider that comes closest to
    /// the body: `(link, collider, body)` (to name the URDF link of a collider merged into a
    /// robot link, [`RobotLink::source`](super::RobotLink::source)).
    pub fn scene_contact(
        &self,
        link_poses: &[Isometry3<f64>],
        model: &SceneModel,
        data: &SceneData,
        exempt: Exempt<'_>,
        margin: f64,
    ) -> Option<(usize, usize, Body)> {
        let (ignore, grasped) = exempt.split();
        let margin = if margin > 0.0 { margin } else { 0.0 };
        let links = self.shapes.len().min(link_poses.len());
        let placed: Vec<Vec<(Placed<'_>, WorldBox)>> = (0..links)
            .map(|l| {
                self.shapes[l]
                    .iter()
                    .map(|s| {
                        (
                            Placed::new(s, &link_poses[l]),
                            inflate(s.enclosing_world_box(&link_poses[l]), margin),
                        )
                    })
                    .collect()
            })
            .collect();
        let robot_box = placed
            .iter()
            .flatten()
            .map(|(_, b)| *b)
            .reduce(WorldBox::union)?;
        // Scene shapes whose box meets the robot's (inflated) box.
        let mut candidates: Vec<(Body, Placed<'_>, WorldBox)> = Vec::new();
        for (body, shape, pose) in scene_shapes(model, data, ignore) {
            let b = shape.world_box(&pose);
            if b.overlaps(&robot_box) {
                candidates.push((body, Placed::new(shape, &pose), b));
            }
        }
        if candidates.is_empty() {
            return None;
        }
        for (l, link) in placed.iter().enumerate() {
            let base_link = self.base_links.contains(&l);
            let mut best: Option<(f64, usize, Body)> = None;
            for (k, (robot_shape, robot_box)) in link.iter().enumerate() {
                let contact = self.contact[l].get(k).copied().unwrap_or(false);
                for (body, scene_shape, scene_box) in &candidates {
                    if contact && matches!(body, Body::Part(p) if grasped.contains(p)) {
                        continue;
                    }
                    if base_link && scene_box.max.z <= GROUND_TOP {
                        continue;
                    }
                    if !robot_box.overlaps(scene_box)
                        || robot_shape.sphere_gap(scene_shape) > margin
                    {
                        continue;
                    }
                    let d = robot_shape.distance_within(scene_shape, margin);
                    if d <= margin && best.is_none_or(|(b, _, _)| d < b) {
                        best = Some((d, k, *body));
                    }
                }
            }
            if let Some((_, k, body)) = best {
                return Some((l, k, body));
            }
        }
        None
    }

    /// How far the gripper's contact shapes reach beyond the tool origin along the approach
    /// (tool +z), m: the largest z, in the tool frame, of the bounding boxes of the contact
    /// shapes of the last link (the fingertips). A conservative bound (a box encloses its
    /// shape). `None` if the robot has no contact shapes on its last link.
    pub fn fingertip_reach(&self, robot: &RobotModel) -> Option<f64> {
        self.fingertip_boxes(robot)?
            .map(|b| b.max.z)
            .reduce(f64::max)
    }

    /// How far the gripper's contact shapes reach sideways from the tool's x-z plane (m): the
    /// largest |y|, in the tool frame, of the bounding boxes of the contact shapes of the last
    /// link (the fingers' half thickness across their closing direction for a two-finger
    /// gripper). `None` if the robot has no contact shapes on its last link.
    pub fn fingertip_side_reach(&self, robot: &RobotModel) -> Option<f64> {
        self.fingertip_boxes(robot)?
            .map(|b| b.max.y.abs().max(b.min.y.abs()))
            .reduce(f64::max)
    }

    /// The bounding boxes, in the tool frame, of the contact shapes of the last link (the
    /// fingers); `None` if the robot has no links.
    fn fingertip_boxes<'a>(
        &'a self,
        robot: &RobotModel,
    ) -> Option<impl Iterator<Item = WorldBox> + 'a> {
        let last = self.shapes.len().checked_sub(1)?;
        let tool_from_last = robot.last_from_tool().inverse();
        Some(
            self.shapes[last]
                .iter()
                .zip(&self.contact[last])
                .filter(|(_, c)| **c)
                .map(move |(s, _)| s.world_box(&tool_from_last)),
        )
    }

    /// The links rigidly attached to the base (they move with the base only, whatever the arm
    /// does): `[0]`, the base link with every link merged into it. SE(2) base validity with the
    /// arm stowed checks these and the arm links at the stowed configuration.
    pub fn base_links(&self) -> &[usize] {
        &self.base_links
    }

    /// The lowest and highest world z of the shapes of links `first..` at `link_poses` (their
    /// world boxes; `(+∞, −∞)` without shapes).
    pub(super) fn height_range(&self, link_poses: &[Isometry3<f64>], first: usize) -> (f64, f64) {
        (first..self.shapes.len().min(link_poses.len()))
            .flat_map(|l| {
                self.shapes[l]
                    .iter()
                    .map(move |s| s.world_box(&link_poses[l]))
            })
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), b| {
                (lo.min(b.min.z), hi.max(b.max.z))
            })
    }

    /// Every pair `(i, j)`, `i < j`, of links with shapes whose shapes touch or overlap at
    /// `link_poses`, exempt or not.
    pub(super) fn touching_pairs(&self, link_poses: &[Isometry3<f64>]) -> Vec<(usize, usize)> {
        let centers = self.world_spheres(link_poses);
        let placed = self.place(link_poses);
        let mut touching = Vec::new();
        for i in 0..placed.len() {
            for j in i + 1..placed.len() {
                let (Some((ci, ri)), Some((cj, rj))) = (centers[i], centers[j]) else {
                    continue;
                };
                if (ci - cj).norm() > ri + rj {
                    continue;
                }
                if min_distance(&placed[i], &placed[j], 0.0) <= 0.0 {
                    touching.push((i, j));
                }
            }
        }
        touching
    }

    /// Whether collider pair `(a, b)` of link pair `(i, j)`, `i < j`, is exempt.
    fn exempt_collider_pair(&self, (i, j): (usize, usize), (a, b): (usize, usize)) -> bool {
        self.masks.get(&(i, j)).is_some_and(|m| {
            let n = self.shapes[j].len();
            m.get(a * n + b).copied().unwrap_or(false)
        })
    }

    /// The least distance between links `i < j`, placed as `a` and `b`, as [`min_distance`]
    /// takes it, without the collider pairs the robot exempts.
    fn pair_min_distance(
        &self,
        i: usize,
        j: usize,
        a: &[Placed<'_>],
        b: &[Placed<'_>],
        cutoff: f64,
    ) -> f64 {
        let (i, j, a, b) = if i < j { (i, j, a, b) } else { (j, i, b, a) };
        masked_min_distance(a, b, cutoff, self.masks.get(&(i, j)).map(Vec::as_slice))
    }

    /// Every link's shapes placed at `link_poses`.
    fn place<'a>(&'a self, link_poses: &[Isometry3<f64>]) -> Vec<Vec<Placed<'a>>> {
        (0..self.shapes.len().min(link_poses.len()))
            .map(|l| self.place_link(l, &link_poses[l]))
            .collect()
    }

    fn place_link<'a>(&'a self, link: usize, world_from_link: &Isometry3<f64>) -> Vec<Placed<'a>> {
        self.shapes[link]
            .iter()
            .map(|s| Placed::new(s, world_from_link))
            .collect()
    }

    /// Per link, its enclosing sphere in the world.
    fn world_spheres(&self, link_poses: &[Isometry3<f64>]) -> Vec<Option<(Point3<f64>, f64)>> {
        self.spheres
            .iter()
            .zip(link_poses)
            .map(|(s, pose)| s.map(|(c, r)| (pose * c, r)))
            .collect()
    }
}

/// The smallest distance between two sets of placed shapes, exact when it is `<= cutoff`
/// (pairs whose bounding spheres are farther apart than `cutoff` are skipped; `+∞` if all are).
fn min_distance(a: &[Placed<'_>], b: &[Placed<'_>], cutoff: f64) -> f64 {
    masked_min_distance(a, b, cutoff, None)
}

/// [`min_distance`] without the shape pairs `(x, y)` whose flag `mask[x · b.len() + y]` is set.
fn masked_min_distance(
    a: &[Placed<'_>],
    b: &[Placed<'_>],
    cutoff: f64,
    mask: Option<&[bool]>,
) -> f64 {
    let mut best = f64::INFINITY;
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            if mask.is_some_and(|m| m.get(i * b.len() + j).copied().unwrap_or(false)) {
                continue;
            }
            if x.sphere_gap(y) > cutoff {
                continue;
            }
            best = best.min(x.distance_within(y, cutoff));
            if best <= 0.0 {
                return best;
            }
        }
    }
    best
}

/// A sphere (centre, radius) enclosing the shapes' bounding spheres: centred on the mean of
/// their centres.
fn enclosing_sphere(shapes: &[CompiledShape]) -> Option<(Point3<f64>, f64)> {
    if shapes.is_empty() {
        return None;
    }
    let sum: Vector3<f64> = shapes.iter().map(|s| s.sphere.center.coords).sum();
    let center = Point3::from(sum / shapes.len() as f64);
    let radius = shapes
        .iter()
        .map(|s| (s.sphere.center - center).norm() + s.sphere.radius)
        .fold(0.0, f64::max);
    Some((center, radius))
}

/// `b` grown by `margin` (plus 1 nm, so that boxes of shapes exactly `margin` apart still
/// overlap: [`WorldBox::overlaps`] compares open boxes) on every side.
fn inflate(b: WorldBox, margin: f64) -> WorldBox {
    let grow = Vector3::repeat(margin + 1e-9);
    WorldBox {
        min: b.min - grow,
        max: b.max + grow,
    }
}
