//! Conservative sphere coverings of one collision shape: every point of the solid lies in some
//! sphere of its covering.
//!
//! - **Sphere:** itself.
//! - **Capsule** (radius `r`, segment length `L`): `n ≥ 2` spheres centred on the segment at
//!   spacing `s = L/(n−1)`, endpoints included, of radius `√(r² + (s/2)²)`. A point `p` of the
//!   capsule is within `r` of its nearest segment point `t`; if `t` is an endpoint it is a
//!   centre, otherwise `p − t` is normal to the axis and a centre lies within `s/2` of `t`
//!   along it, so `|p − c|² ≤ r² + s²/4`. With `n = 1`: one sphere of radius `r + L/2`.
//! - **Cylinder** (radius `r`, length `L`): `n` slices of length `L/n`, each inside the sphere
//!   at its centre of radius `√(r² + (L/2n)²)` (the slice's circumscribed sphere); or, if it
//!   gives a smaller total volume, the grid cover of its bounding box.
//! - **Box:** a grid of `nx × ny × nz ≤ n` equal cells, chosen to minimise the cell's
//!   half-diagonal; each cell inside the sphere at its centre of radius its half-diagonal.
//! - **Convex hull:** a grid over the hull's bounding box in its principal axes (the
//!   vertices' covariance eigenvectors), keeping only the cells that parry finds intersecting
//!   the hull (cells grown by [`CELL_SLACK`], so a touching cell is kept). A kept cell's
//!   sphere encloses the candidate vertices of the polytope `cell ∩ hull` (see the `clip`
//!   module): a ball is convex, so it then encloses their convex hull, which is
//!   `cell ∩ hull`. If no candidate is found (round-off at a touching cell), the cell's
//!   circumscribed sphere. Whatever its centre, such a ball covers the cell's part; the centre
//!   is moved inwards from the part's box centre to make the ball reach less far past the
//!   hull's faces (the `clip` module's `inward`). The grids tried are the finest grid of
//!   smallest cells whose kept cells fit the budget (finer grids keep fewer boundary cells
//!   per volume) and slabs across the longest axis, one to three cells across each other
//!   axis, as many as fit (a rod-like link is covered more tightly by balls on its axis than
//!   by a grid's boundary cells); the one kept has the least largest overshoot past a face
//!   (radius less the centre's depth in the hull). On the Panda's link hulls at 12 spheres
//!   this halves the overshoot (largest per link 1.9–4.0 cm against 4.0–7.8 cm for the box
//!   centres of the smallest-cell grid).

use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, SymmetricEigen, UnitQuaternion, Vector3};
use parry3d_f64::query::intersection_test;
use parry3d_f64::shape::Cuboid;

use super::Sphere;
use super::clip::Polytope;
use crate::scene::Shape;
use crate::scene::collision::convert;
use crate::scene::collision::parry_shape;

/// How much (m) a grid cell is grown on every side before parry's intersection test with a
/// hull, so that cells the hull only touches (or misses by round-off) are kept.
pub const CELL_SLACK: f64 = 1e-7;

/// Finer grids tried for a hull, as multiples of the budget (the cells kept must still fit).
const HULL_REFINEMENTS: [usize; 5] = [1, 2, 4, 8, 16];

/// A covering of `shape` (in its own frame) by at most `budget ≥ 1` spheres.
///
/// # Errors
/// The message of parry's failure to build a convex mesh's hull.
pub(super) fn cover(shape: &Shape, budget: usize) -> Result<Vec<Sphere>, String> {
    let budget = budget.max(1);
    Ok(match shape {
        Shape::Sphere { radius } => vec![Sphere::new(Point3::origin(), *radius)],
        Shape::Capsule { radius, length } => capsule(*radius, *length, budget),
        Shape::Cylinder { radius, length } => {
            let slices = cylinder_slices(*radius, *length, budget);
            let half = Vector3::new(*radius, *radius, length / 2.0);
            let grid = grid_cover(&Isometry3::identity(), &half, budget, &whole_cell);
            if total_volume(&grid) < total_volume(&slices) {
                grid
            } else {
                slices
            }
        }
        Shape::Cuboid { half_extents } => {
            grid_cover(&Isometry3::identity(), half_extents, budget, &whole_cell)
        }
        Shape::ConvexMesh { vertices, .. } => hull(shape, vertices, budget)?,
    })
}

fn capsule(radius: f64, length: f64, n: usize) -> Vec<Sphere> {
    if n == 1 {
        return vec![Sphere::new(Point3::origin(), radius + length / 2.0)];
    }
    let spacing = length / (n - 1) as f64;
    let r = radius.hypot(spacing / 2.0);
    (0..n)
        .map(|i| Sphere::new(Point3::new(0.0, 0.0, -length / 2.0 + i as f64 * spacing), r))
        .collect()
}

fn cylinder_slices(radius: f64, length: f64, n: usize) -> Vec<Sphere> {
    let slice = length / n as f64;
    let r = radius.hypot(slice / 2.0);
    (0..n)
        .map(|i| {
            let z = -length / 2.0 + (i as f64 + 0.5) * slice;
            Sphere::new(Point3::new(0.0, 0.0, z), r)
        })
        .collect()
}

fn total_volume(spheres: &[Sphere]) -> f64 {
    spheres.iter().map(|s| s.radius.powi(3)).sum()
}

/// The sphere covering the shape's part in a cell (pose, half extents), `None` if it misses
/// (or, with another `T`, what a cell gives: `()` to count the cells kept).
type CellFit<'a, T = Sphere> = dyn Fn(&Isometry3<f64>, &Vector3<f64>) -> Option<T> + 'a;

/// The cell counts `(nx, ny, nz)`, product at most `budget`, that minimise the half-diagonal
/// of a cell of the box with half extents `half`.
fn grid_dims(half: &Vector3<f64>, budget: usize) -> [usize; 3] {
    let mut best = ([1, 1, 1], f64::INFINITY);
    for nx in 1..=budget {
        for ny in 1..=budget / nx {
            let nz = budget / (nx * ny);
            let d = (half.x / nx as f64).powi(2)
                + (half.y / ny as f64).powi(2)
                + (half.z / nz as f64).powi(2);
            if d < best.1 {
                best = ([nx, ny, nz], d);
            }
        }
    }
    best.0
}

/// The grid cover of the box `shape_from_box` with half extents `half` by at most `budget`
/// cells; `fit(cell_pose, cell_half)` gives the sphere covering the shape's part in a cell,
/// or `None` when the cell misses the shape.
fn grid_cover(
    shape_from_box: &Isometry3<f64>,
    half: &Vector3<f64>,
    budget: usize,
    fit: &CellFit<'_>,
) -> Vec<Sphere> {
    grid_cells(shape_from_box, half, grid_dims(half, budget), fit)
}

/// What `fit` gives for each cell of an `n[0] × n[1] × n[2]` grid of equal cells over the box
/// `shape_from_box` with half extents `half` (see [`grid_cover`]), the `None`s left out.
fn grid_cells<T>(
    shape_from_box: &Isometry3<f64>,
    half: &Vector3<f64>,
    n: [usize; 3],
    fit: &CellFit<'_, T>,
) -> Vec<T> {
    let cell_half = Vector3::new(
        half.x / n[0] as f64,
        half.y / n[1] as f64,
        half.z / n[2] as f64,
    );
    let mut spheres = Vec::new();
    for i in 0..n[0] {
        for j in 0..n[1] {
            for k in 0..n[2] {
                let local = Vector3::new(
                    -half.x + (2 * i + 1) as f64 * cell_half.x,
                    -half.y + (2 * j + 1) as f64 * cell_half.y,
                    -half.z + (2 * k + 1) as f64 * cell_half.z,
                );
                let cell = shape_from_box * nalgebra::Translation3::from(local);
                spheres.extend(fit(&cell, &cell_half));
            }
        }
    }
    spheres
}

/// The sphere circumscribing a whole cell: its centre, its half-diagonal.
fn whole_cell(cell: &Isometry3<f64>, half: &Vector3<f64>) -> Option<Sphere> {
    Some(Sphere::new(
        Point3::from(cell.translation.vector),
        half.norm(),
    ))
}

/// The cover of a convex hull by a grid in its principal axes: of the candidate grids whose
/// kept cells fit `budget` (the module's list), the one whose balls reach least far past the
/// hull's faces.
fn hull(shape: &Shape, vertices: &[Point3<f64>], budget: usize) -> Result<Vec<Sphere>, String> {
    let (compiled, shape_from_parry) = parry_shape(shape).map_err(|e| e.to_string())?;
    let hull_pose = convert::pose(&shape_from_parry);
    let polytope = compiled
        .as_convex_polyhedron()
        .map(|p| Polytope::new(p, &shape_from_parry));
    let meets = |cell: &Isometry3<f64>, half: &Vector3<f64>| {
        let cuboid = Cuboid::new(convert::vector(&half.add_scalar(CELL_SLACK)));
        intersection_test(&convert::pose(cell), &cuboid, &hull_pose, &*compiled)
            .map(|i| i.intersecting)
            .unwrap_or(true)
    };
    // The cells a grid keeps (counted without their spheres).
    let kept = |cell: &Isometry3<f64>, half: &Vector3<f64>| meets(cell, half).then_some(());
    let fit = |cell: &Isometry3<f64>, half: &Vector3<f64>| {
        if !meets(cell, half) {
            return None;
        }
        polytope
            .as_ref()
            .and_then(|p| p.sphere_in_cell(cell, half))
            .or_else(|| whole_cell(cell, half))
    };
    let (shape_from_box, half) = principal_box(vertices);
    let fits = |dims: [usize; 3]| grid_cells(&shape_from_box, &half, dims, &kept).len() <= budget;
    // Candidate grids: the finest smallest-cell grid whose kept cells fit the budget, and
    // slabs across the box's longest axis (one to three cells across each other axis, as many
    // slabs as fit).
    let mut candidates = vec![grid_dims(&half, budget)];
    for factor in &HULL_REFINEMENTS[1..] {
        let finer = grid_dims(&half, budget * factor);
        if !fits(finer) {
            break;
        }
        candidates[0] = finer;
    }
    let long = half.imax();
    let (a, b) = ((long + 1) % 3, (long + 2) % 3);
    for (na, nb) in [(1, 1), (1, 2), (2, 1), (2, 2), (1, 3), (3, 1)] {
        let slabs = |n: usize| {
            let mut dims = [1; 3];
            dims[long] = n;
            dims[a] = na;
            dims[b] = nb;
            dims
        };
        // Each slab keeps at least one cell, so at most `budget` slabs fit.
        if let Some(n) = (1..=budget).take_while(|&n| fits(slabs(n))).last() {
            candidates.push(slabs(n));
        }
    }
    // The candidate whose balls reach least far past the hull's faces.
    let Some(polytope) = &polytope else {
        return Ok(grid_cells(&shape_from_box, &half, candidates[0], &fit));
    };
    let excess = |spheres: &[Sphere]| {
        spheres
            .iter()
            .map(|s| polytope.overshoot(s))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    Ok(candidates
        .into_iter()
        .map(|dims| grid_cells(&shape_from_box, &half, dims, &fit))
        .map(|cover| (excess(&cover), cover))
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, cover)| cover)
        .unwrap_or_default())
}

/// The bounding box of `vertices` in their principal axes: its pose in the shape frame and its
/// half extents.
fn principal_box(vertices: &[Point3<f64>]) -> (Isometry3<f64>, Vector3<f64>) {
    let n = vertices.len().max(1) as f64;
    let mean = vertices.iter().map(|v| v.coords).sum::<Vector3<f64>>() / n;
    let covariance = vertices
        .iter()
        .map(|v| (v.coords - mean) * (v.coords - mean).transpose())
        .sum::<Matrix3<f64>>()
        / n;
    let mut axes = SymmetricEigen::new(covariance).eigenvectors;
    if axes.determinant() < 0.0 {
        axes.set_column(2, &(-axes.column(2)));
    }
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(axes));
    let mut lo = Vector3::repeat(f64::INFINITY);
    let mut hi = Vector3::repeat(f64::NEG_INFINITY);
    for v in vertices {
        let local = rotation.inverse() * v.coords;
        lo = lo.inf(&local);
        hi = hi.sup(&local);
    }
    let center = rotation * ((lo + hi) / 2.0);
    (
        Isometry3::from_parts(center.into(), rotation),
        (hi - lo) / 2.0,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points of a box's surface grid and interior all lie in its cover (corners included:
    /// the cells' corners are the farthest points from their centres).
    #[test]
    fn box_cover_contains_its_corners_and_fits_the_budget() {
        let half = Vector3::new(0.3, 0.1, 0.05);
        for budget in [1, 2, 5, 12] {
            let spheres = cover(&Shape::cuboid(half), budget).unwrap();
            assert!(spheres.len() <= budget && !spheres.is_empty());
            for sx in [-1.0, -0.5, 0.0, 0.5, 1.0] {
                for sy in [-1.0, 0.0, 1.0] {
                    for sz in [-1.0, 1.0] {
                        let p = Point3::new(sx * half.x, sy * half.y, sz * half.z);
                        assert!(spheres.iter().any(|s| s.contains(&p, 1e-12)), "{p}");
                    }
                }
            }
        }
    }

    /// A 12-sphere box cover is tighter than the box's bounding sphere: its largest radius is
    /// the half-diagonal of a `6 × 2 × 1` cell, `√(0.05² + 0.05² + 0.05²)` (by hand).
    #[test]
    fn box_grid_is_the_one_with_the_smallest_cell() {
        let spheres = cover(&Shape::cuboid(Vector3::new(0.3, 0.1, 0.05)), 12).unwrap();
        assert_eq!(spheres.len(), 12);
        let r = spheres.iter().map(|s| s.radius).fold(0.0, f64::max);
        assert!((r - 0.05 * 3f64.sqrt()).abs() < 1e-12, "{r}");
    }

    /// The cube `[−0.05, 0.05]³` as a hull.
    fn cube_hull() -> Shape {
        let vertices = (0..8)
            .map(|k| {
                let c = |bit: usize| if k & (1 << bit) == 0 { -0.05 } else { 0.05 };
                Point3::new(c(0), c(1), c(2))
            })
            .collect();
        Shape::ConvexMesh {
            vertices,
            source: None,
        }
    }

    /// A cell holding a 1 cm slice of the cube at its `x = 0.05` face: the cell spans
    /// `x ∈ [0.04, 0.14]`, `y, z ∈ [−0.05, 0.05]`. The slice's box-centred ball (centre
    /// `x = 0.045`, radius `√(0.005² + 2·0.05²)` = 0.0709, depth 0.005) reaches 0.0659 m past
    /// the face. By hand, the ball centred at `(c, 0, 0)` enclosing the slice reaches
    /// `√((0.05 − c)² + 2·0.05²) − (0.05 − |c|)` past the faces (for `|c| ≤ 0.04`), least at
    /// `c = 0`: `√3·0.05 − 0.05` = 0.0366 m. The moved ball comes within 1 mm of that and
    /// still holds the slice's eight corners.
    #[test]
    fn a_face_slice_s_ball_is_moved_inwards() {
        let shape = cube_hull();
        let (compiled, shape_from_parry) = parry_shape(&shape).unwrap();
        let polytope = Polytope::new(compiled.as_convex_polyhedron().unwrap(), &shape_from_parry);
        let cell = Isometry3::translation(0.09, 0.0, 0.0);
        let ball = polytope
            .sphere_in_cell(&cell, &Vector3::repeat(0.05))
            .unwrap();
        let reach = polytope.overshoot(&ball);
        let best = 3f64.sqrt() * 0.05 - 0.05;
        assert!(
            reach >= best - 1e-9 && reach <= best + 1e-3,
            "{reach} vs {best}"
        );
        for k in 0..8 {
            let c = |bit: usize, lo: f64, hi: f64| if k & (1 << bit) == 0 { lo } else { hi };
            let corner = Point3::new(c(0, 0.04, 0.05), c(1, -0.05, 0.05), c(2, -0.05, 0.05));
            assert!(ball.contains(&corner, 1e-12), "{corner}");
        }
    }

    /// A hull's cover holds every point of the hull: of a 21³ grid over an irregular hull's
    /// box, the points inside the hull (inside every half-space of the faces parry found) each
    /// lie in some sphere, at every budget.
    #[test]
    fn a_hull_cover_holds_the_hull() {
        // An irregular hull: a rod bent at one end and a few stray points.
        let mut vertices: Vec<Point3<f64>> = (0..8)
            .map(|k| {
                let c = |bit: usize, h: f64| if k & (1 << bit) == 0 { -h } else { h };
                Point3::new(c(0, 0.04), c(1, 0.05), c(2, 0.15))
            })
            .collect();
        vertices.extend([
            Point3::new(0.09, 0.0, 0.17),
            Point3::new(0.07, 0.03, 0.19),
            Point3::new(-0.05, -0.06, -0.1),
        ]);
        let shape = Shape::ConvexMesh {
            vertices,
            source: None,
        };
        let (compiled, shape_from_parry) = parry_shape(&shape).unwrap();
        let polytope = Polytope::new(compiled.as_convex_polyhedron().unwrap(), &shape_from_parry);
        for budget in [1, 4, 12, 30] {
            let spheres = cover(&shape, budget).unwrap();
            assert!(!spheres.is_empty() && spheres.len() <= budget);
            let mut inside = 0;
            for i in 0..=20 {
                for j in 0..=20 {
                    for k in 0..=20 {
                        let p = Point3::new(
                            -0.06 + 0.16 * f64::from(i) / 20.0,
                            -0.07 + 0.14 * f64::from(j) / 20.0,
                            -0.16 + 0.36 * f64::from(k) / 20.0,
                        );
                        if !polytope.holds(&p) {
                            continue;
                        }
                        inside += 1;
                        assert!(
                            spheres.iter().any(|s| s.contains(&p, 1e-9)),
                            "budget {budget}: {p} is outside every sphere"
                        );
                    }
                }
            }
            assert!(inside > 1000, "{inside}");
        }
    }

    /// The capsule's end caps: the points on the axis at `±(L/2 + r)` and the rim points
    /// between two centres are covered.
    #[test]
    fn capsule_cover_reaches_the_caps() {
        let (r, l) = (0.05, 0.4);
        for n in 1..6 {
            let spheres = cover(
                &Shape::Capsule {
                    radius: r,
                    length: l,
                },
                n,
            )
            .unwrap();
            for z in [-(l / 2.0 + r), l / 2.0 + r, 0.0, 0.07, -0.13] {
                let p = Point3::new(0.0, 0.0, z);
                assert!(spheres.iter().any(|s| s.contains(&p, 1e-12)), "n {n} z {z}");
                let rim = Point3::new(r, 0.0, z.clamp(-l / 2.0, l / 2.0));
                assert!(
                    spheres.iter().any(|s| s.contains(&rim, 1e-12)),
                    "n {n} z {z}"
                );
            }
        }
    }
}
