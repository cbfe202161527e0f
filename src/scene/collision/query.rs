//! Collision and distance queries at one state.

use crate::scene::collision::geometry::Placed;
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

/// Checked pairs whose exact distance is `<= threshold`, at the poses in `data`.
fn pairs_within(
    model: &SceneModel,
    data: &SceneData,
    settings: &CollisionSettings,
    threshold: f64,
) -> Result<Vec<Contact>, Error> {
    settings.validate()?;
    data.check(model)?;
    let placement = Placement::new(model, data);
    Ok(checked_pairs(model, settings, None)
        .into_iter()
        .filter_map(|(a, b)| {
            let c = clearance(placement.body(Body::Part(a)), placement.body(b), threshold);
            (c.exact <= threshold).then_some(Contact {
                a: Body::Part(a),
                b,
                distance: c.exact,
            })
        })
        .collect())
}

/// The colliding body pairs at the state of the last
/// [`forward_kinematics`](crate::scene::forward_kinematics) (predicate: see
/// [`CollisionSettings`]). Bounding spheres skip far pairs before exact parry distances.
///
/// # Errors
/// [`Error::InvalidSetting`] for invalid settings; [`Error::DimensionMismatch`] if `data` is
/// not sized for `model`.
pub fn collisions(
    model: &SceneModel,
    data: &SceneData,
    settings: &CollisionSettings,
) -> Result<Vec<Contact>, Error> {
    pairs_within(model, data, settings, settings.contact_distance)
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
        return Err(Error::InvalidSetting {
            what: "max_distance".into(),
            value: max_distance,
        });
    }
    pairs_within(model, data, settings, max_distance)
}
