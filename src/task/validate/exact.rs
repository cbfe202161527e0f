//! The validator's exact base-pose rule at the grid's boundary, with parry's own queries: a
//! recorded base pose in a cell that the inflated occupancy blocks (or cuts off) is accepted
//! when the robot's footprint there clears every shape by the boundary clearance and a chain
//! of straight moves, each free of contact, joins it to a free cell connected to the start.

use std::collections::{HashMap, HashSet, VecDeque};

use nalgebra::{Isometry3, Vector3};

use super::replay::{Free, Replay};
use crate::scene::collision::parry::math::{Pose, Rotation, Vector};
use crate::scene::collision::parry::query::{self, ShapeCastOptions};
use crate::scene::collision::parry::shape::{Cylinder, SharedShape};
use crate::scene::collision::parry_shape;
use crate::scene::{SceneData, SceneModel, State, forward_kinematics};
use crate::task::Error;

/// Points per side of a cell tried as links of a chain.
const SAMPLES: usize = 7;

/// The shapes in the grid's height band at one state, as parry shapes with world poses and
/// their horizontal bounding boxes `[x0, y0, x1, y1]`, and the robot's footprint: a vertical
/// cylinder of the robot radius spanning the band.
struct Obstacles {
    shapes: Vec<(SharedShape, Pose, [f64; 4])>,
    robot: Cylinder,
    radius: f64,
    z: f64,
}

fn to_pose(iso: &Isometry3<f64>) -> Pose {
    let q = iso.rotation.quaternion();
    let t = iso.translation.vector;
    Pose::from_parts(
        Vector::new(t.x, t.y, t.z),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

impl Obstacles {
    fn at(model: &SceneModel, data: &SceneData, radius: f64) -> Result<Self, Error> {
        let nav = &model.base().nav;
        let mut placed: Vec<(&crate::scene::Shape, Isometry3<f64>)> = model
            .base()
            .shapes
            .iter()
            .map(|b| (&b.shape, b.world_from_shape))
            .collect();
        for p in model.parts() {
            let world_from_part = data.world_from_parts()[p.id().index()];
            for c in p.colliders() {
                placed.push((&c.shape, world_from_part * c.part_from_shape));
            }
        }
        let mut shapes = Vec::new();
        for (shape, world_from_shape) in placed {
            let (compiled, shape_from_parry) = parry_shape(shape)?;
            let pose = to_pose(&(world_from_shape * shape_from_parry));
            let aabb = compiled.compute_aabb(&pose);
            if nav.in_band(aabb.mins.z, aabb.maxs.z) {
                let bounds = [aabb.mins.x, aabb.mins.y, aabb.maxs.x, aabb.maxs.y];
                shapes.push((compiled, pose, bounds));
            }
        }
        let half = 0.5 * (nav.max_height - nav.min_height);
        Ok(Obstacles {
            shapes,
            robot: Cylinder::new(half, radius),
            radius,
            z: nav.min_height + half,
        })
    }

    /// The footprint's pose at `(x, y)` (parry's cylinder axis, y, turned onto z).
    fn pose(&self, [x, y]: [f64; 2]) -> Pose {
        to_pose(&Isometry3::new(
            Vector3::new(x, y, self.z),
            Vector3::x() * std::f64::consts::FRAC_PI_2,
        ))
    }

    /// The shapes whose horizontal box comes within `reach` of the box of `a` and `b`.
    fn near(
        &self,
        a: [f64; 2],
        b: [f64; 2],
        reach: f64,
    ) -> impl Iterator<Item = &(SharedShape, Pose, [f64; 4])> {
        let (x0, y0) = (a[0].min(b[0]) - reach, a[1].min(b[1]) - reach);
        let (x1, y1) = (a[0].max(b[0]) + reach, a[1].max(b[1]) + reach);
        self.shapes
            .iter()
            .filter(move |(_, _, s)| !(s[2] < x0 || s[0] > x1 || s[3] < y0 || s[1] > y1))
    }

    /// Whether the footprint at `p` is farther than `gap` (m) from every shape (a failed
    /// query counts as a contact).
    fn clear(&self, p: [f64; 2], gap: f64) -> bool {
        let pose = self.pose(p);
        self.near(p, p, self.radius + gap + 1e-6).all(|(s, sp, _)| {
            query::distance(&pose, &self.robot, sp, s.as_ref()).is_ok_and(|d| d.distance > gap)
        })
    }

    /// Whether the footprint moving straight from `a` to `b` touches no shape.
    fn path_clear(&self, a: [f64; 2], b: [f64; 2]) -> bool {
        let pose = self.pose(a);
        let velocity = Vector::new(b[0] - a[0], b[1] - a[1], 0.0);
        let options = ShapeCastOptions {
            max_time_of_impact: 1.0,
            target_distance: 0.0,
            stop_at_penetration: true,
            compute_impact_geometry_on_penetration: false,
        };
        self.near(a, b, self.radius + 1e-6).all(|(s, sp, _)| {
            let still = Vector::new(0.0, 0.0, 0.0);
            query::cast_shapes(&pose, velocity, &self.robot, sp, still, s.as_ref(), options)
                .is_ok_and(|hit| hit.is_none())
        })
    }
}

impl Replay<'_> {
    /// Whether base position `xy` is free in exact geometry at `state` (footprint at least
    /// `clearance` from every in-band shape, base and parts) and joined to a cell of `free`
    /// connected to the start: breadth-first over the cells from `xy`'s, each entered at the
    /// first of its `SAMPLES²` points that is clear and reached by a contact-free straight move
    /// from the point the search came from; a free connected cell is entered at its centre.
    pub(super) fn exact_base(
        &mut self,
        state: &State,
        free: &Free,
        xy: [f64; 2],
        clearance: f64,
    ) -> Result<bool, Error> {
        forward_kinematics(self.model, &mut self.data, state)?;
        let obstacles = Obstacles::at(self.model, &self.data, self.radius)?;
        if !obstacles.clear(xy, clearance - 1e-9) {
            return Ok(false);
        }
        let grid = self.model.base_grid();
        let (w, h, res) = (grid.width(), grid.height(), grid.resolution());
        let Some((i, j)) = grid.cell_of(nalgebra::Point2::new(xy[0], xy[1])) else {
            return Ok(false);
        };
        let open = |c: usize| !free.cells.blocked[c] && free.connected[c];
        let mut points: HashMap<usize, Vec<[f64; 2]>> = HashMap::new();
        let mut entered = HashSet::from([j * w + i]);
        let mut queue = VecDeque::from([(j * w + i, xy)]);
        while let Some((c, p)) = queue.pop_front() {
            let (ci, cj) = (c % w, c / w);
            let sides = [
                (ci > 0).then(|| c - 1),
                (ci + 1 < w).then(|| c + 1),
                (cj > 0).then(|| c - w),
                (cj + 1 < h).then(|| c + w),
            ];
            for n in sides.into_iter().flatten() {
                if open(n) {
                    let q = grid.cell_center(n % w, n / w);
                    if obstacles.path_clear(p, [q.x, q.y]) {
                        return Ok(true);
                    }
                    continue;
                }
                if entered.contains(&n) {
                    continue;
                }
                let clear = points.entry(n).or_insert_with(|| {
                    let centre = grid.cell_center(n % w, n / w);
                    let step = res / (SAMPLES - 1) as f64;
                    let off = |m: usize| (m as f64 - (SAMPLES - 1) as f64 / 2.0) * step;
                    (0..SAMPLES * SAMPLES)
                        .map(|k| [centre.x + off(k % SAMPLES), centre.y + off(k / SAMPLES)])
                        .filter(|q| obstacles.clear(*q, 0.0))
                        .collect()
                });
                if let Some(q) = clear.iter().find(|q| obstacles.path_clear(p, **q)) {
                    entered.insert(n);
                    queue.push_back((n, *q));
                }
            }
        }
        Ok(false)
    }
}
