//! How far a handle stands off its part's front: the room a gripper's fingertips have behind
//! the grasp point.

use nalgebra::{Isometry3, Point3};

use crate::scene::{Error, HandleId, SceneModel};

/// A grasp point at most this deep inside a shape (m) lies on that shape's surface: the shape
/// is part of the front, not the handle's own bar or knob.
const ON_SURFACE: f64 = 1e-3;

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
    let part = handle.part();
    let identity = Isometry3::identity();
    let p: Point3<f64> = h.position;
    let inward = -h.normal.normalize();
    let mut best: Option<f64> = None;
    for shape in &model.geometry.parts[part.index()] {
        let (nearest, inside) = shape.project_point(&identity, &p);
        if inside && (nearest - p).norm() > ON_SURFACE {
            continue;
        }
        if let Some(t) = shape.cast_ray(&identity, &p, &inward, max) {
            best = Some(best.map_or(t, |b: f64| b.min(t)));
        }
    }
    Ok(best)
}
