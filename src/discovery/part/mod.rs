//! Register (Algorithm 1, last line): one estimated part and joint into the scene model.
//! The part's front, its boxes and its handle's grasp point are in `front.rs`; here the joint
//! (`joint.rs`), the parent the part is attached to (`attach.rs`) and the part's points
//! (`points.rs`).

mod attach;
mod joint;
mod points;

use nalgebra::{Isometry3, Point3, Unit, Vector3};

use super::front::{front, grasp_point, part_boxes};
use super::settings::DiscoverySettings;
use super::shapes::PlacedShape;
use crate::articulation::{Estimate, PointCloud};
use crate::scene::{Handle, JointKind, PartSpec, SceneModel, Shape, State};
use attach::attach;
use joint::{joint_line, joint_motion, pivot_out_of};
use points::part_points;
pub(super) use points::placed_base;

/// Connectivity radius (m) of the part's points: points of one surface seen by a depth camera
/// at a metre are millimetres to a centimetre apart; separate surfaces (the floor below a
/// door) are farther.
pub(super) const CONNECTIVITY: f64 = 0.03;

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
    let base = placed_base(model);
    let mut line = joint_line(estimate, c, s, &mut notes)?;
    if line.kind == JointKind::Revolute {
        if let Some((moved, d)) = pivot_out_of(&base, &line.axis, &line.origin, &observed.normal) {
            notes.push(format!(
                "the estimated hinge lay inside the base map; moved {d:.3} m out along the \
                 front's normal, clear of it"
            ));
            line.origin = moved;
        }
    }
    let (mut spec, world_from_joint) = attach(index, &line, c, model, state, s)?;
    // Part frame = joint frame at value 0 = the closed pose observed before the interaction.
    let part_from_world = world_from_joint.inverse();
    let points = part_points(estimate, observed, &base, &line, s, &mut notes);
    let (split, normal) = front(points, &line.axis, &observed.normal, s, &mut notes);
    let grasp = grasp_point(&split.protrusions, &c, &mut notes);
    let boxes = part_boxes(&split, &line, &normal, &base, s, &mut notes);
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
