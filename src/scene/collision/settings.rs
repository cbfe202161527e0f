//! Collision settings: the contact distance, allowed pairs, sweep resolution.

use std::collections::BTreeSet;

use serde::{Deserialize, Serialize};

use crate::InvalidSetting;
use crate::scene::validate::check_setting_nonneg;
use crate::scene::{BaseShapeId, Error, PartId};

/// A rigid body that can take part in a collision: an articulated part or a base shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Body {
    /// An articulated part (all its colliders).
    Part(PartId),
    /// One static shape of the base map.
    Base(BaseShapeId),
}

/// A body in a failure report: a part or a base shape, by name.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BodyName {
    /// An articulated part.
    Part(String),
    /// A static shape of the base map.
    Base(String),
}

impl BodyName {
    /// The name of `body` in `model` (its id must be one of `model`'s).
    pub fn of(model: &crate::scene::SceneModel, body: Body) -> BodyName {
        match body {
            Body::Part(p) => BodyName::Part(model.parts()[p.index()].name().into()),
            Body::Base(s) => BodyName::Base(model.base().shapes[s.index()].name.clone()),
        }
    }
}

impl std::fmt::Display for BodyName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BodyName::Part(n) => write!(f, "part {n:?}"),
            BodyName::Base(n) => write!(f, "base shape {n:?}"),
        }
    }
}

/// Pairs of bodies exempt from collision checking, e.g. a closed door flush against its
/// carcass. The order within a pair does not matter.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct AllowedCollisions {
    pairs: BTreeSet<(Body, Body)>,
}

fn ordered(a: Body, b: Body) -> (Body, Body) {
    if a <= b { (a, b) } else { (b, a) }
}

impl AllowedCollisions {
    /// No allowed pairs.
    pub fn new() -> Self {
        Self::default()
    }

    /// Allows the pair `(a, b)`.
    pub fn allow(&mut self, a: Body, b: Body) -> &mut Self {
        self.pairs.insert(ordered(a, b));
        self
    }

    /// Whether the pair `(a, b)` is allowed.
    pub fn is_allowed(&self, a: Body, b: Body) -> bool {
        self.pairs.contains(&ordered(a, b))
    }

    /// The allowed pairs, each ordered.
    pub fn iter(&self) -> impl Iterator<Item = (Body, Body)> + '_ {
        self.pairs.iter().copied()
    }
}

/// What counts as a collision.
///
/// **Predicate.** Two bodies *collide* at a state iff the pair is checked and the exact
/// separation distance between some collider of one and some collider of the other is
/// `<= contact_distance`. Distances are 0 for touching or overlapping shapes, so with the
/// default `contact_distance = 0` touching counts as colliding. A pair is checked unless it
/// is in `allowed`, or it is a part and its parent part and `check_parent_child` is false.
/// Colliders of the same part never collide with each other; base shapes never collide with
/// each other.
///
/// Touching geometry is a modelling issue: a closed door modelled flush against its carcass
/// touches it. Scene authors should leave a small gap (a few millimetres, larger than
/// `contact_distance`) or list the pair in `allowed`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CollisionSettings {
    /// Separation (m) at or below which two bodies count as colliding, >= 0. Default 0.
    pub contact_distance: f64,
    /// Whether a part is checked against its parent part. Default false: a child usually
    /// rides in or on its parent (a rack in a dishwasher door). Parts on the base are always
    /// checked against base shapes (a door against the wall).
    pub check_parent_child: bool,
    /// Pairs never checked.
    pub allowed: AllowedCollisions,
}

impl CollisionSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a negative or non-finite `contact_distance`.
    pub fn validate(&self) -> Result<(), Error> {
        check_setting_nonneg(self.contact_distance, "contact_distance")
    }
}

/// Settings of the sampled continuous check along a one-joint motion
/// ([`check_joint_motion`](super::check_joint_motion)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepSettings {
    /// Initial margin `m` (m), in `(0, 1e6]`: first samples are spaced so that no point of the moving
    /// subtree travels more than `2m` between consecutive samples. Default 0.01.
    pub margin: f64,
    /// Resolution (m), in `[1e-9, margin]`: intervals are halved while their margin
    /// (half the travel bound across the interval) exceeds this. Default 1e-4.
    pub min_margin: f64,
    /// Budget of distance evaluations (samples); exceeding it gives an inconclusive outcome.
    /// Default 100 000.
    pub max_samples: usize,
    /// What counts as a collision.
    pub collision: CollisionSettings,
}

impl Default for SweepSettings {
    fn default() -> Self {
        SweepSettings {
            margin: 0.01,
            min_margin: 1e-4,
            max_samples: 100_000,
            collision: CollisionSettings::default(),
        }
    }
}

impl SweepSettings {
    /// Checks the settings.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a margin outside `(0, 1e6]`, a resolution outside
    /// `[1e-9, margin]`, or an invalid [`CollisionSettings`].
    pub fn validate(&self) -> Result<(), Error> {
        if !(self.margin > 0.0 && self.margin <= 1e6) {
            return Err(InvalidSetting::new("sweep.margin", self.margin, "in (0, 1e6]").into());
        }
        if !(self.min_margin >= 1e-9 && self.min_margin <= self.margin) {
            return Err(InvalidSetting::new(
                "sweep.min_margin",
                self.min_margin,
                "in [1e-9, sweep.margin]",
            )
            .into());
        }
        self.collision.validate()
    }
}
