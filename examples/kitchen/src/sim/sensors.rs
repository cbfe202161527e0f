//! Simulated perception: a ray-cast depth camera (head and wrist) and a handle detector.
//!
//! Both sensors ray-cast against a snapshot of the world's colliders ([`Placed`]): the static
//! kitchen, the parts and the robot's own links, so the robot occludes its cameras for free.
//! Shapes whose interior contains a camera's origin are ignored (a camera does not see the
//! inside of the body it is mounted in: the wrist camera sits inside the gripper body's box).
//! Every random draw comes from the caller's seeded generator in a fixed order, so equal seeds
//! give equal observations; ray casting itself runs in parallel (rayon) and draws nothing.

use kinscene::discovery::{HandleDetection, PointCloud};
use nalgebra::{Isometry2, Isometry3, Point3, Vector3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use parry3d_f64::query::Ray;
use parry3d_f64::shape::SharedShape;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Who a placed shape belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Owner {
    /// The static kitchen (walls, counters, floor).
    Base,
    /// The part with this index in the ground-truth model (`SceneModel::parts()` order).
    Part(usize),
    /// The robot (chassis, arm links, gripper): occludes the cameras.
    Robot,
}

/// A collision shape placed in the world (a snapshot of the physics world's colliders).
#[derive(Clone)]
pub struct Placed {
    /// The shape.
    pub shape: SharedShape,
    /// Its pose in the map frame.
    pub pose: Pose,
    /// Whose it is.
    pub owner: Owner,
}

/// A handle as it truly is: what the detector may report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrueHandle {
    /// Centre (m), map frame.
    pub position: Point3<f64>,
    /// Outward normal (unit), map frame.
    pub normal: Vector3<f64>,
}

/// The depth cameras.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CameraSettings {
    /// Head camera height above the floor (m).
    pub head_height: f64,
    /// Head camera rays, columns × rows.
    pub head_rays: (usize, usize),
    /// Head field of view, horizontal × vertical (degrees).
    pub head_fov_deg: (f64, f64),
    /// Head camera pitch (degrees, negative looks down).
    pub head_pitch_deg: f64,
    /// Wrist camera: rays per side (square grid).
    pub wrist_rays: usize,
    /// Wrist field of view (degrees, square).
    pub wrist_fov_deg: f64,
    /// Wrist camera offset behind the tool point along the approach axis (m).
    pub wrist_offset: f64,
    /// Largest range (m); farther returns are missing.
    pub max_range: f64,
    /// Gaussian depth noise along each ray (m, standard deviation).
    pub depth_noise: f64,
    /// Probability that a return is missing (dropout), independent per ray.
    pub dropout: f64,
}

impl Default for CameraSettings {
    /// A RealSense D435 / Azure Kinect class head camera (87° × 58°, 160 × 120 rays: a 640 × 480
    /// image subsampled by 4) on a 1.3 m mast looking 35° down, and a 24 × 24, 80° wrist camera
    /// 0.12 m behind the tool point (inside the gripper body, on the flange side). Depth noise
    /// 5 mm (a structured-light or ToF camera at 1–2 m), 2 % missing returns, 4 m range.
    fn default() -> Self {
        CameraSettings {
            head_height: 1.3,
            head_rays: (160, 120),
            head_fov_deg: (87.0, 58.0),
            head_pitch_deg: -35.0,
            wrist_rays: 24,
            wrist_fov_deg: 80.0,
            wrist_offset: 0.12,
            max_range: 4.0,
            depth_noise: 0.005,
            dropout: 0.02,
        }
    }
}

/// The handle detector.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DetectorSettings {
    /// Position noise per axis (m, standard deviation).
    pub position_noise: f64,
    /// Probability that a visible handle is missed.
    pub miss_rate: f64,
    /// Expected number of false positives per call (Poisson), placed on visible surfaces.
    pub false_positives: f64,
    /// Largest detection range (m).
    pub range: f64,
    /// Half field of view (degrees, horizontal).
    pub half_fov_deg: f64,
}

impl Default for DetectorSettings {
    /// 1 cm position noise, 10 % misses, 0.2 false positives per call, 3 m range and the head
    /// camera's horizontal field of view (±43.5°).
    fn default() -> Self {
        DetectorSettings {
            position_noise: 0.01,
            miss_rate: 0.1,
            false_positives: 0.2,
            range: 3.0,
            half_fov_deg: 43.5,
        }
    }
}

/// A sensor setting out of its domain.
#[non_exhaustive]
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SensorSettingsError {
    /// A value that must be finite and at least `min` (and at most `max`) is not.
    #[error("sensor setting {what} = {value} is outside [{min}, {max}]")]
    OutOfRange {
        /// The setting's field name.
        what: &'static str,
        /// Its value.
        value: f64,
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },
}

/// Checks `value` is finite and in `[min, max]`.
fn check(what: &'static str, value: f64, min: f64, max: f64) -> Result<(), SensorSettingsError> {
    if value.is_finite() && (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(SensorSettingsError::OutOfRange {
            what,
            value,
            min,
            max,
        })
    }
}

/// Largest mean number of false positives per call that [`detect`] honours (larger means are
/// clamped; [`DetectorSettings::validate`] rejects them).
pub const MAX_FALSE_POSITIVES: f64 = 100.0;

impl CameraSettings {
    /// Checks every field is in its domain: positive height and range, fields of view in
    /// (0°, 170°], pitch in [−90°, 90°], non-negative noise and offset, dropout in [0, 1].
    /// Ray counts may be zero (an empty image).
    ///
    /// # Errors
    /// [`SensorSettingsError::OutOfRange`] naming the first bad field. The sensor functions
    /// never panic on bad settings: they clamp probabilities and produce no rays for
    /// degenerate fields of view, but their output is then meaningless.
    pub fn validate(&self) -> Result<(), SensorSettingsError> {
        check("head_height", self.head_height, 0.0, 100.0)?;
        check("head_fov_deg.0", self.head_fov_deg.0, 1e-6, 170.0)?;
        check("head_fov_deg.1", self.head_fov_deg.1, 1e-6, 170.0)?;
        check("head_pitch_deg", self.head_pitch_deg, -90.0, 90.0)?;
        check("wrist_fov_deg", self.wrist_fov_deg, 1e-6, 170.0)?;
        check("wrist_offset", self.wrist_offset, 0.0, 10.0)?;
        check("max_range", self.max_range, 1e-6, 1e3)?;
        check("depth_noise", self.depth_noise, 0.0, 1.0)?;
        check("dropout", self.dropout, 0.0, 1.0)
    }
}

impl DetectorSettings {
    /// Checks every field is in its domain: non-negative noise, miss rate in [0, 1], mean false
    /// positives in [0, [`MAX_FALSE_POSITIVES`]], positive range, half field of view in
    /// (0°, 180°].
    ///
    /// # Errors
    /// [`SensorSettingsError::OutOfRange`] naming the first bad field.
    pub fn validate(&self) -> Result<(), SensorSettingsError> {
        check("position_noise", self.position_noise, 0.0, 1.0)?;
        check("miss_rate", self.miss_rate, 0.0, 1.0)?;
        check(
            "false_positives",
            self.false_positives,
            0.0,
            MAX_FALSE_POSITIVES,
        )?;
        check("range", self.range, 1e-6, 1e3)?;
        check("half_fov_deg", self.half_fov_deg, 1e-6, 180.0)
    }
}

/// The head camera's origin and ray directions (unit, map frame) for a base pose.
///
/// The camera sits at `head_height` above the base origin, looks along the base heading pitched
/// by `head_pitch_deg`, and casts one ray through the centre of each pixel of a
/// `head_rays.0 × head_rays.1` pinhole image spanning `head_fov_deg`; rays are ordered row by
/// row from the top-left pixel.
pub fn head_rays(
    base: &Isometry2<f64>,
    settings: &CameraSettings,
) -> (Point3<f64>, Vec<Vector3<f64>>) {
    let t = base.translation.vector;
    let origin = Point3::new(t.x, t.y, settings.head_height);
    let (forward, right, up) = head_frame(base.rotation.angle(), settings.head_pitch_deg);
    let (cols, rows) = settings.head_rays;
    let (h_fov, v_fov) = settings.head_fov_deg;
    let dirs = pinhole(cols, rows, h_fov, v_fov, &forward, &right, &up);
    (origin, dirs)
}

/// The head pitch (degrees) that puts `target` (map frame) at the centre row of the head
/// image from base pose `base`: the elevation of `target` seen from the camera origin, in
/// [−90°, 90°]. A pan-tilt head uses it to look at a handle above or below the default view
/// (a wall cabinet from the passage: the default −35° ± 29° view ends 6° below the horizon);
/// pass it as `head_pitch_deg` to [`head_rays`]. The default pitch when `target` is not finite.
pub fn tilt_towards(base: &Isometry2<f64>, settings: &CameraSettings, target: &Point3<f64>) -> f64 {
    let t = base.translation.vector;
    let horizontal = (target.x - t.x).hypot(target.y - t.y);
    let pitch = f64::atan2(target.z - settings.head_height, horizontal).to_degrees();
    if pitch.is_finite() {
        pitch.clamp(-90.0, 90.0)
    } else {
        settings.head_pitch_deg
    }
}

/// The wrist camera's origin and ray directions (unit, map frame) for a tool pose (tool z is the
/// approach direction).
///
/// The camera sits `wrist_offset` behind the tool point on the tool z axis and casts a square
/// `wrist_rays × wrist_rays` pinhole grid over `wrist_fov_deg` about tool z (image columns
/// along tool x, rows along tool y).
pub fn wrist_rays(
    world_from_tool: &Isometry3<f64>,
    settings: &CameraSettings,
) -> (Point3<f64>, Vec<Vector3<f64>>) {
    let origin = world_from_tool * Point3::new(0.0, 0.0, -settings.wrist_offset);
    let r = world_from_tool.rotation;
    let forward = r * Vector3::z();
    let right = r * Vector3::x();
    // Rows run along +y (the image's "down" is tool +y), so "up" is −y.
    let up = -(r * Vector3::y());
    let n = settings.wrist_rays;
    let fov = settings.wrist_fov_deg;
    let dirs = pinhole(n, n, fov, fov, &forward, &right, &up);
    (origin, dirs)
}

/// Ray-casts `dirs` from `origin` against `scene`: one point per ray that hits within range and
/// is not dropped, with depth noise; stamped `stamp`.
///
/// Each direction is normalised first (zero or non-finite directions give no point). The
/// nearest hit within `max_range` counts; then, in ray order, each hit is dropped with
/// probability `dropout` and otherwise moved along its ray by a Gaussian draw of standard
/// deviation `depth_noise`. Points are in the map frame.
pub fn render(
    scene: &[Placed],
    origin: &Point3<f64>,
    dirs: &[Vector3<f64>],
    settings: &CameraSettings,
    stamp: f64,
    rng: &mut ChaCha8Rng,
) -> PointCloud {
    let index = SceneIndex::new(scene, origin);
    let max_range = settings.max_range;
    let units: Vec<Option<Vector3<f64>>> = dirs.iter().map(unit).collect();
    // Casting draws nothing from the generator: parallel and still deterministic.
    let hits: Vec<Option<f64>> = units
        .par_iter()
        .with_min_len(256)
        .map(|d| d.and_then(|d| index.cast(origin, &d, max_range)))
        .collect();
    let dropout = settings.dropout.clamp(0.0, 1.0);
    let sigma = finite_or_zero(settings.depth_noise).abs();
    let mut points = Vec::with_capacity(hits.len());
    for (t, d) in hits.iter().zip(&units) {
        let (Some(t), Some(d)) = (t, d) else {
            continue;
        };
        if rng.random::<f64>() < dropout {
            continue;
        }
        let noisy = t + sigma * gaussian(rng);
        points.push(origin + d * noisy);
    }
    PointCloud::new(points, *origin, stamp)
}

/// The detector's output from a head camera at `origin` looking along `yaw`: visible handles
/// (in range, in the field of view, line of sight free in `scene`) with noise and misses, plus
/// false positives.
///
/// A handle is visible when it is within `range` of `origin`, its bearing is within
/// ±`half_fov_deg` of `yaw`, it faces the camera (`normal · (origin − position) > 0`) and no
/// shape of `scene` blocks the segment from `origin` to it, except within 5 cm of the handle
/// (the handle's own body and the front it is mounted on). In the order of `handles`, each
/// visible handle is missed with probability `miss_rate`, else reported with Gaussian noise on
/// each coordinate, a (0.02, 0.02, 0.06) m box and a confidence in [0.5, 1] that falls with
/// distance and obliquity. Then a Poisson number (mean `false_positives`) of false positives is
/// placed at the hit points of random head-camera rays within `range` (up to 16 tries each;
/// a false positive whose rays all miss is dropped), with confidence in [0.3, 0.7]. The random
/// rays span ±`half_fov_deg` horizontally and the default head camera's vertical field of view
/// about its default pitch ([`CameraSettings::default`]); position noise applies to them too.
pub fn detect(
    scene: &[Placed],
    handles: &[TrueHandle],
    origin: &Point3<f64>,
    yaw: f64,
    settings: &DetectorSettings,
    stamp: f64,
    rng: &mut ChaCha8Rng,
) -> Vec<HandleDetection> {
    let index = SceneIndex::new(scene, origin);
    let range = finite_or_zero(settings.range).max(0.0);
    let half_fov = finite_or_zero(settings.half_fov_deg).to_radians();
    let miss_rate = settings.miss_rate.clamp(0.0, 1.0);
    let sigma = finite_or_zero(settings.position_noise).abs();
    let mut out = Vec::new();
    for h in handles {
        let to_camera = origin - h.position;
        let dist = to_camera.norm();
        if dist.is_nan() || dist > range {
            continue;
        }
        let bearing = wrap_angle(f64::atan2(-to_camera.y, -to_camera.x) - yaw);
        if bearing.is_nan() || bearing.abs() > half_fov {
            continue;
        }
        let Some(normal) = unit(&h.normal) else {
            continue;
        };
        let facing = normal.dot(&to_camera);
        if facing.is_nan() || facing <= 0.0 {
            continue;
        }
        if dist > HANDLE_CLEARANCE {
            let d = -to_camera / dist;
            if index.cast(origin, &d, dist - HANDLE_CLEARANCE).is_some() {
                continue;
            }
        }
        if rng.random::<f64>() < miss_rate {
            continue;
        }
        let noise = Vector3::new(gaussian(rng), gaussian(rng), gaussian(rng)) * sigma;
        // Both terms are in [0, 1]: distance over range, and one minus the cosine of the
        // viewing angle (positive since the handle faces the camera).
        let far = if range > 0.0 { dist / range } else { 1.0 };
        let oblique = 1.0 - facing / dist.max(f64::MIN_POSITIVE);
        let confidence = (1.0 - 0.3 * far - 0.2 * oblique).clamp(0.5, 1.0);
        out.push(HandleDetection {
            position: h.position + noise,
            half_extents: handle_box(),
            confidence,
            stamp,
        });
    }
    let mean = finite_or_zero(settings.false_positives).clamp(0.0, MAX_FALSE_POSITIVES);
    // A non-finite heading has no field of view to place false positives in.
    let count = if yaw.is_finite() {
        poisson(mean, rng)
    } else {
        0
    };
    let camera = CameraSettings::default();
    let (forward, right, up) = head_frame(yaw, camera.head_pitch_deg);
    let a_max = half_fov.min(MAX_SAMPLED_HALF_FOV).tan();
    let b_max = (camera.head_fov_deg.1 / 2.0).to_radians().tan();
    for _ in 0..count {
        for _ in 0..FALSE_POSITIVE_TRIES {
            let a = a_max * (2.0 * rng.random::<f64>() - 1.0);
            let b = b_max * (2.0 * rng.random::<f64>() - 1.0);
            let d = (forward + right * a + up * b).normalize();
            if let Some(t) = index.cast(origin, &d, range) {
                let noise = Vector3::new(gaussian(rng), gaussian(rng), gaussian(rng)) * sigma;
                out.push(HandleDetection {
                    position: origin + d * t + noise,
                    half_extents: handle_box(),
                    confidence: 0.3 + 0.4 * rng.random::<f64>(),
                    stamp,
                });
                break;
            }
        }
    }
    out
}

/// Occluders closer than this to a handle (m) do not hide it.
const HANDLE_CLEARANCE: f64 = 0.05;

/// Random rays tried per false positive before it is dropped.
const FALSE_POSITIVE_TRIES: usize = 16;

/// Largest half field of view the false-positive sampler uses (just under 90°, where the
/// pinhole's tangent diverges).
const MAX_SAMPLED_HALF_FOV: f64 = 1.55;

/// The detector's box around a handle (half extents, m).
fn handle_box() -> Vector3<f64> {
    Vector3::new(0.02, 0.02, 0.06)
}

/// The head camera's forward, right and up axes (map frame) for a heading `yaw` (rad) and a
/// pitch (degrees, negative looks down).
fn head_frame(yaw: f64, pitch_deg: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let p = pitch_deg.to_radians();
    let (sy, cy) = yaw.sin_cos();
    let (sp, cp) = p.sin_cos();
    let forward = Vector3::new(cp * cy, cp * sy, sp);
    let right = Vector3::new(sy, -cy, 0.0);
    let up = Vector3::new(-sp * cy, -sp * sy, cp);
    (forward, right, up)
}

/// Unit rays through the pixel centres of a `cols × rows` pinhole image spanning `h_fov` ×
/// `v_fov` degrees, row by row from the top-left pixel; empty for a degenerate field of view.
fn pinhole(
    cols: usize,
    rows: usize,
    h_fov: f64,
    v_fov: f64,
    forward: &Vector3<f64>,
    right: &Vector3<f64>,
    up: &Vector3<f64>,
) -> Vec<Vector3<f64>> {
    let half = |fov: f64| (fov / 2.0).to_radians();
    let (h, v) = (half(h_fov), half(v_fov));
    let valid = |a: f64| a.is_finite() && a > 0.0 && a < std::f64::consts::FRAC_PI_2;
    if !valid(h) || !valid(v) {
        return Vec::new();
    }
    let (th, tv) = (h.tan(), v.tan());
    let mut dirs = Vec::with_capacity(cols.saturating_mul(rows));
    for r in 0..rows {
        let b = tv * (1.0 - 2.0 * (r as f64 + 0.5) / rows as f64);
        for c in 0..cols {
            let a = th * (2.0 * (c as f64 + 0.5) / cols as f64 - 1.0);
            dirs.push((forward + right * a + up * b).normalize());
        }
    }
    dirs
}

/// The scene's shapes with finite bounding boxes in a bounding-volume hierarchy, minus those
/// that contain the camera origin.
struct SceneIndex<'a> {
    scene: &'a [Placed],
    /// Per BVH leaf (contiguous ids), its index into `scene`. Contiguous because parry 0.31's
    /// `Bvh::from_iter` assumes leaf ids 0 and 1 when it holds only one or two leaves.
    leaves: Vec<usize>,
    bvh: Bvh,
}

impl<'a> SceneIndex<'a> {
    fn new(scene: &'a [Placed], origin: &Point3<f64>) -> SceneIndex<'a> {
        let o = to_parry(&origin.coords);
        let finite = o.is_finite();
        let (leaves, aabbs): (Vec<usize>, Vec<Aabb>) = scene
            .iter()
            .enumerate()
            .filter_map(|(i, p)| {
                let aabb = p.shape.compute_aabb(&p.pose);
                let ok = aabb.mins.is_finite() && aabb.maxs.is_finite();
                let inside = finite && p.shape.contains_point(&p.pose, o);
                (ok && !inside).then_some((i, aabb))
            })
            .unzip();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &aabbs);
        SceneIndex { scene, leaves, bvh }
    }

    /// Distance (m) along the unit direction `d` to the nearest hit within `max`, if any.
    fn cast(&self, origin: &Point3<f64>, d: &Vector3<f64>, max: f64) -> Option<f64> {
        if max.is_nan() || max <= 0.0 || !origin.coords.iter().all(|x| x.is_finite()) {
            return None;
        }
        let ray = Ray::new(to_parry(&origin.coords), to_parry(d));
        self.bvh
            .cast_ray(&ray, max, |i, best| {
                let p = &self.scene[*self.leaves.get(i as usize)?];
                p.shape.cast_ray(&p.pose, &ray, best, true)
            })
            .map(|(_, t)| t)
    }
}

fn to_parry(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

/// `v` normalised, or `None` when it is zero or not finite.
fn unit(v: &Vector3<f64>) -> Option<Vector3<f64>> {
    let n = v.norm();
    (n.is_finite() && n > 1e-12).then(|| v / n)
}

fn finite_or_zero(x: f64) -> f64 {
    if x.is_finite() { x } else { 0.0 }
}

/// `a` wrapped to (−π, π].
fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::PI;
    let w = (a + PI).rem_euclid(2.0 * PI) - PI;
    if w == -PI { PI } else { w }
}

/// A standard normal draw (Box–Muller, cosine branch; two uniforms per draw).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    // 1 − u is in (0, 1], so the logarithm is finite.
    let u1 = 1.0 - rng.random::<f64>();
    let u2 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// A Poisson draw with mean `mean` (finite, in [0, `MAX_FALSE_POSITIVES`]): Knuth's product of
/// uniforms, on chunks of mean at most 30 so `exp(−mean)` stays far from underflow.
fn poisson(mean: f64, rng: &mut ChaCha8Rng) -> usize {
    let mut left = mean;
    let mut count = 0;
    while left > 0.0 {
        let chunk = left.min(30.0);
        left -= chunk;
        let limit = (-chunk).exp();
        let mut p = rng.random::<f64>();
        while p > limit {
            count += 1;
            p *= rng.random::<f64>();
        }
    }
    count
}
