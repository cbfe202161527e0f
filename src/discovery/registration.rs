//! Mapping stage, part 2: registering fused handles against the static base map.

use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

use super::error::{DiscoveryError, check_finite, check_nonneg, check_positive};
use super::fusion::MappedHandle;
use super::shapes::PlacedShape;
use crate::scene::{BaseMap, SceneModelBuilder, Shape};

/// Settings of [`register_handles`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RegistrationSettings {
    /// A handle farther than this (m) from every base-map solid is dropped (a false positive
    /// in free space), and only faces within this distance are candidates. Default 0.35: a
    /// handle stands a few centimetres proud of its front, but the front may close an
    /// open-fronted bay whose nearest static panel is a quarter of a metre to the side.
    pub max_distance: f64,
    /// A handle deeper than this (m) inside a base-map solid is dropped. Default 0.005.
    pub inside_tolerance: f64,
    /// Weight of the lateral offset in the face score (see [`register_handles`]), >= 0.
    /// Default 0.25.
    pub lateral_weight: f64,
    /// Score penalty (m) per unit of the face normal's vertical component, >= 0: the prior
    /// that handles sit on vertical fronts (doors, drawers, appliance doors), which keeps the
    /// underside of a worktop or panel just above a handle from winning. 0 disables it.
    /// Default 0.1.
    pub vertical_weight: f64,
}

impl Default for RegistrationSettings {
    fn default() -> Self {
        RegistrationSettings {
            max_distance: 0.35,
            inside_tolerance: 0.005,
            lateral_weight: 0.25,
            vertical_weight: 0.1,
        }
    }
}

impl RegistrationSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`DiscoveryError::InvalidSetting`] for a non-positive `max_distance` or a negative or
    /// non-finite field.
    pub fn validate(&self) -> Result<(), DiscoveryError> {
        check_positive("max_distance", self.max_distance)?;
        check_nonneg("inside_tolerance", self.inside_tolerance)?;
        check_nonneg("lateral_weight", self.lateral_weight)?;
        check_nonneg("vertical_weight", self.vertical_weight)
    }
}

/// Where a handle sits on the base map: the face it is mounted in front of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Attachment {
    /// Name of the base shape.
    pub base_shape: String,
    /// Foot of the perpendicular from the handle onto the face's plane (m), map frame.
    pub surface_point: Point3<f64>,
    /// Unit outward normal of the face, map frame.
    pub normal: Vector3<f64>,
    /// Distance of the handle in front of the face's plane (m).
    pub distance: f64,
}

/// Why [`register_handles`] dropped a handle.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Rejection {
    /// The handle lies inside a base-map solid.
    InsideSolid {
        /// The base shape.
        base_shape: String,
        /// Depth below its surface (m).
        depth: f64,
    },
    /// No base-map solid within `max_distance`.
    FarFromBase {
        /// Distance to the nearest solid (m; infinite for an empty base map).
        distance: f64,
    },
}

/// The result of [`register_handles`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Registration {
    /// The registered handles, in input order, with their [`Attachment`].
    pub handles: Vec<MappedHandle>,
    /// The dropped handles with the reason, in input order.
    pub rejected: Vec<(MappedHandle, Rejection)>,
}

/// Registers handles against the static base map: drops handles inside or far from its solids
/// and attaches each remaining one to a base-map face, whose outward normal becomes the
/// handle's normal (the direction the robot approaches and first pulls along).
///
/// The rule. A handle deeper than `inside_tolerance` inside a solid is rejected
/// ([`Rejection::InsideSolid`]); one farther than `max_distance` from every solid (parry's
/// point projection) is rejected ([`Rejection::FarFromBase`]). Otherwise the candidate faces
/// are those within `max_distance` of the handle that it stands in front of (signed plane
/// distance `d >= -inside_tolerance`): the six faces of each box; for every other shape the
/// tangent plane at the projected point, with normal from that point to the handle. The face
/// with the smallest score `max(d, 0) + lateral_weight · l + vertical_weight · |n_z|` wins,
/// where `l` is how far the handle's foot on the plane lies outside the face and `n_z` the
/// vertical component of the face normal. The lateral term matters at open-fronted carcasses
/// (a drawer between two shelf panels): the shelf's front edge face, a few centimetres behind
/// the handle but beside it, beats the shelf's top face, which is laterally closer but
/// farther in plane distance. The vertical term is the prior that handles sit on vertical
/// fronts: a dishwasher handle 4 cm proud of its door and 2 cm below the tub's top panel
/// attaches to the panel's front face, not to its underside. A handle with no candidate face
/// (only possible when it is level with an edge of a non-box shape) is rejected as far.
///
/// # Errors
/// [`DiscoveryError::InvalidSetting`]; [`DiscoveryError::NonFinite`] for a handle with a
/// NaN or infinite position; [`DiscoveryError::Scene`] if the base map is invalid.
pub fn register_handles(
    handles: &[MappedHandle],
    base: &BaseMap,
    settings: &RegistrationSettings,
) -> Result<Registration, DiscoveryError> {
    settings.validate()?;
    let base = SceneModelBuilder {
        base: base.clone(),
        parts: Vec::new(),
    }
    .build()?
    .base()
    .clone();
    let placed: Vec<(usize, PlacedShape)> = base
        .shapes
        .iter()
        .enumerate()
        .filter_map(|(k, s)| Some((k, PlacedShape::new(&s.shape, &s.world_from_shape)?)))
        .collect();
    let mut out = Registration {
        handles: Vec::new(),
        rejected: Vec::new(),
    };
    for (k, h) in handles.iter().enumerate() {
        check_finite(h.position.coords.iter().copied(), || {
            format!("position of handle {k}")
        })?;
        match attach(&h.position, &base, &placed, settings) {
            Ok(a) => out.handles.push(MappedHandle {
                attachment: Some(a),
                ..h.clone()
            }),
            Err(r) => out.rejected.push((h.clone(), r)),
        }
    }
    Ok(out)
}

/// The attachment of one point, or why it has none.
fn attach(
    p: &Point3<f64>,
    base: &BaseMap,
    placed: &[(usize, PlacedShape)],
    s: &RegistrationSettings,
) -> Result<Attachment, Rejection> {
    let mut nearest = f64::INFINITY;
    let mut best: Option<(f64, Attachment)> = None;
    for (k, shape) in placed {
        let base_shape = &base.shapes[*k];
        let proj = shape.project(p);
        let gap = (proj.point - p).norm();
        if proj.inside {
            if gap > s.inside_tolerance {
                return Err(Rejection::InsideSolid {
                    base_shape: base_shape.name.clone(),
                    depth: gap,
                });
            }
            nearest = 0.0;
        } else {
            nearest = nearest.min(gap);
        }
        if gap > s.max_distance {
            continue;
        }
        for face in faces(p, &base_shape.shape, &base_shape.world_from_shape, &proj) {
            let (d, lateral) = (face.distance, face.lateral);
            if d < -s.inside_tolerance || d.hypot(lateral) > s.max_distance {
                continue;
            }
            let score =
                d.max(0.0) + s.lateral_weight * lateral + s.vertical_weight * face.normal.z.abs();
            if best.as_ref().is_none_or(|(b, _)| score < *b) {
                best = Some((
                    score,
                    Attachment {
                        base_shape: base_shape.name.clone(),
                        surface_point: p - face.normal * d,
                        normal: face.normal,
                        distance: d,
                    },
                ));
            }
        }
    }
    match best {
        Some((_, a)) => Ok(a),
        None => Err(Rejection::FarFromBase { distance: nearest }),
    }
}

/// A candidate face: outward unit normal, signed plane distance of the point, lateral offset.
struct Face {
    normal: Vector3<f64>,
    distance: f64,
    lateral: f64,
}

/// The candidate faces of a shape for point `p` (world frame).
fn faces(
    p: &Point3<f64>,
    shape: &Shape,
    world_from_shape: &nalgebra::Isometry3<f64>,
    proj: &super::shapes::Projection,
) -> Vec<Face> {
    if let Shape::Cuboid { half_extents: h } = shape {
        let local = world_from_shape.inverse_transform_point(p);
        let mut out = Vec::with_capacity(6);
        for k in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut lateral = 0.0f64;
                for j in (0..3).filter(|&j| j != k) {
                    let over = (local[j].abs() - h[j]).max(0.0);
                    lateral = lateral.hypot(over);
                }
                let mut n = Vector3::zeros();
                n[k] = sign;
                out.push(Face {
                    normal: world_from_shape.rotation * n,
                    distance: sign * local[k] - h[k],
                    lateral,
                });
            }
        }
        return out;
    }
    let d = proj.point - p;
    let gap = d.norm();
    if proj.inside || gap <= 1e-9 {
        return Vec::new();
    }
    vec![Face {
        normal: -d / gap,
        distance: gap,
        lateral: 0.0,
    }]
}
