//! The face cuts: one cut, a model with cuts applied, and the least-volume cuts that resolve a
//! conflict.

use nalgebra::{Translation3, Vector3};

use super::conflicts::still_conflicting;
use super::{CUTS, MIN_HALF_EXTENT, Observation};
use crate::discovery::error::DiscoveryError;
use crate::scene::collision::{Body, SweepSettings};
use crate::scene::{PartId, SceneModel, Shape};

/// One face cut: part, collider index, box axis, side (+1 or −1), depth (m).
#[derive(Debug, Clone, Copy)]
pub(super) struct Cut {
    pub(super) part: PartId,
    pub(super) collider: usize,
    pub(super) axis: usize,
    pub(super) side: f64,
    pub(super) depth: f64,
}

/// `model` with `cuts` applied: each box face moved inward by its depth, the opposite face
/// kept. `None` if a collider is not a box or too thin for its cuts.
fn apply(model: &SceneModel, cuts: &[Cut]) -> Result<Option<SceneModel>, DiscoveryError> {
    let mut builder = model.to_builder();
    for cut in cuts {
        let Some(c) = builder
            .parts
            .get_mut(cut.part.index())
            .and_then(|p| p.colliders.get_mut(cut.collider))
        else {
            return Ok(None);
        };
        let Shape::Cuboid { half_extents } = &mut c.shape else {
            return Ok(None);
        };
        let half = half_extents[cut.axis] - cut.depth / 2.0;
        if half < MIN_HALF_EXTENT {
            return Ok(None);
        }
        half_extents[cut.axis] = half;
        let mut shift = Vector3::zeros();
        shift[cut.axis] = -cut.side * cut.depth / 2.0;
        c.part_from_shape *= Translation3::from(shift);
    }
    Ok(Some(builder.build()?))
}

/// The cuts of least volume that resolve the conflict of `(a, b)` in `observation`, with the
/// cut model, among the faces of `parts` (the conflict's parts, or some of them). One face; in a
/// [`Observation::State`] also two faces of the same box (a box tilted into a corner of a
/// carcass overlaps it on two sides), which a sweep is too costly to try.
pub(super) fn best_cut(
    model: &SceneModel,
    observation: &Observation,
    sweep: &SweepSettings,
    a: Body,
    b: Body,
    parts: &[PartId],
) -> Result<Option<(Vec<Cut>, SceneModel)>, DiscoveryError> {
    // Every candidate with the volume it removes (face area times depth), tried cheapest
    // first: the first that resolves the conflict is the least-volume one.
    let mut candidates: Vec<(f64, Vec<Cut>)> = Vec::new();
    for &p in parts {
        let Some(part) = model.part(p) else { continue };
        for (i, collider) in part.colliders().iter().enumerate() {
            let Shape::Cuboid { half_extents: h } = &collider.shape else {
                continue;
            };
            let mut faces = Vec::new();
            for axis in 0..3 {
                let area = 4.0 * h[(axis + 1) % 3] * h[(axis + 2) % 3];
                for side in [1.0, -1.0] {
                    for depth in CUTS {
                        let cut = Cut {
                            part: p,
                            collider: i,
                            axis,
                            side,
                            depth,
                        };
                        faces.push((area * depth, cut));
                    }
                }
            }
            candidates.extend(faces.iter().map(|(v, c)| (*v, vec![*c])));
            if matches!(observation, Observation::State(_)) {
                for (x, (v1, c1)) in faces.iter().enumerate() {
                    for (v2, c2) in &faces[x + 1..] {
                        if (c1.axis, c1.side) != (c2.axis, c2.side) {
                            candidates.push((v1 + v2, vec![*c1, *c2]));
                        }
                    }
                }
            }
        }
    }
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0));
    for (_, cuts) in candidates {
        let Some(cut_model) = apply(model, &cuts)? else {
            continue;
        };
        if !still_conflicting(&cut_model, observation, sweep, a, b)? {
            return Ok(Some((cuts, cut_model)));
        }
    }
    Ok(None)
}
