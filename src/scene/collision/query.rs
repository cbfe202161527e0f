//! Collision and distance queries at one state.

use std::cell::OnceCell;

use nalgebra::Isometry3;

use crate::InvalidSetting;
use crate::scene::collision::geometry::{Placed, WorldBox};
use crate::scene::collision::settings::{Body, CollisionSettings};
use crate::scene::ids::{BaseShapeId, Parent, PartId};
use crate::scene::{Error, SceneData, SceneModel};

/// A checked pair of bodies and their separation distance (m, 0 when touching or overlapping).
/// `a` is always a part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// The first body (a part; in a sweep, the moving one).
    pub a: Body,
    /// The second body.
    pub b: Body,
    /// Exact separation distance (m).
    pub distance: f64,
}

/// Every collider of the scene placed in the world.
pub(crate) struct Placement<'a> {
    pub parts: Vec<Vec<Placed<'a>>>,
    pub base: Vec<Placed<'a>>,
}

impl<'a> Placement<'a> {
    /// Places all colliders at the poses in `data`.
    pub(crate) fn new(model: &'a SceneModel, data: &SceneData) -> Self {
        let parts = model
            .geometry
            .parts
            .iter()
            .zip(data.world_from_parts())
            .map(|(shapes, pose)| shapes.iter().map(|s| Placed::new(s, pose)).collect())
            .collect();
        let identity = nalgebra::Isometry3::identity();
        let base = model
            .geometry
            .base
            .iter()
            .map(|s| Placed::new(s, &identity))
            .collect();
        Placement { parts, base }
    }

    /// The placed colliders of a body.
    pub(crate) fn body(&self, body: Body) -> &[Placed<'a>] {
        match body {
            Body::Part(p) => &self.parts[p.0],
            Body::Base(b) => std::slice::from_ref(&self.base[b.0]),
        }
    }
}

/// Distance information between two bodies, see [`clearance`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Clearance {
    /// Minimum over the collider pairs whose exact distance was computed (∞ if none).
    pub exact: f64,
    /// A lower bound on the true minimum distance.
    pub lower: f64,
}

/// Collider-pair distances between two bodies. Exact distances are computed for every pair
/// whose bounding-sphere gap is `<= cutoff` and below the best exact distance so far; the
/// other pairs contribute their sphere gap (a lower bound). Hence: if the true minimum is
/// `<= cutoff` then `exact` equals it; `lower` never exceeds it.
pub(crate) fn clearance(a: &[Placed<'_>], b: &[Placed<'_>], cutoff: f64) -> Clearance {
    let mut exact = f64::INFINITY;
    let mut skipped = f64::INFINITY;
    for x in a {
        for y in b {
            let gap = x.sphere_gap(y);
            if gap > cutoff || gap >= exact {
                skipped = skipped.min(gap);
            } else {
                exact = exact.min(x.distance(y));
            }
        }
    }
    Clearance {
        exact,
        lower: exact.min(skipped.max(0.0)),
    }
}

/// The checked body pairs `(part, other)`: with `moving = Some(root)`, the parts of `root`'s
/// subtree against every other body; with `None`, every part against every later part and
/// every base shape.
pub(crate) fn checked_pairs(
    model: &SceneModel,
    settings: &CollisionSettings,
    moving: Option<PartId>,
) -> Vec<(PartId, Body)> {
    let n = model.parts.len();
    let (first, end) = match moving {
        Some(root) => (root.0, model.parts[root.0].subtree_end),
        None => (0, n),
    };
    let adjacent = |a: PartId, b: PartId| {
        model.parts[a.0].parent == Parent::Part(b) || model.parts[b.0].parent == Parent::Part(a)
    };
    let mut pairs = Vec::new();
    for i in first..end {
        let a = PartId(i);
        let others = (0..n)
            .filter(|&j| {
                if moving.is_some() {
                    j < first || j >= end
                } else {
                    j > i
                }
            })
            .map(|j| Body::Part(PartId(j)))
            .chain((0..model.base.shapes.len()).map(|k| Body::Base(BaseShapeId(k))));
        for b in others {
            let skip_adjacent = match b {
                Body::Part(p) => !settings.check_parent_child && adjacent(a, p),
                Body::Base(_) => false,
            };
            if !skip_adjacent && !settings.allowed.is_allowed(Body::Part(a), b) {
                pairs.push((a, b));
            }
        }
    }
    pairs
}

/// Slack (m) of the box pre-filter: a collider pair is skipped only if its boxes are more
/// than `threshold + BOX_SLACK` apart. The slack is far above the rounding of the box corners
/// (about `1e-16` of the coordinates), so a skipped pair is farther apart than `threshold` in
/// exact arithmetic, not only in floating point.
const BOX_SLACK: f64 = 1e-9;

/// World boxes of the colliders of each body, computed on first use.
struct Boxes<'a> {
    model: &'a SceneModel,
    data: &'a SceneData,
    parts: Vec<OnceCell<Vec<WorldBox>>>,
    base: Vec<OnceCell<WorldBox>>,
}

impl<'a> Boxes<'a> {
    fn new(model: &'a SceneModel, data: &'a SceneData) -> Self {
        Boxes {
            model,
            data,
            parts: (0..model.parts.len()).map(|_| OnceCell::new()).collect(),
            base: (0..model.base.shapes.len())
                .map(|_| OnceCell::new())
                .collect(),
        }
    }

    /// The boxes of a body's colliders, in the order of its placed colliders.
    fn body(&self, body: Body) -> &[WorldBox] {
        match body {
            Body::Part(p) => self.parts[p.0].get_or_init(|| {
                let world_from_part = &self.data.world_from_parts()[p.0];
                self.model.geometry.parts[p.0]
                    .iter()
                    .map(|c| c.world_box(world_from_part))
                    .collect()
            }),
            Body::Base(b) => {
                std::slice::from_ref(self.base[b.0].get_or_init(|| {
                    self.model.geometry.base[b.0].world_box(&Isometry3::identity())
                }))
            }
        }
    }
}

/// The exact distance between two bodies (minimum over their collider pairs) if it is
/// `<= threshold`, else `None`. A collider pair is evaluated exactly only if neither its
/// bounding spheres nor its world boxes are farther apart than `threshold` (both are lower
/// bounds on its distance) and its sphere gap is below the best distance so far.
fn distance_within(
    placement: &Placement<'_>,
    boxes: &Boxes<'_>,
    a: Body,
    b: Body,
    threshold: f64,
) -> Option<f64> {
    let mut best = f64::INFINITY;
    let (pa, pb) = (placement.body(a), placement.body(b));
    for (i, x) in pa.iter().enumerate() {
        for (j, y) in pb.iter().enumerate() {
            let gap = x.sphere_gap(y);
            if gap > threshold || gap >= best {
                continue;
            }
            if boxes.body(a)[i].gap(&boxes.body(b)[j]) > threshold + BOX_SLACK {
                continue;
            }
            best = best.min(x.distance(y));
        }
    }
    (best <= threshold).then_some(best)
}

/// Checked pairs whose exact distance is `<= threshold`, at the poses in `data`: every
/// checked pair (`moving = None`) or those between the subtree of `moving` and the other
/// bodies (`a` in the subtree).
fn pairs_within(
    model: &SceneModel,
    data: &SceneData,
    settings: &CollisionSettings,
    moving: Option<PartId>,
    threshold: f64,
) -> Result<Vec<Contact>, Error> {
    settings.validate()?;
    data.check(model)?;
    if let Some(root) = moving {
        model.checked_part(root)?;
    }
    let placement = Placement::new(model, data);
    let boxes = Boxes::new(model, data);
    Ok(checked_pairs(model, settings, moving)
        .into_iter()
        .filter_map(|(a, b)| {
            // Lower part id first, as in `checked_pairs(.., None)`, so that a pair's distance
            // does not depend on which query found it.
            let (first, second) = match b {
                Body::Part(q) if q < a => (b, Body::Part(a)),
                _ => (Body::Part(a), b),
            };
            let distance = distance_within(&placement, &boxes, first, second, threshold)?;
            Some(Contact {
                a: Body::Part(a),
                b,
                distance,
            })
        })
        .collect())
}

/// The colliding body pairs at the state of the last
/// [`forward_kinematics`](crate::scene::forward_kinematics) (predicate: see
/// [`CollisionSettings`]). Exact parry distances are computed only for collider pairs whose
/// bounding spheres and world-aligned boxes (both lower bounds on their distance) are within
/// `contact_distance`; a box skips a pair only when it is more than `1e-9` m beyond it (in
/// exact arithmetic), so the filters change no answer beyond the exact distance query's own
/// tolerance.
///
/// # Errors
/// [`Error::InvalidSetting`] for invalid settings; [`Error::DimensionMismatch`] if `data` is
/// not sized for `model`.
pub fn collisions(
    model: &SceneModel,
    data: &SceneData,
    settings: &CollisionSettings,
) -> Result<Vec<Contact>, Error> {
    pairs_within(model, data, settings, None, settings.contact_distance)
}

/// The colliding body pairs between the subtree of `moving` (the part and its descendants)
/// and every other body, at the state of the last
/// [`forward_kinematics`](crate::scene::forward_kinematics): exactly the pairs of
/// [`collisions`] with one body in the subtree and the other outside it, with the same
/// distances (same predicate, see [`CollisionSettings`]; same pre-filters).
/// Pairs inside the subtree and pairs outside it are not evaluated, which is what makes this
/// cheaper than filtering [`collisions`] when only one subtree moves.
///
/// In each [`Contact`], `a` is the part of the subtree. Order: by the subtree's part id, then
/// the other parts by id, then the base shapes by id.
///
/// # Errors
/// As [`collisions`], and [`Error::UnknownId`] if `moving` is not a part of `model`.
///
/// # Example
/// ```
/// use kinscene::scene::collision::{Body, CollisionSettings, collisions_of};
/// use kinscene::scene::{
///     BaseShape, Joint, Limits, PartSpec, SceneData, SceneModelBuilder, Shape,
///     forward_kinematics,
/// };
/// use nalgebra::{Isometry3, Point3, Vector3};
///
/// // A drawer sliding along +x into a wall at x = 0.5 (wall box x ∈ [0.5, 0.7]).
/// let mut b = SceneModelBuilder::new();
/// b.add_base_shape(BaseShape::new(
///     "wall",
///     Shape::cuboid(Vector3::new(0.1, 1.0, 1.0)),
///     Isometry3::translation(0.6, 0.0, 0.0),
/// ));
/// let slide = Joint::prismatic("slide", Point3::origin(), Vector3::x(), Limits::new(0.0, 0.5));
/// b.add_part(
///     PartSpec::on_base("drawer", slide)
///         .with_collider(Shape::cuboid(Vector3::new(0.2, 0.2, 0.1)), Isometry3::identity()),
/// );
/// let model = b.build()?;
/// let mut data = SceneData::new(&model);
/// let drawer = model.part_id("drawer")?;
/// let settings = CollisionSettings::default();
/// // Closed, the drawer (x ∈ [-0.2, 0.2]) is 0.3 m from the wall.
/// forward_kinematics(&model, &mut data, &model.zero_state())?;
/// assert!(collisions_of(&model, &data, &settings, drawer)?.is_empty());
/// // Pulled 0.4 m, it reaches x = 0.6: inside the wall.
/// let state = kinscene::scene::State::from_slice(&model, &[0.4])?;
/// forward_kinematics(&model, &mut data, &state)?;
/// let contacts = collisions_of(&model, &data, &settings, drawer)?;
/// assert_eq!(contacts.len(), 1);
/// assert_eq!(contacts[0].a, Body::Part(drawer));
/// assert_eq!(contacts[0].distance, 0.0);
/// # Ok::<(), kinscene::scene::Error>(())
/// ```
pub fn collisions_of(
    model: &SceneModel,
    data: &SceneData,
    settings: &CollisionSettings,
    moving: PartId,
) -> Result<Vec<Contact>, Error> {
    pairs_within(
        model,
        data,
        settings,
        Some(moving),
        settings.contact_distance,
    )
}

/// Whether no checked pair collides at the state of the last forward kinematics.
///
/// # Errors
/// As [`collisions`].
pub fn is_collision_free(
    model: &SceneModel,
    data: &SceneData,
    settings: &CollisionSettings,
) -> Result<bool, Error> {
    Ok(collisions(model, data, settings)?.is_empty())
}

/// Every checked pair within `max_distance` (m) of each other, with its exact distance.
///
/// # Errors
/// As [`collisions`], and [`Error::InvalidSetting`] for a negative or NaN `max_distance`.
pub fn distances(
    model: &SceneModel,
    data: &SceneData,
    settings: &CollisionSettings,
    max_distance: f64,
) -> Result<Vec<Contact>, Error> {
    if max_distance.is_nan() || max_distance < 0.0 {
        return Err(InvalidSetting::new("max_distance", max_distance, ">= 0").into());
    }
    pairs_within(model, data, settings, None, max_distance)
}
