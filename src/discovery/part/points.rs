//! The part's points at the closed pose: the estimator's or the fallback segmentation's,
//! without those beyond the hinge line, near the base map or not connected to the contact.

use nalgebra::{Isometry3, Point3, Vector3};

use super::joint::joint_motion;
use super::{CONNECTIVITY, JointLine, Observed};
use crate::articulation::Estimate;
use crate::discovery::cloud::{VoxelIndex, connected_to};
use crate::discovery::settings::DiscoverySettings;
use crate::discovery::shapes::PlacedShape;
use crate::scene::{JointKind, SceneModel};

/// Moving points farther than this (m) from the contact are not used for the fallback
/// segmentation (a kitchen front is at most about a metre wide).
const SEGMENT_RADIUS: f64 = 1.0;
/// Part points within this distance (m) of the contact seed the connectivity filter.
const SEED_RADIUS: f64 = 0.06;
/// The fallback segmentation's change threshold is at least this multiple of the median
/// pre → post nearest-neighbour distance (the sampling and noise scale of the scene).
const NOISE_MULTIPLIER: f64 = 4.0;

/// The part's points at the closed pose: the estimator's, or with fewer than 4 those the
/// fallback segmentation finds; without the points beyond the hinge line, near the base map
/// or not connected to the contact (each drop noted).
pub(super) fn part_points(
    estimate: &Estimate,
    observed: &Observed<'_>,
    base: &[PlacedShape],
    line: &JointLine,
    s: &DiscoverySettings,
    notes: &mut Vec<String>,
) -> Vec<Point3<f64>> {
    let JointLine {
        kind,
        axis,
        origin,
        motion,
        ..
    } = *line;
    let c = observed.contact_pre;
    let mut points = estimate.part_points.clone();
    if points.len() < 4 {
        points = segment_by_motion(observed, &joint_motion(kind, &axis, &origin, motion), s);
        notes.push(format!(
            "estimator gave {} part points; motion-consistency segmentation found {}",
            estimate.part_points.len(),
            points.len()
        ));
    }
    if kind == JointKind::Revolute {
        let before = points.len();
        points = hinge_side(points, &axis, &origin, &c);
        if points.len() < before {
            notes.push(format!(
                "{} of {before} part points lie beyond the hinge line (a front turns about an \
                 edge); dropped from the box",
                before - points.len()
            ));
        }
    }
    let before = points.len();
    let points = clear_of_base(base, points, s.base_clearance);
    if points.len() < before {
        notes.push(format!(
            "{} of {before} part points lie within {} m of the base map at the closed pose \
             (static surfaces the segmentation took for the part); dropped from the box",
            before - points.len(),
            s.base_clearance
        ));
    }
    let all = points.len();
    let points = connected_to(&points, &c, SEED_RADIUS, CONNECTIVITY);
    if points.len() < all {
        notes.push(format!(
            "{} of {all} part points are not connected to the contact; dropped from the box",
            all - points.len()
        ));
    }
    points
}

/// The base map's shapes, placed for queries.
pub(in crate::discovery) fn placed_base(model: &SceneModel) -> Vec<PlacedShape> {
    model
        .base()
        .shapes
        .iter()
        .filter_map(|b| PlacedShape::new(&b.shape, &b.world_from_shape))
        .collect()
}

/// The points of `points` on the contact's side of the hinge line (none beyond it: a front's
/// hinge edge is on the axis, and the neighbouring front flush with it is 3 mm away): the
/// plane through the axis (`axis` unit, through `origin`) normal to the contact's
/// perpendicular offset from it. A cabinet door, an oven or dishwasher door, a
/// flap turns about one of its edges, so everything on the other side is static (the
/// neighbouring fronts near the hinge, which the turning front hides in the post view and
/// the rotation moves little). A front turning about an axis through its middle (a pivot
/// window) would lose its far half; kitchens have none. With the contact on the axis, all
/// points are kept.
fn hinge_side(
    points: Vec<Point3<f64>>,
    axis: &Vector3<f64>,
    origin: &Point3<f64>,
    contact: &Point3<f64>,
) -> Vec<Point3<f64>> {
    let off = contact - origin;
    let Some(u) = (off - axis * off.dot(axis)).try_normalize(1e-6) else {
        return points;
    };
    points
        .into_iter()
        .filter(|p| (p - origin).dot(&u) >= 0.0)
        .collect()
}

/// The points of `points` (the part at its closed pose, map frame) farther than `clearance`
/// from every shape of the base map (`base`, [`placed_base`]). A front closed in its carcass stands in front of
/// the static surfaces around it, so points on them are static surfaces taken for the part
/// (seen through the gap the open part left, or within the segmentation's tolerance); kept in
/// the box they make it overlap the carcass at the closed state.
fn clear_of_base(
    base: &[PlacedShape],
    points: Vec<Point3<f64>>,
    clearance: f64,
) -> Vec<Point3<f64>> {
    if clearance <= 0.0 {
        return points;
    }
    points
        .into_iter()
        .filter(|p| base.iter().all(|b| b.distance(p) > clearance))
        .collect()
}

/// Fallback segmentation for estimators without one: the pre points within
/// [`SEGMENT_RADIUS`] of the contact that left their place (no post point within `τ`) and
/// whose estimated new place is observed (a post point within `τ` of the moved point), with
/// `τ = max(displacement_threshold, 4 · median pre → post nearest-neighbour distance)` so that
/// sparsely sampled static surfaces do not count as moved.
fn segment_by_motion(
    observed: &Observed<'_>,
    motion: &Isometry3<f64>,
    s: &DiscoverySettings,
) -> Vec<Point3<f64>> {
    let post = VoxelIndex::new(&observed.post.points, s.displacement_cap);
    let mut nn: Vec<f64> = observed
        .pre
        .points
        .iter()
        .map(|p| post.nearest_capped(p))
        .collect();
    let d_static = nn.clone();
    nn.sort_by(f64::total_cmp);
    let median = nn.get(nn.len() / 2).copied().unwrap_or(0.0);
    let tol = s.displacement_threshold.max(NOISE_MULTIPLIER * median);
    observed
        .pre
        .points
        .iter()
        .zip(d_static)
        .filter(|(p, d)| {
            (*p - observed.contact_pre).norm() <= SEGMENT_RADIUS
                && *d > tol
                && post.nearest_capped(&(motion * *p)) <= tol
        })
        .map(|(p, _)| *p)
        .collect()
}
