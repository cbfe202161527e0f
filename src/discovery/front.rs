//! The part's front as registered: its points split into the front and what protrudes from it
//! (the handle) along the front's fitted normal, the handle's grasp point, and the boxes of the
//! part (with a drawer's body behind its front).

use nalgebra::{Point3, Unit, Vector3};

use super::cloud::{OrientedBox, components, oriented_box_along, trimmed_range};
use super::part::{CONNECTIVITY, JointLine};
use super::settings::DiscoverySettings;
use super::shapes::PlacedShape;
use crate::scene::{JointKind, Shape};

/// A protrusion whose centre is within this distance (m) of the contact is the handle.
const HANDLE_SNAP: f64 = 0.05;

/// Fewest points of a protrusion that gets its own box (fewer: depth noise, dropped).
const MIN_PROTRUSION_POINTS: usize = 10;

/// A part's points split by [`split_front`].
pub(super) struct FrontSplit {
    /// The front's points, clamped onto its surface.
    pub(super) front: Vec<Point3<f64>>,
    /// Clusters standing out of it (the handle).
    pub(super) protrusions: Vec<Vec<Point3<f64>>>,
    /// Points standing out that are noise, dropped.
    pub(super) dropped: usize,
    /// Points of clusters standing out beyond the front's outline, dropped: nothing of the
    /// part's stands out from where the part has no front (such a cluster is the edge of a
    /// neighbouring front, or of its handle, taken along with the part's points).
    pub(super) outside: usize,
}

impl FrontSplit {
    /// No split: every point in the front, as given.
    fn none(front: Vec<Point3<f64>>) -> Self {
        FrontSplit {
            front,
            protrusions: Vec::new(),
            dropped: 0,
            outside: 0,
        }
    }
}

/// Splits the part's points into its front and what protrudes from it. The front's surface is
/// the median of the points' depths along the outward `normal`; points more than
/// `handle_standoff` in front of it are protrusions (the handle, a tray on a door), grouped
/// into connected clusters ([`CONNECTIVITY`]; clusters under [`MIN_PROTRUSION_POINTS`], or
/// whose median stands less than 1.5 `handle_standoff` out, are depth noise at the front's
/// edges and dropped); the front's other points are clamped onto the surface (depth
/// noise spreads them about 2σ either side of it). One box around all of them would be as
/// thick as the handle is proud, over the whole front, and that thickened edge by the hinge
/// sweeps into the neighbouring front as the part turns. With `handle_standoff` 0, or when
/// more than half of the points stand out (then the "front" is not a front), nothing is
/// split.
fn split_front(
    points: Vec<Point3<f64>>,
    normal: &Vector3<f64>,
    s: &DiscoverySettings,
) -> FrontSplit {
    if points.is_empty() || s.handle_standoff <= 0.0 {
        return FrontSplit::none(points);
    }
    let depth = |p: &Point3<f64>| p.coords.dot(normal);
    let mut depths: Vec<f64> = points.iter().map(depth).collect();
    depths.sort_by(f64::total_cmp);
    let surface = depths[depths.len() / 2];
    let (out, front): (Vec<Point3<f64>>, Vec<Point3<f64>>) = points
        .iter()
        .partition(|p| depth(p) > surface + s.handle_standoff);
    if 2 * out.len() > points.len() {
        return FrontSplit::none(points);
    }
    let front: Vec<Point3<f64>> = front
        .into_iter()
        .map(|p| p - normal * (depth(&p) - surface).max(0.0))
        .collect();
    let outline = Outline::of(&front, normal, s.box_trim);
    let mut clusters = Vec::new();
    let (mut dropped, mut outside) = (0, 0);
    for cluster in components(&out, CONNECTIVITY) {
        let mut d: Vec<f64> = cluster.iter().map(depth).collect();
        d.sort_by(f64::total_cmp);
        let median = d[d.len() / 2] - surface;
        if cluster.len() < MIN_PROTRUSION_POINTS || median < 1.5 * s.handle_standoff {
            dropped += cluster.len();
        } else if outline.as_ref().is_some_and(|o| !o.covers(&cluster)) {
            outside += cluster.len();
        } else {
            clusters.push(cluster);
        }
    }
    FrontSplit {
        front,
        protrusions: clusters,
        dropped,
        outside,
    }
}

/// The front's extent in its plane: the ranges of its points along two directions across the
/// `normal` (up, as far as the front is upright, and level), each trimmed by the box trim at
/// either end as the front's box is.
struct Outline {
    across: [Vector3<f64>; 2],
    ranges: [(f64, f64); 2],
}

impl Outline {
    /// `None` for fewer than 3 points.
    fn of(front: &[Point3<f64>], normal: &Vector3<f64>, trim: f64) -> Option<Outline> {
        if front.len() < 3 {
            return None;
        }
        let up = Vector3::z() - normal * normal.z;
        let first = if up.norm() >= 0.2 {
            up.normalize()
        } else {
            // A level front (a lid): any direction across the normal.
            normal.cross(&Vector3::x()).try_normalize(1e-9)?
        };
        let across = [first, normal.cross(&first).try_normalize(1e-9)?];
        let ranges = across.map(|a| trimmed_range(front.iter().map(|p| p.coords.dot(&a)), trim));
        Some(Outline { across, ranges })
    }

    /// Whether the centre of `cluster` lies within the outline.
    fn covers(&self, cluster: &[Point3<f64>]) -> bool {
        let centre = centre(cluster);
        self.across
            .iter()
            .zip(&self.ranges)
            .all(|(a, (lo, hi))| (*lo..=*hi).contains(&centre.coords.dot(a)))
    }
}

/// The part's points split into its front and what protrudes from it ([`split_front`]) along
/// the front's normal (noted when something protrudes or is dropped), with that normal.
///
/// The front's normal: the axis of the front's box nearest the normal at the contact (a
/// plane fit around the contact tilts by a degree or two, which across a 0.6 m front is
/// more than the handle stands out). Twice: the first box, around the handle too, leans
/// towards it (a 2.4 cm bump at one end of a 0.5 m front tilts it by about 2.5°, and the
/// tilted front pokes out by the hinge); the second is fitted to the front alone.
pub(super) fn front(
    points: Vec<Point3<f64>>,
    axis: &Vector3<f64>,
    at_contact: &Unit<Vector3<f64>>,
    s: &DiscoverySettings,
    notes: &mut Vec<String>,
) -> (FrontSplit, Vector3<f64>) {
    let at_contact = at_contact.into_inner();
    let first = front_normal(&points, axis, &at_contact, s).unwrap_or(at_contact);
    let normal = front_normal(
        &split_front(points.clone(), &first, s).front,
        axis,
        &at_contact,
        s,
    )
    .unwrap_or(first);
    let split = split_front(points, &normal, s);
    let (noise, outside) = (split.dropped, split.outside);
    if !split.protrusions.is_empty() || noise > 0 || outside > 0 {
        notes.push(format!(
            "front boxed at its median depth; {} protrusion(s) more than {} m in front of it \
             (the handle) boxed apart ({} points), {noise} stray points dropped, {outside} \
             points standing out beyond the front's outline dropped",
            split.protrusions.len(),
            s.handle_standoff,
            split.protrusions.iter().map(Vec::len).sum::<usize>()
        ));
    }
    (split, normal)
}

/// The axis of the box around `cloud` (along `axis`) nearest the normal `at_contact`, turned
/// to point the same way as it.
fn front_normal(
    cloud: &[Point3<f64>],
    axis: &Vector3<f64>,
    at_contact: &Vector3<f64>,
    s: &DiscoverySettings,
) -> Option<Vector3<f64>> {
    oriented_box_along(cloud, axis, None, s.box_trim, s.min_half_extent).map(|b| {
        let r = b.rotation.to_rotation_matrix();
        let k = (0..3)
            .max_by(|&i, &j| {
                let (a, b) = (r.matrix().column(i), r.matrix().column(j));
                a.dot(at_contact).abs().total_cmp(&b.dot(at_contact).abs())
            })
            .unwrap_or(0);
        let n = r.matrix().column(k).into_owned();
        if n.dot(at_contact) < 0.0 { -n } else { n }
    })
}

/// The mean of `points` (non-empty).
fn centre(points: &[Point3<f64>]) -> Point3<f64> {
    Point3::from(points.iter().fold(Vector3::zeros(), |a, p| a + p.coords) / points.len() as f64)
}

/// The grasp point: the centre of the protrusion nearest the contact (the handle as the
/// camera saw it, hundreds of points), when one is within `HANDLE_SNAP`; else the contact
/// (where the detector put the handle, about a centimetre off). Noted when it is the
/// protrusion's centre.
pub(super) fn grasp_point(
    protrusions: &[Vec<Point3<f64>>],
    c: &Point3<f64>,
    notes: &mut Vec<String>,
) -> Point3<f64> {
    let grasp = protrusions
        .iter()
        .map(|cluster| centre(cluster))
        .map(|m| (m, (m - c).norm()))
        .filter(|(_, d)| *d <= HANDLE_SNAP)
        .min_by(|a, b| a.1.total_cmp(&b.1));
    match grasp {
        Some((m, d)) => {
            notes.push(format!(
                "handle registered at the centre of its protrusion, {d:.3} m from the contact"
            ));
            m
        }
        None => *c,
    }
}

/// The part's boxes (map frame, along the joint axis, faced by the front's `normal`): one
/// around the front, preceded for a prismatic part by the drawer body behind it (with
/// [`DiscoverySettings::drawer_body`], noted), and one around each protrusion.
pub(super) fn part_boxes(
    split: &FrontSplit,
    line: &JointLine,
    normal: &Vector3<f64>,
    base: &[PlacedShape],
    s: &DiscoverySettings,
    notes: &mut Vec<String>,
) -> Vec<OrientedBox> {
    let mut boxes = Vec::new();
    let clouds = std::iter::once((&split.front, s.box_trim))
        .chain(split.protrusions.iter().map(|p| (p, 0.0)));
    for (k, (cloud, trim)) in clouds.enumerate() {
        if let Some(b) =
            oriented_box_along(cloud, &line.axis, Some(normal), trim, s.min_half_extent)
        {
            if k == 0 && line.kind == JointKind::Prismatic && s.drawer_body {
                let (body, note) = drawer_body(base, &b, &line.axis, line.upper);
                boxes.extend(body);
                notes.push(note);
            }
            boxes.push(b);
        }
    }
    boxes
}

/// Largest share of the front's half width and height a drawer body may lose to fit the base
/// map's free space behind the front.
const BODY_MAX_SHRINK: f64 = 0.4;

/// Step (m) of the body's shrinking.
const BODY_SHRINK_STEP: f64 = 0.005;

/// The drawer body behind `front` (see [`DiscoverySettings::drawer_body`]), `depth` deep along
/// `-axis` (the front box's third axis is the slide axis, pointing out of the cabinet): the
/// front's cross-section, shrunk in [`BODY_SHRINK_STEP`]s on both sides until it is clear of
/// every base shape at the closed pose (the cavity between the carcass panels), at most by
/// [`BODY_MAX_SHRINK`]; `None` if it never is (a map that shows the carcass solid). With the
/// note for the log.
fn drawer_body(
    base: &[PlacedShape],
    front: &OrientedBox,
    axis: &Vector3<f64>,
    depth: f64,
) -> (Option<OrientedBox>, String) {
    let h = front.half_extents;
    let limit = BODY_MAX_SHRINK * h.x.min(h.y);
    let mut shrink = 0.0;
    while shrink <= limit {
        let body = OrientedBox {
            center: front.center - axis * (h.z + depth / 2.0),
            rotation: front.rotation,
            half_extents: Vector3::new(h.x - shrink, h.y - shrink, depth / 2.0),
        };
        let clear = PlacedShape::new(&Shape::cuboid(body.half_extents), &body.world_from_box())
            .is_some_and(|placed| base.iter().all(|b| b.gap(&placed) > 0.0));
        if clear {
            return (
                Some(body),
                format!(
                    "drawer body modelled behind the front, {depth:.2} m deep (its upper \
                     limit), {:.0} mm narrower on each side than the front (clear of the base \
                     map)",
                    shrink * 1e3
                ),
            );
        }
        shrink += BODY_SHRINK_STEP;
    }
    (
        None,
        format!(
            "no drawer body modelled: the base map leaves no room behind the front (checked \
             {depth:.2} m deep, up to {:.0} mm narrower on each side)",
            limit * 1e3
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 0.4 × 0.6 m front in the plane y = 0, x in [0, 0.4], z in [0, 0.6], sampled every
    /// centimetre (41 × 61 points).
    fn front_grid() -> Vec<Point3<f64>> {
        (0..=40)
            .flat_map(|i| (0..=60).map(move |k| Point3::new(i as f64 * 0.01, 0.0, k as f64 * 0.01)))
            .collect()
    }

    /// A 0.4 × 0.6 m front in the plane y = 0 (outward normal −y) sampled every centimetre, a
    /// 2 × 16 cm handle bar 3 cm in front of it, and two stray points 1.2 cm out at the far
    /// edge (depth noise). Hand-derived: the surface (median depth) is y = 0; the handle's 2 × 17
    /// = 34 points form one cluster standing 3 cm out; the two strays are too few (and stand
    /// out less than 1.5 × 1 cm) and are dropped; no front point is moved (all lie on the surface).
    #[test]
    fn a_handle_is_split_from_the_front() {
        let mut points = front_grid();
        let front_len = points.len();
        for i in 0..2 {
            for k in 0..=16 {
                points.push(Point3::new(
                    0.3 + i as f64 * 0.01,
                    -0.03,
                    0.2 + k as f64 * 0.01,
                ));
            }
        }
        points.push(Point3::new(0.0, -0.012, 0.0));
        points.push(Point3::new(0.0, -0.012, 0.01));
        let s = DiscoverySettings::default();
        let FrontSplit {
            front,
            protrusions: clusters,
            dropped,
            outside,
        } = split_front(points, &-Vector3::y(), &s);
        assert_eq!(outside, 0);
        assert_eq!(front.len(), front_len);
        assert!(front.iter().all(|p| p.y == 0.0));
        assert_eq!(clusters.len(), 1);
        assert_eq!(clusters[0].len(), 34);
        assert!(clusters[0].iter().all(|p| p.y == -0.03));
        assert_eq!(dropped, 2);
        // No split with the standoff off.
        let off = DiscoverySettings {
            handle_standoff: 0.0,
            ..DiscoverySettings::default()
        };
        let none = split_front(front.clone(), &-Vector3::y(), &off);
        assert_eq!((none.front.len(), none.protrusions.len()), (front_len, 0));
    }

    /// The same 0.4 × 0.6 m front (x in [0, 0.4], z in [0, 0.6]) with two 3 cm proud bars of
    /// 2 × 17 points: one across its middle (x = 0.2), and one 5 cm past its right edge
    /// (x = 0.45, the edge of a neighbouring front taken along). Hand-derived: the outline is
    /// x in [0, 0.4] (the 1 % trim of 41 columns cuts nothing whole: it cuts 25 of 2501
    /// points, less than the 61 of a column); the first bar's centre is inside it and is kept;
    /// the second's (x = 0.455) is not and is dropped as outside.
    #[test]
    fn a_protrusion_beyond_the_front_is_not_the_part_s() {
        let mut points = front_grid();
        for x0 in [0.2, 0.45] {
            for i in 0..2 {
                for k in 0..=16 {
                    points.push(Point3::new(
                        x0 + i as f64 * 0.01,
                        -0.03,
                        0.2 + k as f64 * 0.01,
                    ));
                }
            }
        }
        let split = split_front(points, &-Vector3::y(), &DiscoverySettings::default());
        assert_eq!(split.protrusions.len(), 1);
        assert!(split.protrusions[0].iter().all(|p| p.x < 0.25));
        assert_eq!(split.outside, 34);
        assert_eq!(split.dropped, 0);
    }
}
