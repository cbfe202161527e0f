//! Register (Algorithm 1, last line): one estimated part and joint into the scene model.
//! The part's front, its boxes and its handle's grasp point are in `front.rs`.

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};

use super::cloud::{VoxelIndex, connected_to};
use super::front::{front, grasp_point, part_boxes};
use super::settings::DiscoverySettings;
use super::shapes::PlacedShape;
use crate::articulation::{Estimate, JointEstimate, PointCloud};
use crate::scene::{
    Handle, Joint, JointKind, Limits, PartSpec, SceneData, SceneModel, Shape, State,
    forward_kinematics,
};

/// Moving points farther than this (m) from the contact are not used for the fallback
/// segmentation (a kitchen front is at most about a metre wide).
const SEGMENT_RADIUS: f64 = 1.0;
/// Part points within this distance (m) of the contact seed the connectivity filter.
const SEED_RADIUS: f64 = 0.06;
/// Connectivity radius (m) of the part's points: points of one surface seen by a depth camera
/// at a metre are millimetres to a centimetre apart; separate surfaces (the floor below a
/// door) are farther.
pub(super) const CONNECTIVITY: f64 = 0.03;
/// The fallback segmentation's change threshold is at least this multiple of the median
/// pre → post nearest-neighbour distance (the sampling and noise scale of the scene).
const NOISE_MULTIPLIER: f64 = 4.0;

/// The observations of one explored handle, as the estimator saw them.
pub(crate) struct Observed<'a> {
    /// Pre-interaction observation (the closed pose).
    pub pre: &'a PointCloud,
    /// Post-interaction observation.
    pub post: &'a PointCloud,
    /// Contact before the interaction (m).
    pub contact_pre: Point3<f64>,
    /// Outward surface normal at the contact before the interaction (unit, map frame).
    pub normal: Unit<Vector3<f64>>,
}

/// A part ready to add to the builder, with its current joint value.
pub(crate) struct NewPart {
    /// The part.
    pub spec: PartSpec,
    /// The joint value the part was left at (the observed opening, within the limits).
    pub value: f64,
    /// Notes for the log.
    pub notes: Vec<String>,
    /// The part's colliders placed at its pre-interaction (closed) pose, map frame.
    pub closed: Vec<PlacedShape>,
    /// The part's estimated motion from the closed pose to where it was left, map frame.
    pub world_motion: Isometry3<f64>,
}

impl NewPart {
    /// Whether `p` (map frame) lies within `margin` of the part's closed-pose colliders.
    pub(crate) fn carries(&self, p: &Point3<f64>, margin: f64) -> bool {
        self.closed.iter().any(|c| c.distance(p) <= margin)
    }
}

/// An estimated joint in the map frame, oriented so that the observed opening is positive.
pub(super) struct JointLine {
    pub(super) kind: JointKind,
    /// Unit axis, map frame.
    pub(super) axis: Vector3<f64>,
    /// A point on the axis: the foot of the perpendicular from the contact (revolute), the
    /// contact (prismatic).
    pub(super) origin: Point3<f64>,
    /// The observed opening (rad or m), at least 0.
    pub(super) motion: f64,
    /// The joint's upper limit: the opening or the default upper limit, the larger.
    pub(super) upper: f64,
}

/// Builds the part of handle `index` from `estimate` (see [`discover`](super::discover) for
/// the rules). `Err` carries the reason the estimate cannot be registered.
pub(crate) fn new_part(
    index: usize,
    estimate: &Estimate,
    observed: &Observed<'_>,
    model: &SceneModel,
    state: &State,
    s: &DiscoverySettings,
) -> Result<NewPart, String> {
    let mut notes = Vec::new();
    let c = observed.contact_pre;
    let line = joint_line(estimate, c, s, &mut notes)?;
    let (mut spec, world_from_joint) = attach(index, &line, c, model, state, s)?;
    // Part frame = joint frame at value 0 = the closed pose observed before the interaction.
    let part_from_world = world_from_joint.inverse();
    let points = part_points(estimate, observed, model, &line, s, &mut notes);
    let (split, normal) = front(points, &line.axis, &observed.normal, s, &mut notes);
    let grasp = grasp_point(&split.protrusions, &c, &mut notes);
    let boxes = part_boxes(&split, &line, &normal, model, s, &mut notes);
    let boxed = !boxes.is_empty();
    for b in boxes {
        spec = spec.with_collider(
            Shape::cuboid(b.half_extents),
            part_from_world * b.world_from_box(),
        );
    }
    if !boxed {
        notes.push("no part geometry: registered without a collider".into());
    }
    // The handle faces where its front faces: the front's fitted normal, not the normal the
    // wrist camera estimated at the contact, which a patch at the bar's side or the front's
    // edge tilts by tens of degrees (the planner approaches and retreats along it).
    let handle_name = format!("{}_handle", spec.name);
    spec = spec.with_handle(Handle::new(
        handle_name,
        part_from_world * grasp,
        part_from_world * normal,
    ));
    let world_from_part = world_from_joint;
    let closed = spec
        .colliders
        .iter()
        .filter_map(|c| PlacedShape::new(&c.shape, &(world_from_part * c.part_from_shape)))
        .collect();
    let value = line.motion.min(line.upper);
    Ok(NewPart {
        world_motion: joint_motion(line.kind, &line.axis, &line.origin, value),
        spec,
        value,
        notes,
        closed,
    })
}

/// The joint of `estimate` in the map frame through the contact `c` (the gravity prior
/// applied, noted), oriented so that the observed opening is positive. `Err` for an unknown
/// joint or non-finite numbers.
fn joint_line(
    estimate: &Estimate,
    c: Point3<f64>,
    s: &DiscoverySettings,
    notes: &mut Vec<String>,
) -> Result<JointLine, String> {
    // Joint in the map frame, oriented so that the observed opening is positive.
    let (kind, axis, origin, motion, default_upper) = match &estimate.joint {
        JointEstimate::Revolute { axis, pivot, angle } => {
            let a = axis.into_inner();
            // The foot of the perpendicular from the contact onto the axis.
            let foot = pivot + a * (c - pivot).dot(&a);
            (
                JointKind::Revolute,
                a,
                foot,
                *angle,
                s.default_revolute_upper,
            )
        }
        JointEstimate::Prismatic { axis, distance } => (
            JointKind::Prismatic,
            axis.into_inner(),
            c,
            *distance,
            s.default_prismatic_upper,
        ),
        JointEstimate::Unknown { reason } => return Err(format!("unknown joint: {reason}")),
    };
    let finite = axis
        .iter()
        .chain(origin.coords.iter())
        .chain(std::iter::once(&motion))
        .all(|v| v.is_finite());
    if !finite {
        return Err("estimate has non-finite numbers".into());
    }
    let (axis, level) = level_axis(&axis, s.axis_snap);
    if let Some((tilt, to)) = level {
        notes.push(format!(
            "axis made {to} (the gravity prior, axis_snap): the estimate was {:.1}° off",
            tilt.to_degrees()
        ));
    }
    let (axis, motion) = if motion < 0.0 {
        (-axis, -motion)
    } else {
        (axis, motion)
    };
    let upper = motion.max(default_upper);
    Ok(JointLine {
        kind,
        axis,
        origin,
        motion,
        upper,
    })
}

/// The part of handle `index` on its parent (the registered part the handle at `c` lies on at
/// `state`, else the base), its joint at `line`'s origin with axes aligned with the map frame
/// at discovery time; with the joint frame in the map frame.
fn attach(
    index: usize,
    line: &JointLine,
    c: Point3<f64>,
    model: &SceneModel,
    state: &State,
    s: &DiscoverySettings,
) -> Result<(PartSpec, Isometry3<f64>), String> {
    let JointLine {
        kind,
        axis,
        origin,
        upper,
        ..
    } = *line;
    // Parent: the registered part the handle lies on, else the base.
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, state).map_err(|e| e.to_string())?;
    let parent = nest_parent(model, &data, &c, s.nest_margin);
    let world_from_parent = parent
        .map(|k| data.world_from_parts()[k])
        .unwrap_or_else(Isometry3::identity);
    // The joint frame: at the origin, axes aligned with the map frame at discovery time.
    let world_from_joint = Isometry3::from_parts(
        Translation3::from(origin.coords),
        UnitQuaternion::identity(),
    );
    let parent_from_joint = world_from_parent.inverse() * world_from_joint;
    let name = format!("part{index}");
    let joint_name = match kind {
        JointKind::Revolute => format!("{name}_hinge"),
        JointKind::Prismatic => format!("{name}_slide"),
    };
    let joint = Joint::new(
        joint_name,
        kind,
        parent_from_joint,
        axis,
        Limits::new(0.0, upper),
    );
    let spec = match parent {
        Some(k) => PartSpec::on_part(name.clone(), model.parts()[k].name(), joint),
        None => PartSpec::on_base(name.clone(), joint),
    };
    Ok((spec, world_from_joint))
}

/// The part's points at the closed pose: the estimator's, or with fewer than 4 those the
/// fallback segmentation finds; without the points beyond the hinge line, near the base map
/// or not connected to the contact (each drop noted).
fn part_points(
    estimate: &Estimate,
    observed: &Observed<'_>,
    model: &SceneModel,
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
    let points = clear_of_base(model, points, s.base_clearance);
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
pub(super) fn placed_base(model: &SceneModel) -> Vec<PlacedShape> {
    model
        .base()
        .shapes
        .iter()
        .filter_map(|b| PlacedShape::new(&b.shape, &b.world_from_shape))
        .collect()
}

/// The gravity prior of [`DiscoverySettings::axis_snap`]: `axis` (unit) projected onto the
/// horizontal plane if it is within `limit` (rad) of it, made vertical (keeping its sense) if
/// within `limit` of the vertical, else unchanged; with the angle it was off and what it was
/// made, when changed.
fn level_axis(axis: &Vector3<f64>, limit: f64) -> (Vector3<f64>, Option<(f64, &'static str)>) {
    let from_horizontal = axis.z.abs().clamp(0.0, 1.0).asin();
    let from_vertical = std::f64::consts::FRAC_PI_2 - from_horizontal;
    if limit <= 0.0 {
        (*axis, None)
    } else if from_horizontal <= limit && from_horizontal > 0.0 {
        // |z| <= sin(limit) < sin 45°: the horizontal part is not zero.
        let flat = Vector3::new(axis.x, axis.y, 0.0).normalize();
        (flat, Some((from_horizontal, "horizontal")))
    } else if from_vertical <= limit && from_vertical > 0.0 {
        let up = Vector3::new(0.0, 0.0, axis.z.signum());
        (up, Some((from_vertical, "vertical")))
    } else {
        (*axis, None)
    }
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
/// from every shape of the model's base map. A front closed in its carcass stands in front of
/// the static surfaces around it, so points on them are static surfaces taken for the part
/// (seen through the gap the open part left, or within the segmentation's tolerance); kept in
/// the box they make it overlap the carcass at the closed state.
fn clear_of_base(model: &SceneModel, points: Vec<Point3<f64>>, clearance: f64) -> Vec<Point3<f64>> {
    if clearance <= 0.0 {
        return points;
    }
    let base = placed_base(model);
    points
        .into_iter()
        .filter(|p| base.iter().all(|b| b.distance(p) > clearance))
        .collect()
}

/// The nesting rule: the registered part (index) with a collider within `margin` of `p` at the
/// current state, the nearest one; ties go to the deeper part.
fn nest_parent(
    model: &SceneModel,
    data: &SceneData,
    p: &Point3<f64>,
    margin: f64,
) -> Option<usize> {
    let mut best: Option<(f64, usize, usize)> = None;
    for part in model.parts() {
        let k = part.id().index();
        let world_from_part = data.world_from_parts()[k];
        for collider in part.colliders() {
            let Some(shape) = PlacedShape::new(
                &collider.shape,
                &(world_from_part * collider.part_from_shape),
            ) else {
                continue;
            };
            let d = shape.distance(p);
            if d > margin {
                continue;
            }
            let better = match best {
                None => true,
                Some((bd, depth, _)) => d < bd - 1e-9 || (d <= bd + 1e-9 && part.depth() > depth),
            };
            if better {
                best = Some((d, part.depth(), k));
            }
        }
    }
    best.map(|(_, _, k)| k)
}

/// The estimated motion pre → post as a map-frame transform.
fn joint_motion(
    kind: JointKind,
    axis: &Vector3<f64>,
    origin: &Point3<f64>,
    motion: f64,
) -> Isometry3<f64> {
    match kind {
        JointKind::Revolute => {
            let to = Isometry3::translation(origin.x, origin.y, origin.z);
            to * Isometry3::rotation(axis * motion) * to.inverse()
        }
        JointKind::Prismatic => {
            let t = axis * motion;
            Isometry3::translation(t.x, t.y, t.z)
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The dishwasher door of kitchen seed 4, estimated 4.6° off horizontal (z = sin 4.65°),
    /// is made horizontal with its x/y direction kept; a hinge 3° off vertical becomes ±z with
    /// its sense kept; a 30° axis is left alone at a 10° limit; a limit of 0 leaves all.
    /// Expected values by hand: (0.9967, −0.0027) normalised, asin(0.081) = 4.65°, asin of
    /// cos 3° = 87°.
    #[test]
    fn a_nearly_level_axis_is_levelled() {
        let limit = 10f64.to_radians();
        let door = Vector3::new(0.9967, -0.0027, 0.081).normalize();
        let (flat, why) = level_axis(&door, limit);
        let (tilt, to) = why.expect("levelled");
        assert_eq!(to, "horizontal");
        assert!(
            (tilt.to_degrees() - 4.65).abs() < 0.01,
            "{}",
            tilt.to_degrees()
        );
        assert_eq!(flat.z, 0.0);
        assert!((flat.norm() - 1.0).abs() < 1e-12);
        let xy = Vector3::new(0.9967, -0.0027, 0.0).normalize();
        assert!((flat - xy).norm() < 1e-12);
        let three = 3f64.to_radians();
        let hinge = Vector3::new(three.sin(), 0.0, -three.cos());
        let (up, why) = level_axis(&hinge, limit);
        assert_eq!(up, Vector3::new(0.0, 0.0, -1.0));
        assert!((why.expect("levelled").0.to_degrees() - 3.0).abs() < 1e-9);
        let thirty = 30f64.to_radians();
        let steep = Vector3::new(thirty.cos(), 0.0, thirty.sin());
        assert_eq!(level_axis(&steep, limit), (steep, None));
        assert_eq!(level_axis(&door, 0.0), (door, None));
        let exact = Vector3::new(0.0, 1.0, 0.0);
        assert_eq!(level_axis(&exact, limit), (exact, None));
    }
}
