//! A footprint polygon (`[base] footprint`, as navigation stacks write it): its checks and the
//! radius of the disc about the base origin that encloses it.

use super::RobotError;

/// The radius (m) of the smallest disc about the base origin that encloses the polygon
/// `vertices` (base frame, m) at every yaw: the largest vertex distance from the origin.
///
/// That disc is what the navigation grid inflates obstacles by: a cell free for the disc is
/// free for the polygon at any yaw, so the polygon is used soundly without a yaw-dependent
/// grid (and as conservatively as the disc). Base poses and base paths are still checked
/// against the robot's real collision shapes.
///
/// # Errors
/// [`RobotError::Description`] naming `base.footprint` for fewer than 3 vertices, a
/// non-finite coordinate, a polygon with no area or one whose edges cross.
pub(super) fn polygon_radius(vertices: &[[f64; 2]]) -> Result<f64, RobotError> {
    let bad = |message: String| RobotError::Description {
        field: "base.footprint".to_owned(),
        message,
    };
    if vertices.len() < 3 {
        return Err(bad(format!(
            "a polygon needs at least 3 vertices, got {}",
            vertices.len()
        )));
    }
    if let Some(i) = vertices
        .iter()
        .position(|v| !(v[0].is_finite() && v[1].is_finite()))
    {
        return Err(bad(format!("vertex {i} is not finite: {:?}", vertices[i])));
    }
    let n = vertices.len();
    let edge = |i: usize| (vertices[i], vertices[(i + 1) % n]);
    for i in 0..n {
        // Edges that share a vertex meet there; every other pair must not touch.
        for k in i + 2..n {
            if i == 0 && k == n - 1 {
                continue;
            }
            if segments_touch(edge(i), edge(k)) {
                return Err(bad(format!(
                    "edges {i} and {k} cross: not a simple polygon"
                )));
            }
        }
    }
    // Shoelace area.
    let twice_area: f64 = (0..n)
        .map(|i| {
            let (a, b) = edge(i);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    if twice_area.abs() <= 1e-12 {
        return Err(bad("the polygon has no area".to_owned()));
    }
    Ok(vertices
        .iter()
        .map(|v| v[0].hypot(v[1]))
        .fold(0.0, f64::max))
}

/// Whether two closed segments share a point (orientation tests, collinear overlaps
/// included).
fn segments_touch((a, b): ([f64; 2], [f64; 2]), (c, d): ([f64; 2], [f64; 2])) -> bool {
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        let v = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
        if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            0
        }
    };
    let on = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        r[0] >= p[0].min(q[0])
            && r[0] <= p[0].max(q[0])
            && r[1] >= p[1].min(q[1])
            && r[1] <= p[1].max(q[1])
    };
    let (o1, o2, o3, o4) = (
        orient(a, b, c),
        orient(a, b, d),
        orient(c, d, a),
        orient(c, d, b),
    );
    if o1 != o2 && o3 != o4 {
        return true;
    }
    (o1 == 0 && on(a, b, c))
        || (o2 == 0 && on(a, b, d))
        || (o3 == 0 && on(c, d, a))
        || (o4 == 0 && on(c, d, b))
}

#[cfg(test)]
mod tests {
    use super::polygon_radius;

    #[test]
    fn the_radius_is_the_farthest_vertex_and_bad_polygons_are_named() {
        // A 0.6 × 0.4 m rectangle centred 0.1 m ahead of the origin: the far corners are at
        // (0.4, ±0.2), hypot = √0.2 ≈ 0.4472 m.
        let rect = [[-0.2, -0.2], [0.4, -0.2], [0.4, 0.2], [-0.2, 0.2]];
        let r = polygon_radius(&rect).unwrap();
        assert!((r - 0.2f64.sqrt()).abs() < 1e-12, "{r}");
        // Clockwise order is as good.
        let cw: Vec<[f64; 2]> = rect.iter().rev().copied().collect();
        assert_eq!(polygon_radius(&cw).unwrap(), r);
        let message = |v: &[[f64; 2]]| polygon_radius(v).unwrap_err().to_string();
        assert!(message(&rect[..2]).contains("at least 3"));
        assert!(message(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]).contains("no area"));
        assert!(message(&[[0.0, 0.0], [f64::NAN, 0.0], [0.0, 1.0]]).contains("not finite"));
        // A bow tie: edges 0 ((0,0)-(1,1)) and 2 ((1,0)-(0,1)) cross at (0.5, 0.5).
        let bow = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(
            message(&bow).contains("edges 0 and 2 cross"),
            "{}",
            message(&bow)
        );
        for m in [message(&rect[..2]), message(&bow)] {
            assert!(m.contains("base.footprint"), "{m}");
        }
    }
}
