//! Preparing the estimated model for planning: boxes that overlap at the closed state are cut
//! back face by face.
//!
//! The discovery stage registers each part as the trimmed bounding box of its observed points
//! (points on the base map dropped). Depth noise and a few segmented points of a neighbouring
//! front make a box reach a centimetre or two past the true surface, and the kitchen's
//! adjacent fronts are 3–6 mm apart, so neighbouring estimated boxes can overlap at the closed
//! state; the task layer then finds every move of either part colliding. The robot saw them
//! closed side by side, so the closed state is collision-free: each overlapping pair is
//! resolved by moving the one box face that resolves it with the least volume (a face of
//! either part in a part–part pair, of the part in a part–base pair), by the smallest cut of
//! [`CUTS`] that separates them. The other faces keep their extent: shrinking every box on
//! every side (this module's first version) took 2 cm off the dishwasher door's edge next to
//! the sink door, and the arm reaching for the sink door's handle then touched the real door.

use kinscene::scene::collision::{Body, CollisionSettings, collisions, collisions_of};
use kinscene::scene::{SceneData, SceneModel, Shape, State, forward_kinematics};
use nalgebra::{Translation3, Vector3};

use super::PipelineError;

/// Face cuts tried (m), smallest first.
const CUTS: [f64; 8] = [0.003, 0.006, 0.01, 0.015, 0.02, 0.03, 0.05, 0.08];
/// The smallest half extent (m) a cut box keeps.
const MIN_HALF_EXTENT: f64 = 0.005;
/// Pairs resolved at most (each round resolves one).
const MAX_ROUNDS: usize = 40;

/// One face cut: part index, collider index, box axis, side (+1 or −1), depth (m).
#[derive(Debug, Clone, Copy)]
struct Cut {
    part: usize,
    collider: usize,
    axis: usize,
    side: f64,
    depth: f64,
}

/// `model` with `cut` applied: the box face moved inward by `cut.depth`, the opposite face
/// kept. `None` if the collider is not a box or too thin for the cut.
fn apply(model: &SceneModel, cut: Cut) -> Result<Option<SceneModel>, PipelineError> {
    let mut builder = model.to_builder();
    let Some(c) = builder
        .parts
        .get_mut(cut.part)
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
    Ok(Some(builder.build()?))
}

/// The body pairs colliding at `state`.
fn collisions_at(model: &SceneModel, state: &State) -> Result<Vec<(Body, Body)>, PipelineError> {
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, state)?;
    Ok(collisions(model, &data, &CollisionSettings::default())?
        .into_iter()
        .map(|c| (c.a, c.b))
        .collect())
}

/// Whether `part` still collides with `other` at `state`.
fn still_colliding(
    model: &SceneModel,
    state: &State,
    part: usize,
    other: Body,
) -> Result<bool, PipelineError> {
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, state)?;
    let Some(id) = model.parts().get(part).map(|p| p.id()) else {
        return Ok(false);
    };
    let contacts = collisions_of(model, &data, &CollisionSettings::default(), id)?;
    Ok(contacts.iter().any(|c| c.a == other || c.b == other))
}

/// The cut of least volume that separates the pair `(a, b)` at `state`, with the cut model.
fn best_cut(
    model: &SceneModel,
    state: &State,
    a: Body,
    b: Body,
) -> Result<Option<(Cut, SceneModel)>, PipelineError> {
    let mut best: Option<(f64, Cut, SceneModel)> = None;
    for (me, other) in [(a, b), (b, a)] {
        let Body::Part(p) = me else { continue };
        let k = p.index();
        let Some(part) = model.parts().get(k) else {
            continue;
        };
        for (i, collider) in part.colliders().iter().enumerate() {
            let Shape::Cuboid { half_extents: h } = &collider.shape else {
                continue;
            };
            for axis in 0..3 {
                // Volume removed per metre of cut: the face's area.
                let area = 4.0 * h[(axis + 1) % 3] * h[(axis + 2) % 3];
                for side in [1.0, -1.0] {
                    for depth in CUTS {
                        let volume = area * depth;
                        if best.as_ref().is_some_and(|(v, _, _)| *v <= volume) {
                            break;
                        }
                        let cut = Cut {
                            part: k,
                            collider: i,
                            axis,
                            side,
                            depth,
                        };
                        let Some(cut_model) = apply(model, cut)? else {
                            break;
                        };
                        if !still_colliding(&cut_model, state, k, other)? {
                            best = Some((volume, cut, cut_model));
                            break;
                        }
                    }
                }
            }
        }
    }
    Ok(best.map(|(_, c, m)| (c, m)))
}

/// The estimated model with the boxes that overlap at the closed state cut back (see the
/// module docs), and the body pairs still colliding at the closed state after that (names).
///
/// # Errors
/// [`PipelineError::Scene`] if a cut model cannot be built (it is the input's tree with
/// smaller boxes, so only an invalid input fails).
pub fn separate_boxes(
    est: &SceneModel,
) -> Result<(SceneModel, Vec<(String, String)>), PipelineError> {
    separate_boxes_at(est, &est.zero_state())
}

/// As [`separate_boxes`], at `state`: a state the robot saw (a goal sequence's start, with a
/// door wide open next to closed drawers) is collision-free, so boxes that overlap there are
/// cut back the same way.
///
/// # Errors
/// As [`separate_boxes`].
pub fn separate_boxes_at(
    est: &SceneModel,
    state: &State,
) -> Result<(SceneModel, Vec<(String, String)>), PipelineError> {
    let mut model = est.clone();
    let mut unresolved: Vec<(Body, Body)> = Vec::new();
    for _ in 0..MAX_ROUNDS {
        let pairs = collisions_at(&model, state)?;
        let Some(&(a, b)) = pairs.iter().find(|p| !unresolved.contains(p)) else {
            break;
        };
        match best_cut(&model, state, a, b)? {
            Some((_, cut_model)) => model = cut_model,
            None => unresolved.push((a, b)),
        }
    }
    let pairs = collisions_at(&model, state)?;
    let name = |b: Body| match b {
        Body::Part(p) => model
            .part(p)
            .map_or_else(|| "a part".to_string(), |p| p.name().to_string()),
        Body::Base(s) => model
            .base_shape(s)
            .map_or_else(|| "the base".to_string(), |s| s.name.clone()),
    };
    let named = pairs.into_iter().map(|(a, b)| (name(a), name(b))).collect();
    Ok((model, named))
}

#[cfg(test)]
mod tests {
    use kinscene::scene::{Joint, JointKind, Limits, PartSpec, SceneModelBuilder};
    use nalgebra::{Isometry3, Vector3};

    use super::*;

    /// Two drawer fronts side by side whose estimated boxes overlap by 1 cm in x at the closed
    /// state (left: x 0 .. 0.50, right: x 0.49 .. 0.79; both 2 cm thick, 0.4 m tall). The
    /// cheapest separating cut moves one x face (the face areas are 0.02 × 0.4 m², against
    /// 0.5 × 0.4 or 0.3 × 0.4 for the y faces and 0.5 × 0.02 or 0.3 × 0.02 for the z faces, which
    /// could not separate them anyway): after it no pair collides, one box lost some x extent
    /// on its inner side only (at least the 1 cm overlap, at most the largest cut) and every
    /// other extent and face is unchanged.
    #[test]
    fn overlapping_fronts_are_cut_on_one_face() {
        let mut b = SceneModelBuilder::new();
        for (name, lo, hi) in [("left", 0.0, 0.50), ("right", 0.49, 0.79)] {
            let joint = Joint::new(
                format!("{name}_slide"),
                JointKind::Prismatic,
                Isometry3::identity(),
                -Vector3::y(),
                Limits::new(0.0, 0.4),
            );
            b.add_part(PartSpec::on_base(name, joint).with_collider(
                Shape::cuboid(Vector3::new((hi - lo) / 2.0, 0.01, 0.2)),
                Isometry3::translation((lo + hi) / 2.0, 0.01, 0.5),
            ));
        }
        let est = b.build().unwrap();
        assert!(!collisions_at(&est, &est.zero_state()).unwrap().is_empty());
        let (cut, left) = separate_boxes(&est).unwrap();
        assert!(left.is_empty(), "{left:?}");
        assert!(collisions_at(&cut, &cut.zero_state()).unwrap().is_empty());
        // World x range of each part's box.
        let range = |m: &SceneModel, k: usize| {
            let c = &m.parts()[k].colliders()[0];
            let Shape::Cuboid { half_extents: h } = &c.shape else {
                panic!("a box")
            };
            let x = c.part_from_shape.translation.x;
            ([x - h.x, x + h.x], [h.y, h.z])
        };
        let before = [range(&est, 0), range(&est, 1)];
        let after = [range(&cut, 0), range(&cut, 1)];
        let changed: Vec<usize> = (0..2).filter(|&k| before[k] != after[k]).collect();
        assert_eq!(changed.len(), 1, "{before:?} → {after:?}");
        let k = changed[0];
        assert_eq!(before[k].1, after[k].1, "y and z extents kept");
        // The outer face stays; the inner one moves in by one of CUTS.
        let (outer, inner) = if k == 0 { (0, 1) } else { (1, 0) };
        assert!((before[k].0[outer] - after[k].0[outer]).abs() < 1e-12);
        let moved = (before[k].0[inner] - after[k].0[inner]).abs();
        assert!(
            CUTS.iter().any(|c| (c - moved).abs() < 1e-12) && moved >= 0.01,
            "moved {moved}"
        );
    }
}
