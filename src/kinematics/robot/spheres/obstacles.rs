//! The scene as a flat array of rounded boxes in lanes of `f32x8`, built once per scene state,
//! and the batch test of a configuration's spheres against it.

use nalgebra::{Isometry3, Vector3};
use wide::f32x8;

use super::check::{FAR, LANES, SPHERE_SLACK, SphereData};
use crate::kinematics::robot::collision::scene_shapes;
use crate::kinematics::robot::{Exempt, GROUND_TOP};
use crate::scene::collision::Body;
use crate::scene::collision::geometry::CompiledShape;
use crate::scene::{SceneData, SceneModel};

/// Eight rounded boxes, one per lane: centre, box axes (world), half extents, radius.
#[derive(Debug, Clone, Copy)]
struct Block {
    center: [f32x8; 3],
    /// `axes[k][c]`: component `c` of box axis `k`.
    axes: [[f32x8; 3]; 3],
    half: [f32x8; 3],
    /// The rounding radius plus the margin and [`SPHERE_SLACK`].
    reach: f32x8,
}

impl Block {
    /// Per lane, the squared distance from `p` to the lane's box (not rounded): every sphere
    /// test of the broad phase goes through this one computation.
    #[inline]
    fn dist2(&self, p: &[f32x8; 3]) -> f32x8 {
        let zero = f32x8::splat(0.0);
        let d = [
            p[0] - self.center[0],
            p[1] - self.center[1],
            p[2] - self.center[2],
        ];
        let mut dist2 = zero;
        for k in 0..3 {
            let along = self.axes[k][0] * d[0] + self.axes[k][1] * d[1] + self.axes[k][2] * d[2];
            let outside = (along.abs() - self.half[k]).max(zero);
            dist2 += outside * outside;
        }
        dist2
    }
}

/// One obstacle before packing: world pose of its box, half extents, reach.
type Rounded = (Isometry3<f64>, Vector3<f64>, f64);

/// The scene's collision shapes at one state as rounded boxes enclosing them (exact for boxes,
/// balls and capsules; the shape's own bounding box for cylinders and hulls), packed in lanes
/// of 8 for [`SphereObstacles::first_hit`].
///
/// It applies the exemptions of [`RobotCollision::scene_collision`] with the same `exempt`
/// and `margin`: base-link spheres skip the floor (shapes with tops at most [`GROUND_TOP`]),
/// contact spheres skip the grasped parts of [`Exempt::Grasp`], and [`Exempt::Parts`] are left
/// out. Each obstacle encloses its exact shape, so [`SphereObstacles::first_hit`] returning
/// `None` implies `scene_collision` returns `None`.
///
/// [`RobotCollision::scene_collision`]: crate::kinematics::robot::RobotCollision::scene_collision
#[derive(Debug, Clone)]
pub struct SphereObstacles {
    /// Per sphere kind (bit 0: base link, bit 1: contact shape), the obstacles it is tested
    /// against.
    sets: [Vec<Block>; 4],
    /// Per sphere kind, per lane of its blocks (block-major), the obstacle's index in the
    /// order [`SphereObstacles::new`] takes the scene's shapes (base shapes, then each part's
    /// shapes, left-out parts skipped); `u32::MAX` for padding lanes.
    index: [Vec<u32>; 4],
    count: usize,
}

impl SphereObstacles {
    /// The obstacles of `model` at the part poses of `data` (which must hold
    /// [`crate::scene::forward_kinematics`] of `model`), with `exempt` and `margin` (m; a
    /// negative or NaN margin counts as 0) as [`RobotCollision::scene_collision`] takes them.
    ///
    /// [`RobotCollision::scene_collision`]: crate::kinematics::robot::RobotCollision::scene_collision
    pub fn new(
        model: &SceneModel,
        data: &SceneData,
        exempt: Exempt<'_>,
        margin: f64,
    ) -> SphereObstacles {
        let (ignore, grasped) = exempt.split();
        let margin = if margin > 0.0 { margin } else { 0.0 };
        // (obstacle, on the floor, grasped)
        let mut all: Vec<(Rounded, bool, bool)> = Vec::new();
        let mut add = |shape: &CompiledShape, world_from_owner: &Isometry3<f64>, grasp: bool| {
            let floor = shape.world_box(world_from_owner).max.z <= GROUND_TOP;
            let (owner_from_box, half, radius) = shape.rounded_box();
            all.push((
                (world_from_owner * owner_from_box, half, radius + margin),
                floor,
                grasp,
            ));
        };
        for (body, shape, pose) in scene_shapes(model, data, ignore) {
            add(
                shape,
                &pose,
                matches!(body, Body::Part(p) if grasped.contains(&p)),
            );
        }
        let count = all.len();
        let kept = |kind: usize| {
            let (base, contact) = (kind & 1 != 0, kind & 2 != 0);
            all.iter()
                .enumerate()
                .filter(move |(_, (_, floor, grasp))| !(base && *floor || contact && *grasp))
        };
        let sets = std::array::from_fn(|kind| {
            let kept: Vec<Rounded> = kept(kind).map(|(_, (o, _, _))| *o).collect();
            kept.chunks(LANES).map(pack).collect()
        });
        let index = std::array::from_fn(|kind| {
            let mut index: Vec<u32> = kept(kind).map(|(i, _)| i as u32).collect();
            index.resize(index.len().div_ceil(LANES) * LANES, u32::MAX);
            index
        });
        SphereObstacles { sets, index, count }
    }

    /// These obstacles with every reach grown by `band` (m; shrunk for a negative one): a
    /// sphere then counts as reaching an obstacle within `band` of it, and every gap is
    /// `band` less.
    pub(super) fn inflated(mut self, band: f32) -> SphereObstacles {
        for block in self.sets.iter_mut().flatten() {
            block.reach += f32x8::splat(band);
        }
        self
    }

    /// The number of obstacles (scene shapes not left out by the exemption).
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether there are no obstacles.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The first link (lowest index) of which a sphere in `spheres` (placed by
    /// [`RobotSpheres::place`](super::RobotSpheres::place)) comes within its obstacles' reach
    /// (rounding radius + margin + [`SPHERE_SLACK`]), or `None`: then the robot's exact
    /// geometry keeps the margin from the scene.
    pub fn first_hit(&self, spheres: &SphereData) -> Option<usize> {
        (0..spheres.links.len()).find(|&l| self.link_hits(spheres, l))
    }

    /// Whether a sphere of link `l` in `spheres` comes within its obstacles' reach (as
    /// [`SphereObstacles::first_hit`] tests each link); `false` for a link not placed.
    pub(super) fn link_hits(&self, spheres: &SphereData, l: usize) -> bool {
        let Some(&(start, n)) = spheres.links.get(l) else {
            return false;
        };
        (start..start + n).any(|s| {
            let set = &self.sets[usize::from(spheres.kind[s] & 3)];
            let p = [
                f32x8::splat(spheres.x[s]),
                f32x8::splat(spheres.y[s]),
                f32x8::splat(spheres.z[s]),
            ];
            let r = f32x8::splat(spheres.r[s]);
            set.iter().any(|b| hits(b, &p, r))
        })
    }
}

/// Scratch of [`SphereObstacles::link_gaps`]: per sphere kind, per block of its obstacles,
/// the least gap over a link's spheres and the mask of the lanes reached; per obstacle the
/// least gap.
#[derive(Debug, Clone, Default)]
pub(super) struct GapScratch {
    least: [Vec<f32x8>; 4],
    reached: [Vec<f32x8>; 4],
    per_obstacle: Vec<f32>,
}

impl SphereObstacles {
    /// One pass over the spheres of link `l` in `spheres` against their obstacles: sets
    /// `hit[k]` for every obstacle `k` (the order of [`SphereObstacles::new`]) that a sphere
    /// reaches as [`SphereObstacles::link_hits`] tests them (`hit` resized to the number of
    /// obstacles, earlier flags kept), and returns whether any is reached, with the least gap
    /// (m) from the link's spheres to the obstacles not flagged in `hit`: the same `f32`
    /// values and minimum as [`SphereObstacles::link_clearance`] with `hit` as `skip`
    /// (`f32::INFINITY` for a link not placed or without obstacles). The broad phase of
    /// [`ArmCheck`](super::ArmCheck) computes each sphere-obstacle gap once with it.
    pub(super) fn link_gaps(
        &self,
        spheres: &SphereData,
        l: usize,
        hit: &mut Vec<bool>,
        scratch: &mut GapScratch,
    ) -> (bool, f32) {
        hit.resize(self.count, false);
        let Some(&(start, n)) = spheres.links.get(l) else {
            return (false, f32::INFINITY);
        };
        let zero = f32x8::splat(0.0);
        let inf = f32x8::splat(f32::INFINITY);
        let mut used = [false; 4];
        for s in start..start + n {
            let kind = usize::from(spheres.kind[s] & 3);
            let set = &self.sets[kind];
            if !used[kind] {
                used[kind] = true;
                scratch.least[kind].clear();
                scratch.least[kind].resize(set.len(), inf);
                scratch.reached[kind].clear();
                scratch.reached[kind].resize(set.len(), zero);
            }
            let p = [
                f32x8::splat(spheres.x[s]),
                f32x8::splat(spheres.y[s]),
                f32x8::splat(spheres.z[s]),
            ];
            let r = f32x8::splat(spheres.r[s]);
            let (least, reached) = (&mut scratch.least[kind], &mut scratch.reached[kind]);
            for ((block, least), reached) in set.iter().zip(least).zip(reached) {
                let dist2 = block.dist2(&p);
                // As `reached` and `link_clearance` compute them.
                let reach = r + block.reach;
                *reached |= dist2.simd_le(reach * reach);
                *least = least.min(dist2.sqrt() - block.reach - r);
            }
        }
        let mut any = false;
        let kinds = used.iter().filter(|u| **u).count();
        if kinds == 1 {
            // One kind (most links): each obstacle is one lane, so the lanes reached are the
            // obstacles left out, and padding lanes (never reached) are kept as
            // `link_clearance` keeps them.
            let kind = used.iter().position(|u| *u).unwrap_or(0);
            let mut clearance = inf;
            for (b, (least, reached)) in scratch.least[kind]
                .iter()
                .zip(&scratch.reached[kind])
                .enumerate()
            {
                let mut mask = reached.to_bitmask();
                while mask != 0 {
                    let lane = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if let Some(flag) = hit.get_mut(self.index[kind][b * LANES + lane] as usize) {
                        *flag = true;
                        any = true;
                    }
                }
                clearance = clearance.min(reached.select(inf, *least));
            }
            let least = clearance
                .to_array()
                .into_iter()
                .fold(f32::INFINITY, f32::min);
            return (any, least);
        }
        // Several kinds: an obstacle is in several sets, gathered per obstacle (padding lanes
        // apart: their gaps kept, as `link_clearance` keeps them).
        let per = &mut scratch.per_obstacle;
        per.clear();
        per.resize(self.count, f32::INFINITY);
        let mut padding = f32::INFINITY;
        for kind in (0..4).filter(|&k| used[k]) {
            for (b, (least, reached)) in scratch.least[kind]
                .iter()
                .zip(&scratch.reached[kind])
                .enumerate()
            {
                let mask = reached.to_bitmask();
                for (lane, g) in least.to_array().into_iter().enumerate() {
                    let index = self.index[kind][b * LANES + lane] as usize;
                    match per.get_mut(index) {
                        Some(least) => {
                            *least = least.min(g);
                            if mask & (1 << lane) != 0 {
                                hit[index] = true;
                                any = true;
                            }
                        }
                        None => padding = padding.min(g),
                    }
                }
            }
        }
        let clearance = per
            .iter()
            .zip(hit.iter())
            .filter(|(_, h)| !**h)
            .fold(padding, |best, (&g, _)| if g < best { g } else { best });
        (any, clearance)
    }
}

impl SphereObstacles {
    /// A lower bound (m) on the distance from the ball at `center` (world) of radius `radius`
    /// to every obstacle, none exempt (so also a bound for any sphere inside the ball,
    /// whatever its kind): the distance from its centre to each rounded box, minus the box's
    /// reach (rounding radius + margin + [`SPHERE_SLACK`]) and the radius, the least over the
    /// obstacles. Every point of the ball is at least this far from every (margin-inflated)
    /// obstacle.
    pub(super) fn ball_clearance(&self, center: [f32; 3], radius: f32) -> f32 {
        let p = center.map(f32x8::splat);
        let mut least = f32x8::splat(f32::INFINITY);
        // Set 0 (neither base link nor contact shape) exempts nothing: every obstacle.
        for b in &self.sets[0] {
            let dist2 = b.dist2(&p);
            least = least.min(dist2.sqrt() - b.reach);
        }
        least.to_array().into_iter().fold(f32::INFINITY, f32::min) - radius
    }

    /// A lower bound (m) on the distance from every sphere of link `l` in `spheres` to the
    /// obstacles it is tested against, leaving out the obstacles `k` with `skip[k]` set (the
    /// order of [`SphereObstacles::new`]; a shorter `skip` leaves out none beyond its end):
    /// as [`SphereObstacles::ball_clearance`] per sphere (against the obstacles of its kind),
    /// the least over the link's spheres. `f32::INFINITY` for a link without spheres or when
    /// every obstacle is left out.
    pub(super) fn link_clearance(&self, spheres: &SphereData, l: usize, skip: &[bool]) -> f32 {
        let Some(&(start, n)) = spheres.links.get(l) else {
            return f32::INFINITY;
        };
        let mut best = f32::INFINITY;
        let mut least = f32x8::splat(f32::INFINITY);
        // Nothing left out: the least over whole lanes, no per-lane look-up.
        let all = !skip.contains(&true);
        for s in start..start + n {
            let kind = usize::from(spheres.kind[s] & 3);
            let p = [
                f32x8::splat(spheres.x[s]),
                f32x8::splat(spheres.y[s]),
                f32x8::splat(spheres.z[s]),
            ];
            let r = f32x8::splat(spheres.r[s]);
            for (b, block) in self.sets[kind].iter().enumerate() {
                let dist2 = block.dist2(&p);
                let gap = dist2.sqrt() - block.reach - r;
                if all {
                    least = least.min(gap);
                    continue;
                }
                for (lane, g) in gap.to_array().into_iter().enumerate() {
                    let index = self.index[kind][b * LANES + lane] as usize;
                    if g < best && !skip.get(index).copied().unwrap_or(false) {
                        best = g;
                    }
                }
            }
        }
        least
            .to_array()
            .into_iter()
            .fold(best, |best, g| if g < best { g } else { best })
    }
}

/// Whether the sphere at `p` of radius `r` reaches any lane's rounded box: the distance from
/// `p` to the box (clamped per box axis) is at most `r` plus the lane's reach.
#[inline]
fn hits(b: &Block, p: &[f32x8; 3], r: f32x8) -> bool {
    reached(b, p, r).any()
}

/// Per lane, whether the sphere at `p` of radius `r` reaches the lane's rounded box (a lane
/// mask, see [`hits`]).
#[inline]
fn reached(b: &Block, p: &[f32x8; 3], r: f32x8) -> f32x8 {
    let reach = r + b.reach;
    b.dist2(p).simd_le(reach * reach)
}

/// Packs up to 8 obstacles into a block; missing lanes are far away with reach 0.
fn pack(obstacles: &[Rounded]) -> Block {
    let mut center = [[FAR; LANES]; 3];
    // Padding lanes keep the identity axes, so that their distance is the (huge) distance to
    // `FAR`: zero axes would put every point at distance 0.
    let mut axes: [[[f32; LANES]; 3]; 3] =
        std::array::from_fn(|k| std::array::from_fn(|c| [f32::from(u8::from(k == c)); LANES]));
    let mut half = [[0.0f32; LANES]; 3];
    let mut reach = [0.0f32; LANES];
    for (lane, (world_from_box, h, rounding)) in obstacles.iter().enumerate() {
        let rotation = world_from_box.rotation.to_rotation_matrix();
        for c in 0..3 {
            center[c][lane] = world_from_box.translation.vector[c] as f32;
            half[c][lane] = h[c] as f32;
        }
        for (k, axis) in axes.iter_mut().enumerate() {
            for (c, component) in axis.iter_mut().enumerate() {
                component[lane] = rotation[(c, k)] as f32;
            }
        }
        reach[lane] = *rounding as f32 + SPHERE_SLACK;
    }
    Block {
        center: center.map(f32x8::new),
        axes: axes.map(|a| a.map(f32x8::new)),
        half: half.map(f32x8::new),
        reach: f32x8::new(reach),
    }
}
