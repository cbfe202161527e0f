//! Synthetic depth observations of box scenes, for tests, benchmarks and simulation.
//!
//! A pinhole depth camera casts one ray per pixel against oriented boxes; the first hit becomes
//! a point (so views are partial and occlusion is exact), perturbed by Gaussian noise along the
//! ray, and a fraction of pixels are replaced by outliers at a random depth along their ray.

use nalgebra::{Isometry3, Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::cloud::PointCloud;
use super::error::ArticulationError;
use crate::InvalidSetting;

/// An oriented box of the synthetic scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyntheticBox {
    /// Pose of the box centre, map frame.
    pub world_from_box: Isometry3<f64>,
    /// Half side lengths along the box axes, m (> 0).
    pub half_extents: Vector3<f64>,
    /// A caller-chosen label reported for every point on this box (e.g. a part index).
    pub label: usize,
}

/// A pinhole depth camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthCamera {
    /// Optical centre, map frame, m.
    pub origin: Point3<f64>,
    /// A point the optical axis passes through, map frame, m.
    pub target: Point3<f64>,
    /// Approximate up direction of the image (must not be parallel to the optical axis).
    pub up: Vector3<f64>,
    /// Horizontal field of view, rad, in (0, π).
    pub horizontal_fov: f64,
    /// Image width and height, pixels (≥ 1); square pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// Rays hitting nothing nearer than this give no point, m.
    pub max_range: f64,
}

/// Sensor noise of [`render`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthNoise {
    /// Standard deviation of the depth along each ray, m (≥ 0).
    pub sigma: f64,
    /// Fraction of returned points replaced by outliers, in [0, 1).
    pub outlier_fraction: f64,
    /// Seed of the noise generator.
    pub seed: u64,
}

/// A rendered observation.
#[derive(Debug, Clone, PartialEq)]
pub struct Rendered {
    /// The points (origin = the camera origin).
    pub cloud: PointCloud,
    /// For each point, the label of the box its ray hit; `None` for outliers.
    pub labels: Vec<Option<usize>>,
}

/// Renders `boxes` with `camera` and `noise`, stamped `stamp`.
///
/// # Errors
/// [`ArticulationError::InvalidSetting`] for a non-finite or out-of-range camera, noise or box
/// field (zero image size, field of view outside (0, π), degenerate `up`, non-positive extents).
pub fn render(
    boxes: &[SyntheticBox],
    camera: &DepthCamera,
    noise: &DepthNoise,
    stamp: f64,
) -> Result<Rendered, ArticulationError> {
    let bad = |field: &str, value: f64, requirement: &str| {
        Err(ArticulationError::from(InvalidSetting::new(
            field,
            value,
            requirement,
        )))
    };
    if !(camera.horizontal_fov > 0.0 && camera.horizontal_fov < std::f64::consts::PI) {
        return bad("horizontal_fov", camera.horizontal_fov, "in (0, π)");
    }
    if camera.width == 0 || camera.height == 0 {
        return bad("width/height", 0.0, "≥ 1");
    }
    if camera.max_range.is_nan() || camera.max_range <= 0.0 {
        return bad("max_range", camera.max_range, "> 0");
    }
    if !(noise.sigma >= 0.0 && noise.sigma.is_finite()) {
        return bad("sigma", noise.sigma, "finite and ≥ 0");
    }
    if !(noise.outlier_fraction >= 0.0 && noise.outlier_fraction < 1.0) {
        return bad("outlier_fraction", noise.outlier_fraction, "in [0, 1)");
    }
    if let Some(b) = boxes
        .iter()
        .find(|b| !b.half_extents.iter().all(|h| h.is_finite() && *h > 0.0))
    {
        return bad("half_extents", b.half_extents.min(), "finite and > 0");
    }
    let forward = camera.target - camera.origin;
    let right = forward.cross(&camera.up);
    let (Some(forward), Some(right)) = (forward.try_normalize(1e-12), right.try_normalize(1e-12))
    else {
        return bad(
            "up",
            0.0,
            "off the optical axis, which needs an origin apart from the target",
        );
    };
    if !camera
        .origin
        .coords
        .iter()
        .chain(camera.target.coords.iter())
        .all(|v| v.is_finite())
    {
        return bad("origin/target", f64::NAN, "finite");
    }
    let up = right.cross(&forward);
    let half_w = (camera.horizontal_fov / 2.0).tan();
    let pixel = 2.0 * half_w / camera.width as f64;
    let half_h = pixel * camera.height as f64 / 2.0;

    let mut rng = ChaCha8Rng::seed_from_u64(noise.seed);
    let mut points = Vec::new();
    let mut labels = Vec::new();
    for v in 0..camera.height {
        for u in 0..camera.width {
            let x = -half_w + (u as f64 + 0.5) * pixel;
            let y = half_h - (v as f64 + 0.5) * pixel;
            let dir = (forward + right * x + up * y).normalize();
            let hit = boxes
                .iter()
                .filter_map(|b| ray_box(&camera.origin, &dir, b).map(|t| (t, b.label)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let Some((depth, label)) = hit.filter(|(t, _)| *t <= camera.max_range) else {
                continue;
            };
            if rng.random::<f64>() < noise.outlier_fraction {
                let d = depth * rng.random_range(0.3..1.5);
                points.push(camera.origin + dir * d);
                labels.push(None);
            } else {
                let d = depth + noise.sigma * gaussian(&mut rng);
                points.push(camera.origin + dir * d);
                labels.push(Some(label));
            }
        }
    }
    Ok(Rendered {
        cloud: PointCloud::new(points, camera.origin, stamp),
        labels,
    })
}

/// The entry distance of the ray `origin + t dir` (t > 0) into `b`, by the slab method.
fn ray_box(origin: &Point3<f64>, dir: &Vector3<f64>, b: &SyntheticBox) -> Option<f64> {
    let inv = b.world_from_box.inverse();
    let o = inv * origin;
    let d = inv.rotation * dir;
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        let h = b.half_extents[k];
        if d[k].abs() < 1e-15 {
            if o[k].abs() > h {
                return None;
            }
            continue;
        }
        let (a, c) = ((-h - o[k]) / d[k], (h - o[k]) / d[k]);
        t0 = t0.max(a.min(c));
        t1 = t1.min(a.max(c));
        if t0 > t1 {
            return None;
        }
    }
    (t0 > 0.0).then_some(t0)
}

/// A standard normal sample (Box–Muller).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}
