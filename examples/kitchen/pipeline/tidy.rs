//! Preparing the estimated model for planning: its part boxes shrunk by the depth noise.
//!
//! The discovery stage registers each part as the trimmed bounding box of its observed
//! points; with depth noise σ the box reaches about 2σ beyond the true surfaces. The
//! kitchen's adjacent fronts are 3–6 mm apart, so neighbouring estimated boxes overlap at the
//! closed state, and the task layer then finds every move of either part colliding (two
//! island drawers estimated 1 cm too wide cannot be opened at all). The pipeline shrinks every
//! estimated box by 2σ per side before planning, the same margin the noise added; parts that
//! still collide at the closed state (a box shifted by a few segmented points of the
//! neighbouring front) are shrunk further, 5 mm per side at a time up to 5 cm, since the
//! robot saw them closed side by side: the closed state is collision-free.

use kinscene::scene::collision::{Body, CollisionSettings, collisions};
use kinscene::scene::{SceneData, SceneModel, Shape, forward_kinematics};

use super::PipelineError;

/// The smallest half extent (m) a shrunk box keeps.
const MIN_HALF_EXTENT: f64 = 0.005;
/// Extra shrink (m per side) of a part still colliding at the closed state, per round.
const EXTRA_STEP: f64 = 0.005;
/// Rounds of extra shrinking.
const EXTRA_ROUNDS: usize = 10;

/// Shrinks the box colliders of the parts `which` (indices; all when `None`) by `by` (m) per
/// side, half extents at least 5 mm.
fn shrink(
    model: &SceneModel,
    which: Option<&[usize]>,
    by: f64,
) -> Result<SceneModel, PipelineError> {
    let mut builder = model.to_builder();
    for (k, part) in builder.parts.iter_mut().enumerate() {
        if which.is_some_and(|w| !w.contains(&k)) {
            continue;
        }
        for c in &mut part.colliders {
            if let Shape::Cuboid { half_extents } = &mut c.shape {
                for h in half_extents.iter_mut() {
                    *h = (*h - by).max(MIN_HALF_EXTENT.min(*h));
                }
            }
        }
    }
    Ok(builder.build()?)
}

/// The bodies colliding at the model's zero state.
fn closed_collisions(model: &SceneModel) -> Result<Vec<(Body, Body)>, PipelineError> {
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, &model.zero_state())?;
    Ok(collisions(model, &data, &CollisionSettings::default())?
        .into_iter()
        .map(|c| (c.a, c.b))
        .collect())
}

/// The estimated model with every box collider shrunk by `erosion` (m) per side, then the
/// parts still colliding at the closed state shrunk further (see the module docs); and the
/// body pairs colliding at the closed state after that (names).
///
/// # Errors
/// [`PipelineError::Scene`] if a shrunk model cannot be built (it is the input's tree with
/// smaller boxes, so only an invalid input fails).
pub fn shrink_boxes(
    est: &SceneModel,
    erosion: f64,
) -> Result<(SceneModel, Vec<(String, String)>), PipelineError> {
    let mut model = shrink(est, None, erosion)?;
    let mut pairs = closed_collisions(&model)?;
    for _ in 0..EXTRA_ROUNDS {
        let mut parts: Vec<usize> = pairs
            .iter()
            .flat_map(|(a, b)| [*a, *b])
            .filter_map(|b| match b {
                Body::Part(p) => Some(p.index()),
                Body::Base(_) => None,
            })
            .collect();
        parts.sort_unstable();
        parts.dedup();
        if parts.is_empty() {
            break;
        }
        model = shrink(&model, Some(&parts), EXTRA_STEP)?;
        pairs = closed_collisions(&model)?;
    }
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
