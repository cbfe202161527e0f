//! Articulation estimators on synthetic observations with known joints, and the DiTH metrics
//! on hand-computed cases.
//!
//! The generator builds cabinets from boxes (body panels, doors, drawers, handles) in the map
//! frame, moves the articulated part by a known joint motion, and renders pre/post depth
//! observations with `synthetic::render` (ray-cast: partial views, exact occlusion, depth noise
//! along the ray, outliers). The expected values of every assertion are that ground truth.

mod calibration;
mod degenerate;
mod estimators;
mod fused;
mod hard;
mod metrics;
mod proprioceptive;
mod scenes;
mod tables;

use kinscene::articulation::synthetic::{DepthCamera, DepthNoise, SyntheticBox, render};
use kinscene::articulation::{
    ArticulationError, ArticulationEstimator, Estimate, InputKind, Interaction, JointEstimate,
    JointKindEstimate, MIN_NOISE_POSES, NoiseSource, OrientationModel, PointCloud, Proprioceptive,
    ProprioceptiveSettings, Screw, TwoView, TwoViewSettings, axis_angle_error, axis_position_error,
    joint_type_accuracy, path_noise,
};
use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{FRAC_PI_2, PI};

use scenes::scenarios;

/// Label of the moving part's boxes; static boxes use 0.
const PART: usize = 1;

/// A known joint and how far it moves between the observations.
use hard::HardTruth as Truth;

/// A scene with one articulated part.
struct Scenario {
    name: &'static str,
    statics: Vec<SyntheticBox>,
    /// The part's boxes in the pre pose (label [`PART`]).
    part: Vec<SyntheticBox>,
    truth: Truth,
    /// Grasp point on the handle (pre pose).
    contact: Point3<f64>,
    /// The end effector's pose at the grasp (pre pose).
    world_from_grasp: Isometry3<f64>,
    camera_pre: DepthCamera,
    camera_post: DepthCamera,
}

/// One synthetic interaction: clouds, ground-truth labels of the pre cloud, contacts, poses.
struct Observation {
    pre: PointCloud,
    post: PointCloud,
    pre_labels: Vec<Option<usize>>,
    contact_pre: Point3<f64>,
    contact_post: Point3<f64>,
    ee_poses: Vec<(f64, Isometry3<f64>)>,
}

impl Observation {
    fn interaction(&self) -> Interaction<'_> {
        Interaction {
            pre: &self.pre,
            post: &self.post,
            contact_pre: self.contact_pre,
            contact_post: self.contact_post,
            ee_poses: &self.ee_poses,
        }
    }
}

/// Noise model of one observation: depth σ (m) for the clouds; the end-effector positions get
/// the same σ per axis, orientations σ/(5 mm) degrees, the contacts σ/2; `outliers` of the cloud
/// points and of the poses are outliers.
fn observe(s: &Scenario, sigma: f64, outliers: f64, seed: u64, travel: f64) -> Observation {
    let moved = s.truth.motion(travel);
    let mut post_boxes = s.statics.clone();
    post_boxes.extend(s.part.iter().map(|b| SyntheticBox {
        world_from_box: moved * b.world_from_box,
        ..*b
    }));
    let mut pre_boxes = s.statics.clone();
    pre_boxes.extend(s.part.iter().copied());
    let noise = |k| DepthNoise {
        sigma,
        outlier_fraction: outliers,
        seed: seed * 2 + k,
    };
    let pre = render(&pre_boxes, &s.camera_pre, &noise(0), 0.0).expect("valid camera");
    let post = render(&post_boxes, &s.camera_post, &noise(1), 10.0).expect("valid camera");
    let (contact_pre, contact_post, ee_poses) = proprioception(s, sigma, outliers, seed, travel);
    Observation {
        pre: pre.cloud,
        post: post.cloud,
        pre_labels: pre.labels,
        contact_pre,
        contact_post,
        ee_poses,
    }
}

/// `(time s, world_from_ee)`.
type TimedPose = (f64, Isometry3<f64>);

/// The contacts and the end-effector path of [`observe`] (200 poses), without rendering: the
/// same random draws as there.
fn proprioception(
    s: &Scenario,
    sigma: f64,
    outliers: f64,
    seed: u64,
    travel: f64,
) -> (Point3<f64>, Point3<f64>, Vec<TimedPose>) {
    let moved = s.truth.motion(travel);
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    let mut gauss = |scale: f64| -> Vector3<f64> {
        let mut g = || {
            let u1: f64 = 1.0 - rng.random::<f64>();
            let u2: f64 = rng.random();
            (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
        };
        Vector3::new(g(), g(), g()) * scale
    };
    let contact_pre = s.contact + gauss(sigma / 2.0);
    let contact_post = moved * s.contact + gauss(sigma / 2.0);
    let n = 200;
    let rot_sigma = (sigma / 0.005).to_radians();
    let mut ee_poses = Vec::new();
    for k in 0..n {
        let pose = s.truth.motion(travel * k as f64 / (n - 1) as f64) * s.world_from_grasp;
        let position_noise = gauss(sigma);
        let rotation_noise = UnitQuaternion::from_scaled_axis(gauss(rot_sigma));
        let mut p = Isometry3::from_parts(
            Translation3::from(pose.translation.vector + position_noise),
            rotation_noise * pose.rotation,
        );
        let mut outlier_rng = ChaCha8Rng::seed_from_u64(seed * 1000 + k as u64);
        if outlier_rng.random::<f64>() < outliers {
            let jump = Vector3::new(
                outlier_rng.random_range(-1.0..1.0),
                outlier_rng.random_range(-1.0..1.0),
                outlier_rng.random_range(-1.0..1.0),
            );
            p.translation.vector += jump.normalize() * outlier_rng.random_range(0.05..0.15);
        }
        ee_poses.push((0.01 * k as f64, p));
    }
    (contact_pre, contact_post, ee_poses)
}

/// Errors of one estimate against the truth.
#[derive(Debug, Clone, Copy)]
struct Errors {
    kind_ok: bool,
    axis_deg: f64,
    /// Revolute only: line-line distance of the axes, m.
    pivot_m: Option<f64>,
    /// |angle − true angle| (deg) or |distance − true distance| (m).
    travel: f64,
    /// Intersection over union of the moving segmentation with the part's points (two-view).
    iou: Option<f64>,
    /// Fraction of the moving segmentation on the part (two-view).
    precision: Option<f64>,
}

fn errors(s: &Scenario, o: &Observation, e: &Estimate, travel: f64) -> Errors {
    let (axis_deg, pivot_m, travel_err) = match (&e.joint, s.truth) {
        (
            JointEstimate::Revolute { axis, pivot, angle },
            Truth::Revolute {
                axis: a,
                pivot: q,
                angle: t,
            },
        ) => {
            let signed = if axis.dot(&a) < 0.0 { -*angle } else { *angle };
            (
                axis_angle_error(axis, &a),
                Some(axis_position_error(pivot, axis, &q, &a)),
                (signed - t * travel).abs().to_degrees(),
            )
        }
        (
            JointEstimate::Prismatic { axis, distance },
            Truth::Prismatic {
                axis: a,
                distance: d,
            },
        ) => {
            let signed = if axis.dot(&a) < 0.0 {
                -*distance
            } else {
                *distance
            };
            (
                axis_angle_error(axis, &a),
                None,
                (signed - d * travel).abs(),
            )
        }
        (JointEstimate::Revolute { axis, .. } | JointEstimate::Prismatic { axis, .. }, truth) => {
            let a = match truth {
                Truth::Revolute { axis, .. } | Truth::Prismatic { axis, .. } => axis,
            };
            (axis_angle_error(axis, &a), None, f64::NAN)
        }
        _ => (f64::NAN, None, f64::NAN),
    };
    let iou = (!e.moving.is_empty()).then(|| {
        let truth: Vec<bool> = o.pre_labels.iter().map(|l| *l == Some(PART)).collect();
        let inter = e.moving.iter().filter(|&&k| truth[k]).count() as f64;
        let union = truth.iter().filter(|&&b| b).count() as f64 + e.moving.len() as f64 - inter;
        inter / union
    });
    let precision = (!e.moving.is_empty()).then(|| {
        let on = e
            .moving
            .iter()
            .filter(|&&k| o.pre_labels[k] == Some(PART))
            .count();
        on as f64 / e.moving.len() as f64
    });
    Errors {
        precision,
        kind_ok: e.joint.kind() == s.truth.kind(),
        axis_deg,
        pivot_m,
        travel: travel_err,
        iou,
    }
}

fn estimators() -> Vec<Box<dyn ArticulationEstimator>> {
    vec![
        Box::new(TwoView::default()),
        Box::new(Proprioceptive::default()),
    ]
}

fn proprio_only(ee_poses: &[(f64, Isometry3<f64>)]) -> Interaction<'_> {
    static EMPTY: PointCloud = PointCloud {
        points: Vec::new(),
        colors: None,
        origin: Point3::new(0.0, 0.0, 0.0),
        stamp: 0.0,
    };
    Interaction {
        pre: &EMPTY,
        post: &EMPTY,
        contact_pre: Point3::origin(),
        contact_post: Point3::origin(),
        ee_poses,
    }
}

/// The proprioceptive estimator with `orientation`, the other settings default.
fn proprio(orientation: OrientationModel) -> Proprioceptive {
    Proprioceptive {
        settings: ProprioceptiveSettings {
            orientation,
            ..Default::default()
        },
    }
}
