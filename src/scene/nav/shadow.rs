//! The 2D shadow (vertical projection onto the floor plane) of a placed shape.
//!
//! A shadow is represented as the Minkowski sum of a convex polygon and a disc, which holds
//! every projected primitive exactly or conservatively: a box or convex mesh projects to the
//! convex hull of its projected vertices (exact), a sphere to a disc (exact), a capsule to a
//! segment grown by its radius (exact), a cylinder to the hull of a circumscribed 16-gon prism
//! (conservative, at most 2% of the radius larger).

use nalgebra::{Isometry3, Point2, Point3};

use crate::scene::shape::Shape;

/// Number of sides of the prism circumscribing a cylinder.
const CYLINDER_SIDES: usize = 16;

/// A convex polygon grown by a disc, with the vertical extent of the shape that cast it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Shadow {
    /// Counter-clockwise convex hull (1 point, 2 points for a segment, or a polygon).
    pub hull: Vec<Point2<f64>>,
    /// Radius of the disc added to the hull (m).
    pub radius: f64,
    /// Lowest world z of the shape (m).
    pub z_min: f64,
    /// Highest world z of the shape (m).
    pub z_max: f64,
}

/// The shadow of `shape` placed at `world_from_shape`.
pub(crate) fn shadow(shape: &Shape, world_from_shape: &Isometry3<f64>) -> Shadow {
    let (points, radius): (Vec<Point3<f64>>, f64) = match shape {
        Shape::Cuboid { half_extents: h } => {
            let corners = (0..8)
                .map(|k| {
                    let s = |bit: usize| if k & bit == 0 { -1.0 } else { 1.0 };
                    Point3::new(s(1) * h.x, s(2) * h.y, s(4) * h.z)
                })
                .collect();
            (corners, 0.0)
        }
        Shape::Sphere { radius } => (vec![Point3::origin()], *radius),
        Shape::Capsule { radius, length } => (
            vec![
                Point3::new(0.0, 0.0, -length / 2.0),
                Point3::new(0.0, 0.0, length / 2.0),
            ],
            *radius,
        ),
        Shape::Cylinder { radius, length } => {
            let n = CYLINDER_SIDES as f64;
            let r = radius / (std::f64::consts::PI / n).cos();
            let prism = (0..2 * CYLINDER_SIDES)
                .map(|k| {
                    let a = (k % CYLINDER_SIDES) as f64 * std::f64::consts::TAU / n;
                    let z = if k < CYLINDER_SIDES { -length } else { *length } / 2.0;
                    Point3::new(r * a.cos(), r * a.sin(), z)
                })
                .collect();
            (prism, 0.0)
        }
        Shape::ConvexMesh { vertices, .. } => (vertices.clone(), 0.0),
    };
    let world: Vec<Point3<f64>> = points.iter().map(|p| world_from_shape * p).collect();
    let z_min = world.iter().map(|p| p.z).fold(f64::INFINITY, f64::min) - radius;
    let z_max = world.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max) + radius;
    let flat: Vec<Point2<f64>> = world.iter().map(|p| Point2::new(p.x, p.y)).collect();
    Shadow {
        hull: convex_hull(flat),
        radius,
        z_min,
        z_max,
    }
}

fn cross(o: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> f64 {
    (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
}

/// Andrew's monotone chain: the counter-clockwise hull without collinear points.
pub(crate) fn convex_hull(mut pts: Vec<Point2<f64>>) -> Vec<Point2<f64>> {
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let mut hull: Vec<Point2<f64>> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Point2<f64>>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2
                && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    if hull.len() < 2 {
        // All points collinear and the chains cancelled out: keep the extreme points.
        return vec![pts[0], pts[pts.len() - 1]];
    }
    hull
}

/// Distance (m) from a point to the axis-aligned rectangle `[lo, hi]` (0 inside).
fn point_rect_distance(p: &Point2<f64>, lo: &Point2<f64>, hi: &Point2<f64>) -> f64 {
    let dx = (lo.x - p.x).max(0.0).max(p.x - hi.x);
    let dy = (lo.y - p.y).max(0.0).max(p.y - hi.y);
    dx.hypot(dy)
}

/// Distance (m) from a point to a segment.
fn point_segment_distance(p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).norm()
}

/// Whether some axis (rectangle normals or hull edge normals) strictly separates the two.
fn separated(hull: &[Point2<f64>], lo: &Point2<f64>, hi: &Point2<f64>) -> bool {
    let corners = [*lo, Point2::new(hi.x, lo.y), *hi, Point2::new(lo.x, hi.y)];
    let (hx0, hx1) = hull
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.x), b.max(p.x))
        });
    let (hy0, hy1) = hull
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.y), b.max(p.y))
        });
    if hx1 < lo.x || hx0 > hi.x || hy1 < lo.y || hy0 > hi.y {
        return true;
    }
    let n = hull.len();
    (0..n).any(|k| {
        let a = hull[k];
        let b = hull[(k + 1) % n];
        let normal = nalgebra::Vector2::new(b.y - a.y, a.x - b.x);
        let proj = |p: &Point2<f64>| normal.dot(&p.coords);
        let (h0, h1) = hull
            .iter()
            .map(proj)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(x, y), v| {
                (x.min(v), y.max(v))
            });
        let (r0, r1) = corners
            .iter()
            .map(proj)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(x, y), v| {
                (x.min(v), y.max(v))
            });
        h1 < r0 || r1 < h0
    })
}

/// Distance (m) from the convex hull to the rectangle `[lo, hi]`; 0 if they touch or overlap.
pub(crate) fn hull_rect_distance(hull: &[Point2<f64>], lo: &Point2<f64>, hi: &Point2<f64>) -> f64 {
    if !separated(hull, lo, hi) {
        return 0.0;
    }
    // Disjoint convex sets: a closest pair has a vertex of one of them.
    let from_hull = hull
        .iter()
        .map(|p| point_rect_distance(p, lo, hi))
        .fold(f64::INFINITY, f64::min);
    let corners = [*lo, Point2::new(hi.x, lo.y), *hi, Point2::new(lo.x, hi.y)];
    let n = hull.len();
    let from_rect = if n < 2 {
        f64::INFINITY
    } else {
        corners
            .iter()
            .flat_map(|c| {
                (0..n).map(move |k| point_segment_distance(c, &hull[k], &hull[(k + 1) % n]))
            })
            .fold(f64::INFINITY, f64::min)
    };
    from_hull.min(from_rect)
}

/// Whether some axis (an edge normal or edge direction of either set) strictly separates two
/// convex point sets (each a point, a segment or a counter-clockwise polygon).
fn convex_separated(a: &[Point2<f64>], b: &[Point2<f64>]) -> bool {
    let axes = |s: &[Point2<f64>]| -> Vec<nalgebra::Vector2<f64>> {
        let n = s.len();
        (0..n)
            .filter(|k| n > 1 && (n > 2 || *k == 0))
            .flat_map(|k| {
                let d = s[(k + 1) % n] - s[k];
                [nalgebra::Vector2::new(d.y, -d.x), d]
            })
            .collect()
    };
    let range = |s: &[Point2<f64>], v: &nalgebra::Vector2<f64>| {
        s.iter()
            .map(|p| v.dot(&p.coords))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            })
    };
    axes(a).iter().chain(axes(b).iter()).any(|v| {
        let (a0, a1) = range(a, v);
        let (b0, b1) = range(b, v);
        a1 < b0 || b1 < a0
    })
}

/// Distance (m) between two convex point sets (each a point, a segment or a
/// counter-clockwise polygon); 0 if they touch or overlap.
pub(crate) fn convex_distance(a: &[Point2<f64>], b: &[Point2<f64>]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return f64::INFINITY;
    }
    let single = a.len() == 1 && b.len() == 1;
    if !single && !convex_separated(a, b) {
        return 0.0;
    }
    // Disjoint convex sets: a closest pair has a vertex of one of them.
    let to_edges = |p: &Point2<f64>, s: &[Point2<f64>]| {
        let n = s.len();
        if n == 1 {
            return (p - s[0]).norm();
        }
        (0..n)
            .map(|k| point_segment_distance(p, &s[k], &s[(k + 1) % n]))
            .fold(f64::INFINITY, f64::min)
    };
    let ab = a
        .iter()
        .map(|p| to_edges(p, b))
        .fold(f64::INFINITY, f64::min);
    let ba = b
        .iter()
        .map(|p| to_edges(p, a))
        .fold(f64::INFINITY, f64::min);
    ab.min(ba)
}

/// Distance (m) from a point to a convex point set (a point, a segment or a
/// counter-clockwise polygon); 0 inside or on it.
pub(crate) fn point_convex_distance(p: &Point2<f64>, s: &[Point2<f64>]) -> f64 {
    let n = s.len();
    match n {
        0 => f64::INFINITY,
        1 => (p - s[0]).norm(),
        2 => point_segment_distance(p, &s[0], &s[1]),
        _ => {
            let mut inside = true;
            let mut best = f64::INFINITY;
            for k in 0..n {
                let (a, b) = (&s[k], &s[(k + 1) % n]);
                if cross(a, b, p) < 0.0 {
                    inside = false;
                }
                best = best.min(point_segment_distance(p, a, b));
            }
            if inside { 0.0 } else { best }
        }
    }
}

impl Shadow {
    /// Distance (m) from the shadow to a point; 0 inside.
    pub(crate) fn distance_to_point(&self, p: &Point2<f64>) -> f64 {
        (point_convex_distance(p, &self.hull) - self.radius).max(0.0)
    }

    /// Distance (m) from the shadow to a convex point set (a point, a segment or a
    /// counter-clockwise polygon); 0 if they touch or overlap.
    pub(crate) fn distance_to(&self, points: &[Point2<f64>]) -> f64 {
        (convex_distance(&self.hull, points) - self.radius).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2<f64> {
        Point2::new(x, y)
    }

    #[test]
    fn convex_distances_match_hand_values() {
        // The unit square, counter-clockwise.
        let square = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
        assert_eq!(convex_distance(&square, &[p(0.5, 0.5)]), 0.0);
        assert_eq!(point_convex_distance(&p(0.5, 0.5), &square), 0.0);
        // (2, 2) is √2 from the corner (1, 1); (0.5, -0.25) is 0.25 below the bottom edge.
        assert!((convex_distance(&square, &[p(2.0, 2.0)]) - 2f64.sqrt()).abs() < 1e-12);
        assert!((point_convex_distance(&p(0.5, -0.25), &square) - 0.25).abs() < 1e-12);
        // A segment crossing the square without a vertex inside it touches it.
        assert_eq!(convex_distance(&square, &[p(-1.0, 0.5), p(2.0, 0.5)]), 0.0);
        // A segment parallel to the right edge, 0.5 from it.
        let d = convex_distance(&square, &[p(1.5, -1.0), p(1.5, 2.0)]);
        assert!((d - 0.5).abs() < 1e-12, "{d}");
        // Collinear disjoint segments: the gap between their ends.
        let d = convex_distance(&[p(0.0, 0.0), p(1.0, 0.0)], &[p(3.0, 0.0), p(4.0, 0.0)]);
        assert!((d - 2.0).abs() < 1e-12, "{d}");
        // A shadow's disc is subtracted, down to 0.
        let s = Shadow {
            hull: square.to_vec(),
            radius: 0.1,
            z_min: 0.0,
            z_max: 1.0,
        };
        assert!((s.distance_to_point(&p(0.5, -0.25)) - 0.15).abs() < 1e-12);
        assert_eq!(s.distance_to(&[p(0.5, -0.05), p(2.0, -0.05)]), 0.0);
    }
}
