//! Change detection between the two clouds (step 1) and the region growing that segments the
//! moving part from a seed at the contact (steps 2 and 6).

use std::collections::HashSet;

use nalgebra::Point3;

use super::TwoViewSettings;
use crate::articulation::kdtree::KdTree;

/// The two clouds, their k-d trees and the change between them.
pub(super) struct Changes<'a> {
    pub(super) pre: &'a [Point3<f64>],
    pub(super) post: &'a [Point3<f64>],
    pub(super) pre_tree: KdTree,
    pub(super) post_tree: KdTree,
    /// Where nearest-neighbour searches stop (a point with no neighbour nearer is reported at
    /// this distance).
    far: f64,
    /// The change threshold τ.
    pub(super) tau: f64,
    /// Per pre point, the distance to the nearest post point (up to `far`).
    pub(super) d_pre: Vec<f64>,
    /// The pre points with no post point within τ.
    pub(super) changed: Vec<bool>,
    /// The post points with no pre point within τ.
    pub(super) new: Vec<bool>,
}

impl<'a> Changes<'a> {
    /// Step 1: a pre point is changed when no post point lies within
    /// `τ = max(change_distance, noise_multiplier · median pre→post nearest-neighbour distance)`;
    /// symmetrically a post point is new.
    pub(super) fn new(
        s: &TwoViewSettings,
        pre: &'a [Point3<f64>],
        post: &'a [Point3<f64>],
    ) -> Self {
        let pre_tree = KdTree::new(pre);
        let post_tree = KdTree::new(post);
        // Nearest-neighbour distances are only compared with τ-sized thresholds, so the searches
        // stop at `far` (a point with no neighbour nearer is reported at `far`): searches that find
        // nothing are what costs time. `far` is at least 2τ (recomputed for very sparse clouds).
        let distances = |far: f64| {
            let nn = |tree: &KdTree, p: &Point3<f64>| tree.nearest(p, far).map_or(far, |(_, d)| d);
            let d_pre: Vec<f64> = pre.iter().map(|p| nn(&post_tree, p)).collect();
            let d_post: Vec<f64> = post.iter().map(|p| nn(&pre_tree, p)).collect();
            let tau = s.change_distance.max(s.noise_multiplier * median(&d_pre));
            (d_pre, d_post, tau)
        };
        let mut far = 10.0 * s.change_distance;
        let (mut d_pre, mut d_post, mut tau) = distances(far);
        if 2.0 * tau > far {
            far = 4.0 * tau;
            (d_pre, d_post, tau) = distances(far);
        }
        let changed: Vec<bool> = d_pre.iter().map(|&d| d > tau).collect();
        let new: Vec<bool> = d_post.iter().map(|&d| d > tau).collect();
        Changes {
            pre,
            post,
            pre_tree,
            post_tree,
            far,
            tau,
            d_pre,
            changed,
            new,
        }
    }

    /// The distance from `p` to the nearest post point, `far` if none is nearer.
    pub(super) fn to_post(&self, p: &Point3<f64>) -> f64 {
        self.post_tree
            .nearest(p, self.far)
            .map_or(self.far, |(_, d)| d)
    }
}

/// Indices of `mask`ed points within `radius` of `contact`, or the masked point nearest to it.
pub(super) fn seeds(
    points: &[Point3<f64>],
    tree: &KdTree,
    mask: &[bool],
    contact: &Point3<f64>,
    radius: f64,
) -> Vec<usize> {
    let mut out = Vec::new();
    tree.for_each_within(contact, radius, |k, _| {
        if mask[k] {
            out.push(k);
        }
    });
    if out.is_empty() {
        let nearest = (0..points.len())
            .filter(|&k| mask[k])
            .map(|k| (k, (points[k] - contact).norm()))
            .filter(|&(_, d)| d <= 3.0 * radius)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        out.extend(nearest.map(|(k, _)| k));
    }
    out
}

/// Breadth-first region growing over `mask`ed points from `seeds` (sorted result).
pub(super) fn grow(
    tree: &KdTree,
    points: &[Point3<f64>],
    mask: &[bool],
    seeds: &[usize],
    radius: f64,
) -> Vec<usize> {
    let mut seen = vec![false; points.len()];
    let mut queue: Vec<usize> = Vec::new();
    for &k in seeds {
        if mask[k] && !seen[k] {
            seen[k] = true;
            queue.push(k);
        }
    }
    let mut head = 0;
    while head < queue.len() {
        let k = queue[head];
        head += 1;
        tree.for_each_within(&points[k], radius, |j, _| {
            if mask[j] && !seen[j] {
                seen[j] = true;
                queue.push(j);
            }
        });
    }
    queue.sort_unstable();
    queue
}

/// The first of `points` in each cube of side `voxel` (all points for `voxel` = 0), in order.
pub(super) fn voxel_subset(points: &[Point3<f64>], voxel: f64) -> Vec<Point3<f64>> {
    if voxel <= 0.0 {
        return points.to_vec();
    }
    let mut seen: HashSet<[i64; 3]> = HashSet::with_capacity(points.len());
    points
        .iter()
        .filter(|p| seen.insert(p.coords.map(|c| (c / voxel).floor() as i64).into()))
        .copied()
        .collect()
}

/// The median of `values` (the upper middle one of an even count), 0 for none.
pub(super) fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let mut v = values.to_vec();
    let mid = v.len() / 2;
    *v.select_nth_unstable_by(mid, f64::total_cmp).1
}
