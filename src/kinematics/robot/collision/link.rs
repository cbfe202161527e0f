//! Per-link exact queries: one pair of links, one link against the scene, and the scene
//! placed once for many such queries against the same scene state ([`PlacedScene`]).

use nalgebra::Isometry3;

use super::{GROUND_TOP, RobotCollision, scene_shapes};
use crate::kinematics::robot::Exempt;
use crate::scene::collision::Body;
use crate::scene::collision::geometry::Placed;
use crate::scene::{PartId, SceneData, SceneModel};

impl RobotCollision {
    /// The first link (lowest index) whose contact shapes touch or overlap one of the shapes
    /// `shapes` (indices into the part's collision shapes) of `part` at the part pose in
    /// `data`: the fronts a grasp's fingers must stay out of while they may touch the
    /// handle's own shape. `None` if none does (or the part or a shape index is foreign).
    pub(crate) fn contact_touches(
        &self,
        link_poses: &[Isometry3<f64>],
        model: &SceneModel,
        data: &SceneData,
        part: PartId,
        shapes: &[usize],
    ) -> Option<usize> {
        let pose = data.world_from_part(part)?;
        let scene = model.geometry.parts.get(part.index())?;
        let targets: Vec<Placed<'_>> = shapes
            .iter()
            .filter_map(|&k| scene.get(k).map(|s| Placed::new(s, pose)))
            .collect();
        (0..self.shapes.len().min(link_poses.len())).find(|&l| {
            self.shapes[l]
                .iter()
                .zip(&self.contact[l])
                .filter(|(_, c)| **c)
                .any(|(s, _)| {
                    let placed = Placed::new(s, &link_poses[l]);
                    targets.iter().any(|t| {
                        placed.sphere_gap(t) <= 0.0 && placed.distance_within(t, 0.0) <= 0.0
                    })
                })
        })
    }

    /// Whether the shapes of links `i` and `j` touch or overlap at `link_poses` (exact, as
    /// [`RobotCollision::self_collision`] tests a pair; allowed or not). `false` if either
    /// link has no pose or no shapes.
    pub fn pair_touches(&self, link_poses: &[Isometry3<f64>], i: usize, j: usize) -> bool {
        match (link_poses.get(i), link_poses.get(j)) {
            (Some(pi), Some(pj)) if i < self.shapes.len() && j < self.shapes.len() => {
                let (a, b) = (self.place_link(i, pi), self.place_link(j, pj));
                self.pair_min_distance(i, j, &a, &b, 0.0) <= 0.0
            }
            _ => false,
        }
    }

    /// The colliders `(a, b)` of links `i` and `j` (indices into their colliders) that come
    /// closest at `link_poses`, among the pairs the robot does not exempt; `None` if either
    /// link has no pose or no shapes. To name what touches, with
    /// [`RobotLink::source`](crate::kinematics::robot::RobotLink::source).
    pub fn closest_colliders(
        &self,
        link_poses: &[Isometry3<f64>],
        i: usize,
        j: usize,
    ) -> Option<(usize, usize)> {
        let (pi, pj) = (link_poses.get(i)?, link_poses.get(j)?);
        if i >= self.shapes.len() || j >= self.shapes.len() {
            return None;
        }
        let (a, b) = (self.place_link(i, pi), self.place_link(j, pj));
        let mut best: Option<(f64, (usize, usize))> = None;
        for (x, pa) in a.iter().enumerate() {
            for (y, pb) in b.iter().enumerate() {
                let pair = if i < j { (x, y) } else { (y, x) };
                if self.exempt_collider_pair((i.min(j), i.max(j)), pair) {
                    continue;
                }
                let d = pa.distance_within(pb, f64::INFINITY);
                if best.is_none_or(|(e, _)| d < e) {
                    best = Some((d, (x, y)));
                }
            }
        }
        best.map(|(_, p)| p)
    }

    /// The exact distance (m) between the shapes of links `i` and `j` at `link_poses` (parry;
    /// `<= 0` when they touch or overlap), allowed pair or not; `+∞` if either link has no
    /// pose or no shapes.
    pub fn pair_distance(&self, link_poses: &[Isometry3<f64>], i: usize, j: usize) -> f64 {
        match (link_poses.get(i), link_poses.get(j)) {
            (Some(pi), Some(pj)) if i < self.shapes.len() && j < self.shapes.len() => {
                let (a, b) = (self.place_link(i, pi), self.place_link(j, pj));
                self.pair_min_distance(i, j, &a, &b, f64::INFINITY)
            }
            _ => f64::INFINITY,
        }
    }

    /// A lower bound (m) on the distance between the shapes of links `i` and `j` at
    /// `link_poses`, exact where it is below `cutoff`: parry's distance over the shape pairs
    /// whose bounding spheres come within `cutoff`, capped at `cutoff` (`<= 0` exactly when
    /// the links touch or overlap, for `cutoff >= 0`). `+∞` if either link has no pose or no
    /// shapes.
    pub(crate) fn pair_distance_below(
        &self,
        link_poses: &[Isometry3<f64>],
        i: usize,
        j: usize,
        cutoff: f64,
    ) -> f64 {
        match (link_poses.get(i), link_poses.get(j)) {
            (Some(pi), Some(pj)) if i < self.shapes.len() && j < self.shapes.len() => {
                let (a, b) = (self.place_link(i, pi), self.place_link(j, pj));
                self.pair_min_distance(i, j, &a, &b, cutoff).min(cutoff)
            }
            _ => f64::INFINITY,
        }
    }

    /// The exact distance (m) from the shapes of link `l` at `link_poses` to the scene's
    /// shapes (as [`RobotCollision::scene_collision`] takes the scene and `exempt`; a base
    /// link ignores the floor), not reduced by any margin; `+∞` without shapes or pose.
    pub fn link_scene_distance(
        &self,
        link_poses: &[Isometry3<f64>],
        l: usize,
        model: &SceneModel,
        data: &SceneData,
        exempt: Exempt<'_>,
    ) -> f64 {
        let (ignore, grasped) = exempt.split();
        let (Some(pose), Some(shapes)) = (link_poses.get(l), self.shapes.get(l)) else {
            return f64::INFINITY;
        };
        let identity = Isometry3::identity();
        let base = model.geometry.base.iter().map(|s| (s, identity, None));
        let parts = (model
            .geometry
            .parts
            .iter()
            .zip(data.world_from_parts())
            .enumerate())
        .filter(|(p, _)| !ignore.contains(&PartId(*p)))
        .flat_map(|(p, (shapes, pose))| shapes.iter().map(move |s| (s, *pose, Some(PartId(p)))));
        let scene: Vec<_> = base.chain(parts).collect();
        let base_link = self.base_links.contains(&l);
        let mut best = f64::INFINITY;
        for (k, shape) in shapes.iter().enumerate() {
            let placed = Placed::new(shape, pose);
            let contact = self.contact[l].get(k).copied().unwrap_or(false);
            for (other, other_pose, part) in &scene {
                let grasp = part.is_some_and(|p| grasped.contains(&p));
                if contact && grasp || base_link && other.world_box(other_pose).max.z <= GROUND_TOP
                {
                    continue;
                }
                let other = Placed::new(other, other_pose);
                if placed.sphere_gap(&other) < best {
                    best = best.min(placed.distance(&other));
                }
            }
        }
        best
    }

    /// Whether a shape of link `l` at `link_poses` comes within `margin` (m; negative or NaN
    /// counts as 0) of a shape `k` of `scene` with `among[k]` (a missing flag counts as
    /// false), with the exemptions `scene` was placed with (a base link ignores the floor, a
    /// contact shape the grasped parts): with every flag set, the predicate of
    /// [`RobotCollision::scene_collision`] for one link. `false` without shapes or pose.
    pub(crate) fn link_meets_scene(
        &self,
        link_poses: &[Isometry3<f64>],
        l: usize,
        scene: &PlacedScene<'_>,
        among: &[bool],
        margin: f64,
    ) -> bool {
        let margin = if margin > 0.0 { margin } else { 0.0 };
        let (Some(pose), Some(shapes)) = (link_poses.get(l), self.shapes.get(l)) else {
            return false;
        };
        let base_link = self.base_links.contains(&l);
        shapes.iter().enumerate().any(|(k, shape)| {
            let placed = Placed::new(shape, pose);
            let contact = self.contact[l].get(k).copied().unwrap_or(false);
            scene.shapes.iter().zip(among).any(|(s, &among)| {
                among
                    && !(contact && s.grasped || base_link && s.floor)
                    && placed.sphere_gap(&s.placed) <= margin
                    && placed.distance_within(&s.placed, margin) <= margin
            })
        })
    }

    /// A lower bound (m) on the distance from the shapes of link `l` at `link_poses` to
    /// shape `k` of `scene`, exact where it is below `cutoff` (shape pairs whose bounding
    /// spheres are farther apart count as `cutoff`), over the link's shapes not exempt from
    /// it (as in [`RobotCollision::link_meets_scene`]); `+∞` when all are exempt or without
    /// shapes, pose or scene shape `k`.
    pub(crate) fn link_shape_distance_below(
        &self,
        link_poses: &[Isometry3<f64>],
        l: usize,
        scene: &PlacedScene<'_>,
        k: usize,
        cutoff: f64,
    ) -> f64 {
        let (Some(pose), Some(shapes), Some(other)) =
            (link_poses.get(l), self.shapes.get(l), scene.shapes.get(k))
        else {
            return f64::INFINITY;
        };
        let base_link = self.base_links.contains(&l);
        if base_link && other.floor {
            return f64::INFINITY;
        }
        let mut best = f64::INFINITY;
        for (m, shape) in shapes.iter().enumerate() {
            if other.grasped && self.contact[l].get(m).copied().unwrap_or(false) {
                continue;
            }
            let placed = Placed::new(shape, pose);
            let d = if placed.sphere_gap(&other.placed) > cutoff {
                cutoff
            } else {
                placed.distance_within(&other.placed, cutoff).min(cutoff)
            };
            best = best.min(d);
        }
        best
    }
}

/// One scene shape placed in the world, with what exempts it.
struct SceneShape<'a> {
    placed: Placed<'a>,
    /// Its top is at most [`GROUND_TOP`]: base links may touch it.
    floor: bool,
    /// A grasped part's shape: contact shapes may touch it.
    grasped: bool,
}

/// The scene's shapes at one state, placed once (world poses, bounding spheres) for many
/// [`RobotCollision::link_meets_scene`] queries, with an exemption applied as
/// [`RobotCollision::scene_collision`] applies it ([`Exempt::Parts`] left out, the floor and
/// [`Exempt::Grasp`] parts flagged).
pub(crate) struct PlacedScene<'a> {
    shapes: Vec<SceneShape<'a>>,
}

impl<'a> PlacedScene<'a> {
    /// The shapes of `model` at the part poses of `data` (which must hold
    /// [`crate::scene::forward_kinematics`] of `model`) under `exempt`.
    pub(crate) fn new(model: &'a SceneModel, data: &SceneData, exempt: Exempt<'_>) -> Self {
        let (ignore, grasped) = exempt.split();
        let shapes = scene_shapes(model, data, ignore)
            .map(|(body, shape, pose)| SceneShape {
                placed: Placed::new(shape, &pose),
                floor: shape.world_box(&pose).max.z <= GROUND_TOP,
                grasped: matches!(body, Body::Part(p) if grasped.contains(&p)),
            })
            .collect();
        PlacedScene { shapes }
    }

    /// The number of shapes placed.
    pub(crate) fn len(&self) -> usize {
        self.shapes.len()
    }
}
