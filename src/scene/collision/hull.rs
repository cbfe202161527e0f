//! Support points of a convex hull by walking its edges: the same point as parry's scan of
//! every vertex, found by visiting a few ([`HullGraph`], [`Walk`]).
//!
//! **Why.** parry's `ConvexPolyhedron` finds a support point (the vertex farthest along a
//! direction) by scanning all its vertices; GJK asks for one per iteration. For the robot's
//! mesh hulls (about a hundred vertices each) the scans were a fifth of all planning
//! instructions of the arm check.
//!
//! **Answer.** parry's scan returns the first vertex (lowest index) of largest computed
//! `p · d`. [`HullGraph::support_id`] returns that same index, so parry's GJK run on a
//! [`Walk`] does the same arithmetic on the same points as on the hull itself and returns the
//! same distance, bit for bit. *Argument.* On the surface of a convex polytope, the vertices
//! with `p · d >= c` span a connected part of its edge graph for every `c` (a superlevel set
//! of a linear function on a convex surface is a disk or all of it; a face's vertices above
//! `c` are a contiguous run of its boundary). The walk climbs to a vertex `v` with no
//! neighbour of larger computed value, then explores every vertex connected to `v` through
//! vertices of computed value at least `v · d − τ|d|`, and returns the first vertex of largest
//! value among them. With `τ` far above the rounding of a dot product (about `1e-16·|p||d|`),
//! the set explored contains every vertex whose exact value is within `τ|d|/2` of `v`'s, so
//! the whole connected superlevel set that holds the true maximisers and the vertices whose
//! rounded value ties with or beats `v`'s. The hull parry builds is convex up to round-off: a
//! hull whose vertices rise above one of its triangles' planes by more than a thousandth of
//! `τ` gets no graph (parry's scan is used), and so does one whose hull cannot be rebuilt
//! with the same vertices, or a direction that is not finite. The test
//! `hull_walk_finds_the_scanned_support_point` compares both on every robot hull.

use std::cell::Cell;

use parry3d_f64::math::Vector;
use parry3d_f64::shape::{ConvexPolyhedron, SupportMap};
use parry3d_f64::utils::point_cloud_support_point_id;

/// Plateau tolerance `τ` per metre of the hull's radius (see the module's argument).
const PLATEAU: f64 = 1e-9;

/// The most vertices a plateau exploration holds before it gives up for parry's scan.
const PLATEAU_CAPACITY: usize = 64;

/// The edge graph of a convex hull's triangulated surface, as adjacency lists.
#[derive(Debug, Clone)]
pub(crate) struct HullGraph {
    /// Per vertex, its first neighbour in `neighbours`; one more entry, the total.
    starts: Vec<u32>,
    neighbours: Vec<u32>,
    /// `τ` (m): the plateau tolerance per unit of `|d|`.
    tolerance: f64,
    /// Per cell of [`seed_cell`], the support vertex of the cell's direction: where a walk
    /// starts.
    seeds: [u32; 27],
}

impl HullGraph {
    /// The graph of `hull` built by parry from `input` (`ConvexPolyhedron::from_convex_hull`
    /// of the same points): parry's hull triangles are rebuilt from `input`, and used only if
    /// their vertices are `hull`'s, bit for bit and in the same order, every vertex is on an
    /// edge, and the surface is convex to within a thousandth of the plateau tolerance
    /// (`None` otherwise: parry's scan stays).
    pub(crate) fn new(input: &[Vector], hull: &ConvexPolyhedron) -> Option<HullGraph> {
        let (points, triangles) = parry3d_f64::transformation::try_convex_hull(input).ok()?;
        let same = points.len() == hull.points().len()
            && points
                .iter()
                .zip(hull.points())
                .all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits));
        if !same || points.len() > u32::MAX as usize {
            return None;
        }
        let radius = points.iter().map(|p| p.length()).fold(0.0, f64::max);
        let tolerance = PLATEAU * radius.max(1e-3);
        if rise_above_faces(&points, &triangles) > tolerance * 1e-3 {
            return None;
        }
        let mut adjacent: Vec<Vec<u32>> = vec![Vec::new(); points.len()];
        for t in &triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                for (x, y) in [(a, b), (b, a)] {
                    let list = adjacent.get_mut(x as usize)?;
                    if !list.contains(&y) {
                        list.push(y);
                    }
                }
            }
        }
        if adjacent.iter().any(Vec::is_empty) {
            return None;
        }
        let mut starts = Vec::with_capacity(points.len() + 1);
        let mut neighbours = Vec::new();
        for list in &adjacent {
            starts.push(neighbours.len() as u32);
            neighbours.extend_from_slice(list);
        }
        starts.push(neighbours.len() as u32);
        let seeds = std::array::from_fn(|cell| {
            let axis = |k: u32| f64::from((cell as u32 / 3u32.pow(k)) % 3) - 1.0;
            let dir = Vector::new(axis(0), axis(1), axis(2));
            point_cloud_support_point_id(dir, &points) as u32
        });
        Some(HullGraph {
            starts,
            neighbours,
            tolerance,
            seeds,
        })
    }

    fn neighbours(&self, v: usize) -> &[u32] {
        &self.neighbours[self.starts[v] as usize..self.starts[v + 1] as usize]
    }

    /// parry's support vertex of `points` (the hull's) along `dir`: the first index of largest
    /// `p · dir` (see the module's answer), walking from vertex `start` or from the support
    /// vertex of the nearest of 26 directions precomputed, whichever is farther along `dir`.
    pub(crate) fn support_id(&self, points: &[Vector], dir: Vector, start: usize) -> usize {
        let dot = |i: usize| points[i].dot(dir);
        let seed = self.seeds[seed_cell(dir)] as usize;
        let start = start.min(points.len() - 1);
        let (mut best, mut best_dot) = (seed, dot(seed));
        let d = dot(start);
        if d > best_dot {
            (best, best_dot) = (start, d);
        }
        if !(best_dot.is_finite() && dir.is_finite()) {
            return point_cloud_support_point_id(dir, points);
        }
        loop {
            // The largest value among the neighbours not above `best_dot`.
            let (mut next, mut below) = (best, f64::NEG_INFINITY);
            for &n in self.neighbours(best) {
                let d = dot(n as usize);
                if d > best_dot {
                    best_dot = d;
                    next = n as usize;
                } else if d > below {
                    below = d;
                }
            }
            if next == best {
                // A local maximum: `below` is its neighbours' largest value. The 1-norm of
                // `dir` is at least its length (a lower floor only explores more).
                let floor = best_dot - self.tolerance * (dir.x.abs() + dir.y.abs() + dir.z.abs());
                if below < floor {
                    return best;
                }
                return self
                    .plateau(points, dir, best, floor)
                    .unwrap_or_else(|| point_cloud_support_point_id(dir, points));
            }
            best = next;
        }
    }

    /// The first vertex of largest `p · dir` among those connected to `from` through vertices
    /// with `p · dir >= floor`; `None` when there are more than [`PLATEAU_CAPACITY`].
    fn plateau(&self, points: &[Vector], dir: Vector, from: usize, floor: f64) -> Option<usize> {
        let mut seen = [0u32; PLATEAU_CAPACITY];
        seen[0] = from as u32;
        let (mut len, mut next) = (1, 0);
        while next < len {
            let v = seen[next] as usize;
            next += 1;
            for &n in self.neighbours(v) {
                if points[n as usize].dot(dir) >= floor && !seen[..len].contains(&n) {
                    *seen.get_mut(len)? = n;
                    len += 1;
                }
            }
        }
        let mut best = seen[0] as usize;
        let mut best_dot = points[best].dot(dir);
        for &v in &seen[1..len] {
            let (v, d) = (v as usize, points[v as usize].dot(dir));
            if d > best_dot || d == best_dot && v < best {
                best = v;
                best_dot = d;
            }
        }
        Some(best)
    }
}

/// The cell of `dir` among the 27 of `{−1, 0, 1}³` (a component counts as `±1` when its
/// magnitude is over half the largest): `Σ_k (c_k + 1)·3^k`. Any cell for a non-finite `dir`.
fn seed_cell(dir: Vector) -> usize {
    let m = 0.5 * dir.x.abs().max(dir.y.abs()).max(dir.z.abs());
    let c = |v: f64| usize::from(v >= -m) + usize::from(v > m);
    c(dir.x) + 3 * c(dir.y) + 9 * c(dir.z)
}

/// The most any point rises above the plane of any triangle (m; outward unit normals), `+∞`
/// for a degenerate triangle: 0 for an exactly convex surface.
fn rise_above_faces(points: &[Vector], triangles: &[[u32; 3]]) -> f64 {
    let mut rise: f64 = 0.0;
    for t in triangles {
        let [a, b, c] = t.map(|i| points[i as usize]);
        let Some(n) = (b - a).cross(c - a).try_normalize() else {
            return f64::INFINITY;
        };
        for p in points {
            rise = rise.max(n.dot(*p - a));
        }
    }
    rise
}

/// A hull's points with its graph, as a parry [`SupportMap`] for one query: the walk starts
/// from the vertex the previous support point of the same query was (GJK's directions change
/// little from one iteration to the next).
pub(crate) struct Walk<'a> {
    points: &'a [Vector],
    graph: &'a HullGraph,
    last: Cell<usize>,
}

impl<'a> Walk<'a> {
    /// The walk over `hull`'s points with `graph` (built from `hull`).
    pub(crate) fn new(hull: &'a ConvexPolyhedron, graph: &'a HullGraph) -> Self {
        Walk {
            points: hull.points(),
            graph,
            last: Cell::new(0),
        }
    }
}

impl SupportMap for Walk<'_> {
    fn local_support_point(&self, dir: Vector) -> Vector {
        let id = self.graph.support_id(self.points, dir, self.last.get());
        self.last.set(id);
        self.points[id]
    }
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    /// Seeded point clouds: points on a sphere (no ties), a box's surface on a grid and a
    /// prism with many coplanar points (whole faces tie for directions along their normals:
    /// the plateau case), and a thin sliver.
    fn clouds(rng: &mut ChaCha8Rng) -> Vec<Vec<Vector>> {
        let sphere = (0..300)
            .map(|_| {
                let v = Vector::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                v.normalize() * 0.12
            })
            .collect();
        let mut grid = Vec::new();
        for i in 0..=4 {
            for j in 0..=4 {
                for k in 0..=4 {
                    if [i, j, k].iter().any(|&c| c == 0 || c == 4) {
                        grid.push(Vector::new(i as f64, j as f64, k as f64) * 0.05);
                    }
                }
            }
        }
        let mut prism = Vec::new();
        for s in 0..24 {
            let a = s as f64 * std::f64::consts::TAU / 24.0;
            for z in [-0.1, 0.0, 0.1] {
                prism.push(Vector::new(0.06 * a.cos(), 0.06 * a.sin(), z));
            }
        }
        let sliver = (0..60)
            .map(|_| {
                Vector::new(
                    rng.random_range(-0.2..0.2),
                    rng.random_range(-0.01..0.01),
                    rng.random_range(-1e-3..1e-3),
                )
            })
            .collect();
        vec![sphere, grid, prism, sliver]
    }

    /// Directions: random, the axes, every hull triangle's normal (ties across whole faces),
    /// and those turned by a hair (near-ties).
    fn directions(hull: &ConvexPolyhedron, rng: &mut ChaCha8Rng) -> Vec<Vector> {
        let mut dirs: Vec<Vector> = (0..4000)
            .map(|_| {
                Vector::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                )
            })
            .collect();
        for axis in [Vector::X, Vector::Y, Vector::Z] {
            dirs.extend([axis, -axis, axis * 3.0]);
        }
        for face in hull.faces() {
            for eps in [0.0, 1e-15, 1e-12, 1e-9] {
                let hair = Vector::new(
                    rng.random_range(-eps..=eps),
                    rng.random_range(-eps..=eps),
                    rng.random_range(-eps..=eps),
                );
                dirs.push(face.normal + hair);
            }
        }
        dirs
    }

    /// The walk returns parry's scanned support vertex (same index) for every direction and
    /// several starting vertices on every cloud, each of which gets a graph.
    #[test]
    fn hull_walk_finds_the_scanned_support_point() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for (c, cloud) in clouds(&mut rng).into_iter().enumerate() {
            let hull = ConvexPolyhedron::from_convex_hull(&cloud).unwrap();
            let graph = HullGraph::new(&cloud, &hull).unwrap_or_else(|| panic!("cloud {c}"));
            let points = hull.points();
            for dir in directions(&hull, &mut rng) {
                let scanned = point_cloud_support_point_id(dir, points);
                for start in [0, points.len() / 2, points.len() - 1, scanned] {
                    assert_eq!(
                        graph.support_id(points, dir, start),
                        scanned,
                        "cloud {c}, direction {dir:?}, start {start}"
                    );
                }
            }
        }
    }

    /// A non-finite direction gets parry's scan (no walk over NaN comparisons).
    #[test]
    fn hull_walk_takes_the_scan_for_non_finite_directions() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let cloud = clouds(&mut rng).swap_remove(0);
        let hull = ConvexPolyhedron::from_convex_hull(&cloud).unwrap();
        let graph = HullGraph::new(&cloud, &hull).unwrap();
        for dir in [
            Vector::new(f64::NAN, 0.0, 1.0),
            Vector::splat(f64::INFINITY),
        ] {
            let scanned = point_cloud_support_point_id(dir, hull.points());
            assert_eq!(graph.support_id(hull.points(), dir, 5), scanned);
        }
    }
}
