//! A static 3-d tree over points: nearest-neighbour and fixed-radius queries.

use nalgebra::Point3;

/// An implicit, balanced k-d tree: the node of the sub-range `[lo, hi)` is at `(lo + hi) / 2`.
#[derive(Debug, Clone)]
pub(crate) struct KdTree {
    /// Points in tree order.
    points: Vec<Point3<f64>>,
    /// `index[k]` is the caller's index of `points[k]`.
    index: Vec<usize>,
    /// Split axis of the node at each position.
    axis: Vec<u8>,
}

impl KdTree {
    /// Builds the tree over `points` (O(n log² n)).
    pub(crate) fn new(points: &[Point3<f64>]) -> Self {
        let mut items: Vec<(Point3<f64>, usize)> = points.iter().copied().zip(0..).collect();
        let mut axis = vec![0u8; points.len()];
        build(&mut items, &mut axis);
        let (points, index) = items.into_iter().unzip();
        KdTree {
            points,
            index,
            axis,
        }
    }

    /// The nearest point to `q` no farther than `max_distance`: `(caller index, distance)`.
    pub(crate) fn nearest(&self, q: &Point3<f64>, max_distance: f64) -> Option<(usize, f64)> {
        let mut best = (usize::MAX, max_distance * max_distance);
        self.nearest_in(q, 0, self.points.len(), &mut best);
        (best.0 != usize::MAX).then(|| (self.index[best.0], best.1.sqrt()))
    }

    /// Calls `f(caller index, squared distance)` for every point within `radius` of `q`.
    pub(crate) fn for_each_within(
        &self,
        q: &Point3<f64>,
        radius: f64,
        mut f: impl FnMut(usize, f64),
    ) {
        self.within(q, radius * radius, 0, self.points.len(), &mut f);
    }

    fn nearest_in(&self, q: &Point3<f64>, lo: usize, hi: usize, best: &mut (usize, f64)) {
        if lo >= hi {
            return;
        }
        let mid = (lo + hi) / 2;
        let p = &self.points[mid];
        let d2 = (p - q).norm_squared();
        if d2 < best.1 {
            *best = (mid, d2);
        }
        let a = self.axis[mid] as usize;
        let diff = q[a] - p[a];
        let (near, far) = if diff < 0.0 {
            ((lo, mid), (mid + 1, hi))
        } else {
            ((mid + 1, hi), (lo, mid))
        };
        self.nearest_in(q, near.0, near.1, best);
        if diff * diff < best.1 {
            self.nearest_in(q, far.0, far.1, best);
        }
    }

    fn within(
        &self,
        q: &Point3<f64>,
        r2: f64,
        lo: usize,
        hi: usize,
        f: &mut impl FnMut(usize, f64),
    ) {
        if lo >= hi {
            return;
        }
        let mid = (lo + hi) / 2;
        let p = &self.points[mid];
        let d2 = (p - q).norm_squared();
        if d2 <= r2 {
            f(self.index[mid], d2);
        }
        let a = self.axis[mid] as usize;
        let diff = q[a] - p[a];
        if diff < 0.0 || diff * diff <= r2 {
            self.within(q, r2, lo, mid, f);
        }
        if diff >= 0.0 || diff * diff <= r2 {
            self.within(q, r2, mid + 1, hi, f);
        }
    }
}

/// Orders `items` so that each sub-range's median splits it along its widest axis.
fn build(items: &mut [(Point3<f64>, usize)], axis: &mut [u8]) {
    if items.len() <= 1 {
        return;
    }
    let mut min = items[0].0;
    let mut max = items[0].0;
    for (p, _) in items.iter() {
        min = min.inf(p);
        max = max.sup(p);
    }
    let a = (max - min).imax();
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |x, y| x.0[a].total_cmp(&y.0[a]));
    axis[mid] = a as u8;
    let (left, rest) = items.split_at_mut(mid);
    let (left_axis, rest_axis) = axis.split_at_mut(mid);
    build(left, left_axis);
    build(&mut rest[1..], &mut rest_axis[1..]);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tree agrees with brute force on a deterministic pseudo-random cloud.
    #[test]
    fn matches_brute_force() {
        let mut s = 12345u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let pts: Vec<_> = (0..500)
            .map(|_| Point3::new(next(), next(), next()))
            .collect();
        let tree = KdTree::new(&pts);
        for _ in 0..100 {
            let q = Point3::new(next(), next(), next());
            let (bi, bd) = pts
                .iter()
                .enumerate()
                .map(|(i, p)| (i, (p - q).norm()))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            let (ti, td) = tree.nearest(&q, f64::INFINITY).unwrap();
            assert_eq!(ti, bi);
            assert!((td - bd).abs() < 1e-12);
            let mut found: Vec<usize> = Vec::new();
            tree.for_each_within(&q, 0.2, |i, _| found.push(i));
            found.sort_unstable();
            let brute: Vec<usize> = (0..pts.len())
                .filter(|&i| (pts[i] - q).norm() <= 0.2)
                .collect();
            assert_eq!(found, brute);
        }
    }
}
