//! How far a handle stands off its part's front: the room a gripper's fingertips have behind
//! the grasp point.

use nalgebra::{Isometry3, Point3, Unit, Vector3};

use super::geometry::CompiledShape;
use crate::scene::{Error, HandleId, SceneModel};

/// A grasp point at most this deep inside a shape (m) lies on that shape's surface: the shape
/// is part of the front, not the handle's own bar or knob.
const ON_SURFACE: f64 = 1e-3;

/// A handle shape is a bar when its longest extent is at least this many times its second
/// longest (a knob or a square boss is not).
const BAR_RATIO: f64 = 2.0;

/// Whether `shape` (part frame) is the handle's own geometry: it holds the grasp point `p`
/// more than [`ON_SURFACE`] deep.
fn holds(shape: &CompiledShape, p: &Point3<f64>) -> bool {
    let (nearest, inside) = shape.project_point(&Isometry3::identity(), p);
    inside && (nearest - p).norm() > ON_SURFACE
}

/// The distance (m) from `handle`'s grasp point, along the inward normal (−normal), to the
/// front of its part: the first surface of the part's collision shapes that do not contain
/// the grasp point. The handle's own geometry (a bar or knob modelled as a shape of the part
/// that holds the grasp point more than 1 mm inside) is passed through. A grasp point on the
/// front's surface gives 0. `None` if no front lies within `max` (m) behind the grasp point,
/// e.g. a part whose only collision shape is its handle.
///
/// The gripper's fingertips reach past the tool origin along the approach; a grasp whose
/// fingertips must stay out of the front backs the tool off by what this leaves short of
/// their reach (the motion layer's `ManipulationSettings::finger_clearance`).
///
/// # Errors
/// [`Error::UnknownId`] for a foreign handle id.
pub fn handle_standoff(
    model: &SceneModel,
    handle: HandleId,
    max: f64,
) -> Result<Option<f64>, Error> {
    let h = model.checked_handle(handle)?;
    let inward = Unit::new_normalize(-h.normal);
    handle_standoff_along(model, handle, &inward, max)
}

/// [`handle_standoff`] along another direction: the distance (m) from the grasp point along
/// `inward` (a unit vector in the part frame, e.g. a grasp direction turned about the
/// handle's bar, [`handle_bar_axis`]) to the first surface of the part's front, `None` if
/// none lies within `max`.
///
/// # Errors
/// [`Error::UnknownId`] for a foreign handle id.
pub fn handle_standoff_along(
    model: &SceneModel,
    handle: HandleId,
    inward: &Unit<Vector3<f64>>,
    max: f64,
) -> Result<Option<f64>, Error> {
    let h = model.checked_handle(handle)?;
    let identity = Isometry3::identity();
    let p: Point3<f64> = h.position;
    let mut best: Option<f64> = None;
    for shape in &model.geometry.parts[handle.part().index()] {
        if holds(shape, &p) {
            continue;
        }
        if let Some(t) = shape.cast_ray(&identity, &p, inward, max) {
            best = Some(best.map_or(t, |b: f64| b.min(t)));
        }
    }
    Ok(best)
}

/// The indices (into the part's collision shapes) of `handle`'s part's *front*: its shapes
/// that do not hold the grasp point more than 1 mm deep (the handle's own bar or knob does).
///
/// # Errors
/// [`Error::UnknownId`] for a foreign handle id.
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
pub(crate) fn handle_front_shapes(
    model: &SceneModel,
    handle: HandleId,
) -> Result<Vec<usize>, Error> {
    let h = model.checked_handle(handle)?;
    Ok(model.geometry.parts[handle.part().index()]
        .iter()
        .enumerate()
        .filter(|(_, s)| !holds(s, &h.position))
        .map(|(k, _)| k)
        .collect())
}

/// The long axis of `handle`'s bar, in the part frame, perpendicular to the handle's normal:
/// the handle's own geometry is the part's collision shape that holds the grasp point more
/// than 1 mm deep (as in [`handle_standoff`]); it is a bar when the longest side of its
/// enclosing box (a box's own sides; a cylinder's or a capsule's axis; a convex mesh's local
/// box), its rounding included, is at least twice the second longest. The axis is that side's
/// direction with its component along the normal removed, normalised. `None` when no shape
/// holds the grasp point, the shape is not a bar (a knob), or the bar points along the normal
/// (its projection shorter than half its length).
///
/// A gripper whose fingers close across such a bar may approach it from any direction
/// perpendicular to the axis, not only along the inward normal.
///
/// # Errors
/// [`Error::UnknownId`] for a foreign handle id.
pub fn handle_bar_axis(
    model: &SceneModel,
    handle: HandleId,
) -> Result<Option<Unit<Vector3<f64>>>, Error> {
    let h = model.checked_handle(handle)?;
    let p: Point3<f64> = h.position;
    let normal = h.normal.normalize();
    let Some(shape) = model.geometry.parts[handle.part().index()]
        .iter()
        .find(|s| holds(s, &p))
    else {
        return Ok(None);
    };
    let (part_from_box, half, radius) = shape.rounded_box();
    let mut sides: Vec<(f64, usize)> = (0..3).map(|i| (half[i] + radius, i)).collect();
    sides.sort_by(|a, b| b.0.total_cmp(&a.0));
    if sides[0].0 < BAR_RATIO * sides[1].0 {
        return Ok(None);
    }
    let long = part_from_box.rotation * Vector3::ith(sides[0].1, 1.0);
    let across = long - normal * long.dot(&normal);
    Ok((across.norm() >= 0.5).then(|| Unit::new_normalize(across)))
}
