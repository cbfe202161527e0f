//! Point-cloud geometry used by the exploration loop and the registration: neighbourhoods,
//! robust plane fits (PCA), nearest-neighbour displacement and oriented bounding boxes.

use std::collections::HashMap;

use nalgebra::{
    Isometry3, Matrix3, Point3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3,
};

/// A uniform voxel hash over points for fixed-radius queries (cell edge = the query radius).
#[derive(Debug, Clone)]
pub(crate) struct VoxelIndex<'a> {
    points: &'a [Point3<f64>],
    cell: f64,
    cells: HashMap<[i64; 3], Vec<usize>>,
}

impl<'a> VoxelIndex<'a> {
    /// Indexes `points` with cells of edge `cell` (m, > 0).
    pub(crate) fn new(points: &'a [Point3<f64>], cell: f64) -> Self {
        let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (k, p) in points.iter().enumerate() {
            cells.entry(key(p, cell)).or_default().push(k);
        }
        VoxelIndex {
            points,
            cell,
            cells,
        }
    }

    /// Distance from `q` to its nearest indexed point, capped at the cell edge (points farther
    /// than one cell may be missed, so everything beyond counts as "one cell away").
    pub(crate) fn nearest_capped(&self, q: &Point3<f64>) -> f64 {
        let mut best = self.cell;
        self.for_each_near(q, |p| best = best.min((p - q).norm()));
        best
    }

    /// Calls `f` for every point within one cell (per axis) of `q`'s cell.
    fn for_each_near(&self, q: &Point3<f64>, mut f: impl FnMut(&Point3<f64>)) {
        let [i, j, k] = key(q, self.cell);
        for di in -1..=1 {
            for dj in -1..=1 {
                for dk in -1..=1 {
                    if let Some(list) = self.cells.get(&[i + di, j + dj, k + dk]) {
                        for &n in list {
                            f(&self.points[n]);
                        }
                    }
                }
            }
        }
    }
}

fn key(p: &Point3<f64>, cell: f64) -> [i64; 3] {
    [
        (p.x / cell).floor() as i64,
        (p.y / cell).floor() as i64,
        (p.z / cell).floor() as i64,
    ]
}

/// The points of `points` within `radius` of `center`.
pub(crate) fn neighbourhood(
    points: &[Point3<f64>],
    center: &Point3<f64>,
    radius: f64,
) -> Vec<Point3<f64>> {
    let r2 = radius * radius;
    points
        .iter()
        .filter(|p| (*p - center).norm_squared() <= r2)
        .copied()
        .collect()
}

/// Mean and covariance of a point set (empty: `None`).
fn moments(points: &[Point3<f64>]) -> Option<(Point3<f64>, Matrix3<f64>)> {
    if points.is_empty() {
        return None;
    }
    let n = points.len() as f64;
    let mean = points.iter().fold(Vector3::zeros(), |s, p| s + p.coords) / n;
    let cov = points.iter().fold(Matrix3::zeros(), |s, p| {
        let d = p.coords - mean;
        s + d * d.transpose()
    }) / n;
    Some((Point3::from(mean), cov))
}

/// Eigenvectors of a symmetric 3×3 matrix as columns of a rotation, sorted by decreasing
/// eigenvalue, with the eigenvalues.
fn principal_axes(cov: &Matrix3<f64>) -> (Rotation3<f64>, Vector3<f64>) {
    let eig = cov.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let e0 = eig.eigenvectors.column(order[0]).into_owned();
    let e1 = eig.eigenvectors.column(order[1]).into_owned();
    // A right-handed frame: the third axis from the cross product.
    let e2 = e0.cross(&e1);
    let m = Matrix3::from_columns(&[e0, e1, e2]);
    let values = Vector3::new(
        eig.eigenvalues[order[0]],
        eig.eigenvalues[order[1]],
        eig.eigenvalues[order[2]],
    );
    (Rotation3::from_matrix_unchecked(m), values)
}

/// A plane fitted to points: a point on it and its unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Plane {
    /// The centroid of the inliers.
    pub point: Point3<f64>,
    /// Unit normal (sign as requested by the caller).
    pub normal: Unit<Vector3<f64>>,
}

/// Robust plane fit: PCA of `points` (normal = eigenvector of the smallest eigenvalue), then
/// one refit on the points within `inlier_distance` of that plane (drops a handle knob, an
/// edge of a neighbouring surface, outliers). `None` with fewer than `min_points` points
/// (before or after the refit). The normal is oriented towards `towards`.
pub(crate) fn fit_plane(
    points: &[Point3<f64>],
    min_points: usize,
    inlier_distance: f64,
    towards: &Point3<f64>,
) -> Option<Plane> {
    let min_points = min_points.max(3);
    if points.len() < min_points {
        return None;
    }
    let (mean, cov) = moments(points)?;
    let (axes, _) = principal_axes(&cov);
    let n = axes.matrix().column(2).into_owned();
    let inliers: Vec<Point3<f64>> = points
        .iter()
        .filter(|p| (*p - mean).dot(&n).abs() <= inlier_distance)
        .copied()
        .collect();
    if inliers.len() < min_points {
        return None;
    }
    let (mean, cov) = moments(&inliers)?;
    let (axes, values) = principal_axes(&cov);
    // Collinear inliers do not define a plane.
    if values[1] <= 1e-12 {
        return None;
    }
    let mut normal = axes.matrix().column(2).into_owned();
    if (towards - mean).dot(&normal) < 0.0 {
        normal = -normal;
    }
    Some(Plane {
        point: mean,
        normal: Unit::new_normalize(normal),
    })
}

/// Mean distance from each of `points` to its nearest neighbour in `index`, each distance
/// capped at the index's cell edge. `None` for an empty `points`.
pub(crate) fn mean_nearest_distance(points: &[Point3<f64>], index: &VoxelIndex<'_>) -> Option<f64> {
    if points.is_empty() {
        return None;
    }
    let sum: f64 = points.iter().map(|p| index.nearest_capped(p)).sum();
    Some(sum / points.len() as f64)
}

/// An oriented box: centre, orientation (world from box axes) and half extents.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct OrientedBox {
    /// Box centre, world frame.
    pub center: Point3<f64>,
    /// World from box axes.
    pub rotation: UnitQuaternion<f64>,
    /// Half extents along the box axes (m).
    pub half_extents: Vector3<f64>,
}

impl OrientedBox {
    /// World from box frame: the centre and the box axes.
    pub fn world_from_box(&self) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::from(self.center.coords), self.rotation)
    }
}

/// The oriented bounding box of `points` with one axis along `axis` (unit): the orientation
/// about it minimises the area of the trimmed bounding rectangle of the points projected on
/// the plane normal to it (1° grid over 180°, then 0.1° around the best). A front's edges run
/// along its joint's axis (a door's hinge edge) or across it (a drawer front across its
/// slide), so its box is aligned with the axis rather than with the sampled points (PCA's axes
/// tilt by a few degrees with uneven sampling density and when one edge is seen better than
/// the other, and a tilted box reaches past the hinge). Extents are the `trim` and `1 - trim`
/// quantiles of the projections on each axis (`trim = 0`: the exact extents; a small `trim`
/// ignores stray outliers), each half extent at least `min_half_extent` (a front seen from one
/// side is flat); an extent padded up to it grows away from `outward` (unit, the surface's
/// outward normal, when given) when its axis is within 45° of it: the points are the surface
/// the camera saw, and the solid lies behind it. `None` for fewer than 4 points or a zero
/// axis.
pub(crate) fn oriented_box_along(
    points: &[Point3<f64>],
    axis: &Vector3<f64>,
    outward: Option<&Vector3<f64>>,
    trim: f64,
    min_half_extent: f64,
) -> Option<OrientedBox> {
    if points.len() < 4 {
        return None;
    }
    let axis = axis.try_normalize(1e-12)?;
    let mean = Point3::from(
        points.iter().fold(Vector3::zeros(), |s, p| s + p.coords) / points.len() as f64,
    );
    let helper = if axis.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e0 = axis.cross(&helper).normalize();
    let e1 = axis.cross(&e0);
    let planar: Vec<(f64, f64)> = points
        .iter()
        .map(|p| {
            let d = p - mean;
            (d.dot(&e0), d.dot(&e1))
        })
        .collect();
    let area = |angle: f64| {
        let (c, s) = (angle.cos(), angle.sin());
        let a = trimmed_range(planar.iter().map(|(x, y)| c * x + s * y), trim);
        let b = trimmed_range(planar.iter().map(|(x, y)| -s * x + c * y), trim);
        (a.1 - a.0) * (b.1 - b.0)
    };
    let best = |angles: &mut dyn Iterator<Item = f64>| {
        angles
            .map(|a| (area(a), a))
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map_or(0.0, |(_, a)| a)
    };
    let coarse = best(&mut (-90..=90).map(|d| f64::from(d).to_radians()));
    let angle = best(&mut (-10..=10).map(|d| coarse + (f64::from(d) * 0.1).to_radians()));
    let (c, s) = (angle.cos(), angle.sin());
    let a0 = e0 * c + e1 * s;
    let a1 = axis.cross(&a0);
    let axes = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[a0, a1, axis]));
    let mut lo = Vector3::zeros();
    let mut hi = Vector3::zeros();
    for k in 0..3 {
        let a = axes.matrix().column(k).into_owned();
        (lo[k], hi[k]) = trimmed_range(points.iter().map(|p| (p - mean).dot(&a)), trim);
    }
    for k in 0..3 {
        let along = outward.map_or(0.0, |o| axes.matrix().column(k).dot(o));
        let short = 2.0 * min_half_extent - (hi[k] - lo[k]);
        if short <= 0.0 {
            continue;
        }
        if along > std::f64::consts::FRAC_1_SQRT_2 {
            lo[k] -= short;
        } else if along < -std::f64::consts::FRAC_1_SQRT_2 {
            hi[k] += short;
        } else {
            lo[k] -= short / 2.0;
            hi[k] += short / 2.0;
        }
    }
    let mid = (lo + hi) / 2.0;
    let half = (hi - lo) / 2.0;
    Some(OrientedBox {
        center: mean + axes * mid,
        rotation: UnitQuaternion::from_rotation_matrix(&axes),
        half_extents: half,
    })
}

/// The `trim` and `1 - trim` quantiles of `values` (non-empty).
pub(crate) fn trimmed_range(values: impl Iterator<Item = f64>, trim: f64) -> (f64, f64) {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    let last = v.len().saturating_sub(1);
    let at = |q: f64| {
        v.get(((q * last as f64).round() as usize).min(last))
            .copied()
            .unwrap_or(0.0)
    };
    (at(trim), at(1.0 - trim))
}

/// The points of `points` bucketed in cubes of side `radius` (for [`flood`]).
fn cells(points: &[Point3<f64>], radius: f64) -> HashMap<[i64; 3], Vec<usize>> {
    let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (k, p) in points.iter().enumerate() {
        cells.entry(key(p, radius)).or_default().push(k);
    }
    cells
}

/// Region growing from the points on `stack` (already labelled): every point reached through
/// chains of points at most `radius` apart gets `label`.
fn flood(
    points: &[Point3<f64>],
    cells: &HashMap<[i64; 3], Vec<usize>>,
    labels: &mut [Option<usize>],
    mut stack: Vec<usize>,
    label: usize,
    radius: f64,
) {
    while let Some(k) = stack.pop() {
        let p = points[k];
        let [i, j, l] = key(&p, radius);
        for di in -1..=1 {
            for dj in -1..=1 {
                for dl in -1..=1 {
                    let Some(list) = cells.get(&[i + di, j + dj, l + dl]) else {
                        continue;
                    };
                    for &n in list {
                        if labels[n].is_none() && (points[n] - p).norm() <= radius {
                            labels[n] = Some(label);
                            stack.push(n);
                        }
                    }
                }
            }
        }
    }
}

/// Region growing: the points of `points` connected to `seed` through chains of points at most
/// `radius` apart, starting from the points within `seed_radius` of `seed` (or the nearest
/// point, if none is that close). Returns them in input order.
pub(crate) fn connected_to(
    points: &[Point3<f64>],
    seed: &Point3<f64>,
    seed_radius: f64,
    radius: f64,
) -> Vec<Point3<f64>> {
    if points.is_empty() {
        return Vec::new();
    }
    let mut stack: Vec<usize> = (0..points.len())
        .filter(|&k| (points[k] - seed).norm() <= seed_radius)
        .collect();
    if stack.is_empty() {
        let nearest = (0..points.len())
            .min_by(|&a, &b| {
                (points[a] - seed)
                    .norm()
                    .total_cmp(&(points[b] - seed).norm())
            })
            .unwrap_or(0);
        stack.push(nearest);
    }
    let mut labels = vec![None; points.len()];
    for &k in &stack {
        labels[k] = Some(0);
    }
    flood(
        points,
        &cells(points, radius),
        &mut labels,
        stack,
        0,
        radius,
    );
    points
        .iter()
        .zip(&labels)
        .filter(|(_, l)| l.is_some())
        .map(|(p, _)| *p)
        .collect()
}

/// The connected components of `points` (chains of points at most `radius` apart), in the
/// order of their first point, each in input order.
pub(crate) fn components(points: &[Point3<f64>], radius: f64) -> Vec<Vec<Point3<f64>>> {
    let cells = cells(points, radius);
    let mut labels = vec![None; points.len()];
    let mut count = 0;
    for k in 0..points.len() {
        if labels[k].is_none() {
            labels[k] = Some(count);
            flood(points, &cells, &mut labels, vec![k], count, radius);
            count += 1;
        }
    }
    let mut out = vec![Vec::new(); count];
    for (p, l) in points.iter().zip(&labels) {
        if let Some(l) = l {
            out[*l].push(*p);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 0.59 × 0.70 grid in the plane y = 0 (a door front): the box is the rectangle, 1 cm
    /// thick at least, centred on it.
    #[test]
    fn oriented_box_of_a_rectangle() {
        let mut pts = Vec::new();
        for i in 0..=59 {
            for k in 0..=70 {
                pts.push(Point3::new(i as f64 * 0.01, 0.0, 0.05 + k as f64 * 0.01));
            }
        }
        let b = oriented_box_along(&pts, &Vector3::z(), None, 0.0, 0.01).unwrap();
        let mut h: Vec<f64> = b.half_extents.iter().copied().collect();
        h.sort_by(f64::total_cmp);
        assert!((h[0] - 0.01).abs() < 1e-9, "{h:?}");
        assert!((h[1] - 0.295).abs() < 1e-9, "{h:?}");
        assert!((h[2] - 0.35).abs() < 1e-9, "{h:?}");
        assert!((b.center - Point3::new(0.295, 0.0, 0.4)).norm() < 1e-9);
    }

    /// A door front 0.544 wide (x) and 0.74 tall (z) in the plane y = 0, turned 20° about
    /// the vertical, with a 5 cm strip of a neighbouring front's points dropped from its
    /// upper-right corner, which tilts a free box. Boxed along its (turned) vertical hinge
    /// axis, the box keeps the hinge axis as one of its axes and the door's height along it
    /// (hand-derived: the points' z range is 0 .. 0.74).
    #[test]
    fn oriented_box_along_keeps_the_axis() {
        let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), 20f64.to_radians());
        let mut pts = Vec::new();
        for i in 0..=54 {
            for k in 0..=74 {
                let (x, z) = (i as f64 * 0.01, k as f64 * 0.01);
                if x > 0.49 && z > 0.6 {
                    continue;
                }
                pts.push(turn * Point3::new(x, 0.0, z));
            }
        }
        let b = oriented_box_along(&pts, &Vector3::z(), None, 0.0, 0.005).unwrap();
        let axes = b.rotation.to_rotation_matrix();
        let k = (0..3)
            .find(|&k| axes.matrix().column(k).dot(&Vector3::z()).abs() > 1.0 - 1e-9)
            .expect("one box axis is the given axis");
        assert!(
            (b.half_extents[k] - 0.37).abs() < 1e-9,
            "{:?}",
            b.half_extents
        );
        let mut h: Vec<f64> = b.half_extents.iter().copied().collect();
        h.sort_by(f64::total_cmp);
        assert!((h[0] - 0.005).abs() < 1e-3, "{h:?}");
        assert!((h[1] - 0.27).abs() < 1e-3, "{h:?}");
        assert!(oriented_box_along(&pts, &Vector3::zeros(), None, 0.0, 0.005).is_none());
        // The flat front padded to 5 mm behind its surface (outward normal: the front's −y
        // turned with it), not 2.5 mm on each side.
        let out = turn * -Vector3::y();
        let b = oriented_box_along(&pts, &Vector3::z(), Some(&out), 0.0, 0.005).unwrap();
        let front = (b.center - Point3::origin()).dot(&out)
            + (b.rotation.to_rotation_matrix().matrix().transpose() * out)
                .abs()
                .dot(&b.half_extents);
        assert!(front.abs() < 1e-9, "front face at {front}");
    }
}
