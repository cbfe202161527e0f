//! Mapping stage, part 1: fusing handle detections from many views into one set of handles.

use nalgebra::{Point3, Vector3};
use serde::{Deserialize, Serialize};

use super::error::{DiscoveryError, check_finite, check_positive, check_range};
use super::interface::HandleDetection;
use super::registration::Attachment;
use crate::InvalidSetting;

/// Settings of [`fuse_detections`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FusionSettings {
    /// Two detections closer than this (m) are the same handle. Default 0.08 (handles of
    /// adjacent fronts are farther apart; detector noise is a few centimetres).
    pub merge_radius: f64,
    /// Smallest fused confidence kept, in [0, 1]. Default 0.5.
    pub min_confidence: f64,
    /// Smallest number of views a kept handle was seen in. Default 1.
    pub min_views: usize,
}

impl Default for FusionSettings {
    fn default() -> Self {
        FusionSettings {
            merge_radius: 0.08,
            min_confidence: 0.5,
            min_views: 1,
        }
    }
}

impl FusionSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`DiscoveryError::InvalidSetting`] for a non-positive radius, a confidence outside
    /// [0, 1] or `min_views == 0`.
    pub fn validate(&self) -> Result<(), DiscoveryError> {
        check_positive("merge_radius", self.merge_radius)?;
        check_range("min_confidence", self.min_confidence, 0.0, 1.0, "in [0, 1]")?;
        if self.min_views == 0 {
            return Err(InvalidSetting::new("min_views", 0.0, "at least 1").into());
        }
        Ok(())
    }
}

/// A handle of the map: fused from detections, optionally registered to the base map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MappedHandle {
    /// Fused centre (m), map frame: the confidence-weighted mean of the detections.
    pub position: Point3<f64>,
    /// Fused half extents of the approximate box (m), confidence-weighted mean.
    pub half_extents: Vector3<f64>,
    /// Fused confidence in [0, 1]: `1 - Π(1 - cᵢ)` over the views that saw it.
    pub confidence: f64,
    /// Number of views whose detections were fused.
    pub views: usize,
    /// Confidence-weighted RMS distance of the detections from the fused centre (m): how
    /// consistent the views are.
    pub spread: f64,
    /// Latest detection time (s).
    pub stamp: f64,
    /// Where the handle sits on the base map, set by
    /// [`register_handles`](super::register_handles).
    pub attachment: Option<Attachment>,
}

impl MappedHandle {
    /// An unregistered handle from a single detection.
    pub fn from_detection(d: &HandleDetection) -> Self {
        MappedHandle {
            position: d.position,
            half_extents: d.half_extents,
            confidence: d.confidence,
            views: 1,
            spread: 0.0,
            stamp: d.stamp,
            attachment: None,
        }
    }
}

/// Fuses handle detections from several views (each inner list is one view) into one set of
/// handles in the map frame: 3D non-maximum suppression and clustering with confidence.
///
/// The rule:
/// 1. **Per view**, non-maximum suppression: a detection within `merge_radius` of a more
///    confident detection of the same view is dropped (one handle, one detection per view).
/// 2. **Across views**, greedy clustering in order of decreasing confidence: a detection joins
///    the cluster whose current centre is nearest, if that centre is within `merge_radius` and
///    the cluster has no detection of the same view yet; otherwise it starts a new cluster.
/// 3. **Fusion**: position and half extents are confidence-weighted means; the fused
///    confidence is `1 - Π(1 - cᵢ)` (the views as independent evidence), so a handle seen
///    consistently in several views scores higher than in any one of them; `spread` is the
///    weighted RMS distance to the centre.
/// 4. **Selection**: clusters with fused confidence below `min_confidence` or fewer than
///    `min_views` views are dropped. A single weak detection (below `min_confidence`) is
///    therefore dropped, while the same weak detection repeated in enough views is kept
///    (three views at 0.3 fuse to 0.657).
///
/// The result is sorted by decreasing confidence (ties by position), which is the order
/// [`discover`](super::discover) explores them in. Handles are unregistered
/// (`attachment: None`).
///
/// # Errors
/// [`DiscoveryError::InvalidSetting`] for invalid settings; [`DiscoveryError::NonFinite`]
/// for a detection with a NaN or infinite number; [`DiscoveryError::ConfidenceOutOfRange`].
pub fn fuse_detections(
    views: &[Vec<HandleDetection>],
    settings: &FusionSettings,
) -> Result<Vec<MappedHandle>, DiscoveryError> {
    settings.validate()?;
    let mut all: Vec<(usize, &HandleDetection)> = Vec::new();
    for (v, view) in views.iter().enumerate() {
        for (k, d) in view.iter().enumerate() {
            let what = || format!("detection {k} of view {v}");
            check_finite(
                d.position
                    .coords
                    .iter()
                    .chain(d.half_extents.iter())
                    .copied()
                    .chain([d.confidence, d.stamp]),
                what,
            )?;
            if !(0.0..=1.0).contains(&d.confidence) {
                return Err(DiscoveryError::ConfidenceOutOfRange {
                    what: what(),
                    value: d.confidence,
                });
            }
        }
        all.extend(suppress(view, settings.merge_radius).map(|d| (v, d)));
    }
    // Stable sort: ties keep view order.
    all.sort_by(|a, b| b.1.confidence.total_cmp(&a.1.confidence));
    let mut clusters: Vec<Cluster> = Vec::new();
    for (view, d) in all {
        let best = clusters
            .iter_mut()
            .filter(|c| !c.views.contains(&view))
            .map(|c| ((c.center() - d.position).norm(), c))
            .filter(|(dist, _)| *dist <= settings.merge_radius)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((_, c)) => c.add(view, d),
            None => {
                let mut c = Cluster::default();
                c.add(view, d);
                clusters.push(c);
            }
        }
    }
    let mut out: Vec<MappedHandle> = clusters
        .iter()
        .map(Cluster::fused)
        .filter(|h| h.confidence >= settings.min_confidence && h.views >= settings.min_views)
        .collect();
    out.sort_by(|a, b| {
        b.confidence.total_cmp(&a.confidence).then_with(|| {
            a.position
                .coords
                .iter()
                .zip(b.position.coords.iter())
                .map(|(x, y)| x.total_cmp(y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        })
    });
    Ok(out)
}

/// Per-view non-maximum suppression: the detections not within `radius` of a more confident
/// one (ties: the earlier one wins).
fn suppress(view: &[HandleDetection], radius: f64) -> impl Iterator<Item = &HandleDetection> {
    view.iter().enumerate().filter_map(move |(k, d)| {
        let dominated = view.iter().enumerate().any(|(j, o)| {
            j != k
                && (o.position - d.position).norm() <= radius
                && (o.confidence > d.confidence || (o.confidence == d.confidence && j < k))
        });
        (!dominated).then_some(d)
    })
}

/// Detections of one handle across views.
#[derive(Debug, Default)]
struct Cluster {
    views: Vec<usize>,
    members: Vec<HandleDetection>,
}

impl Cluster {
    fn add(&mut self, view: usize, d: &HandleDetection) {
        self.views.push(view);
        self.members.push(*d);
    }

    /// Total weight: the sum of confidences (a zero-confidence member still counts a little,
    /// so the mean is defined).
    fn weights(&self) -> impl Iterator<Item = f64> + '_ {
        self.members.iter().map(|d| d.confidence.max(1e-9))
    }

    fn center(&self) -> Point3<f64> {
        let w: f64 = self.weights().sum();
        let s = self
            .members
            .iter()
            .zip(self.weights())
            .fold(Vector3::zeros(), |s, (d, c)| s + d.position.coords * c);
        Point3::from(s / w)
    }

    fn fused(&self) -> MappedHandle {
        let w: f64 = self.weights().sum();
        let center = self.center();
        let half = self
            .members
            .iter()
            .zip(self.weights())
            .fold(Vector3::zeros(), |s, (d, c)| s + d.half_extents * c)
            / w;
        let var = self
            .members
            .iter()
            .zip(self.weights())
            .map(|(d, c)| c * (d.position - center).norm_squared())
            .sum::<f64>()
            / w;
        let miss: f64 = self.members.iter().map(|d| 1.0 - d.confidence).product();
        MappedHandle {
            position: center,
            half_extents: half,
            confidence: 1.0 - miss,
            views: self.members.len(),
            spread: var.sqrt(),
            stamp: self
                .members
                .iter()
                .map(|d| d.stamp)
                .fold(f64::NEG_INFINITY, f64::max),
            attachment: None,
        }
    }
}
