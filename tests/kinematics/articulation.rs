//! Articulation estimators on synthetic observations with known joints, and the DiTH metrics
//! on hand-computed cases.
//!
//! The generator builds cabinets from boxes (body panels, doors, drawers, handles) in the map
//! frame, moves the articulated part by a known joint motion, and renders pre/post depth
//! observations with `synthetic::render` (ray-cast: partial views, exact occlusion, depth noise
//! along the ray, outliers). The expected values of every assertion are that ground truth.

use kinscene::kinematics::articulation::synthetic::{
    DepthCamera, DepthNoise, SyntheticBox, render,
};
use kinscene::kinematics::articulation::{
    ArticulationError, ArticulationEstimator, Estimate, InputKind, Interaction, JointEstimate,
    JointKindEstimate, OrientationModel, PointCloud, Proprioceptive, ProprioceptiveSettings, Screw,
    TwoView, TwoViewSettings, axis_angle_error, axis_position_error, joint_type_accuracy,
};
use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{FRAC_PI_2, PI};

/// Label of the moving part's boxes; static boxes use 0.
const PART: usize = 1;
/// Panel thickness, m.
const T: f64 = 0.018;

/// A known joint and how far it moves between the observations.
#[derive(Debug, Clone, Copy)]
enum Truth {
    Revolute {
        axis: Unit<Vector3<f64>>,
        pivot: Point3<f64>,
        angle: f64,
    },
    Prismatic {
        axis: Unit<Vector3<f64>>,
        distance: f64,
    },
}

impl Truth {
    /// The part's map-frame motion after `fraction` of the full joint travel.
    fn motion(&self, fraction: f64) -> Isometry3<f64> {
        match *self {
            Truth::Revolute { axis, pivot, angle } => Screw {
                axis,
                point: pivot,
                angle: angle * fraction,
                translation: 0.0,
            }
            .to_isometry(),
            Truth::Prismatic { axis, distance } => Isometry3::from_parts(
                Translation3::from(axis.into_inner() * distance * fraction),
                UnitQuaternion::identity(),
            ),
        }
    }

    fn kind(&self) -> JointKindEstimate {
        match self {
            Truth::Revolute { .. } => JointKindEstimate::Revolute,
            Truth::Prismatic { .. } => JointKindEstimate::Prismatic,
        }
    }
}

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

fn boxed(
    world_from_frame: &Isometry3<f64>,
    center: [f64; 3],
    half: [f64; 3],
    label: usize,
) -> SyntheticBox {
    SyntheticBox {
        world_from_box: world_from_frame * Isometry3::translation(center[0], center[1], center[2]),
        half_extents: Vector3::from(half),
        label,
    }
}

/// A cabinet body open at the front, in its frame: x right, y into the cabinet, z up, front
/// opening at y = 0 spanning x ∈ [0, w], z ∈ [0, h]; depth d.
fn cabinet_body(f: &Isometry3<f64>, w: f64, d: f64, h: f64) -> Vec<SyntheticBox> {
    vec![
        boxed(
            f,
            [T / 2.0, d / 2.0, h / 2.0],
            [T / 2.0, d / 2.0, h / 2.0],
            0,
        ),
        boxed(
            f,
            [w - T / 2.0, d / 2.0, h / 2.0],
            [T / 2.0, d / 2.0, h / 2.0],
            0,
        ),
        boxed(
            f,
            [w / 2.0, d / 2.0, T / 2.0],
            [w / 2.0 - T, d / 2.0, T / 2.0],
            0,
        ),
        boxed(
            f,
            [w / 2.0, d / 2.0, h - T / 2.0],
            [w / 2.0 - T, d / 2.0, T / 2.0],
            0,
        ),
        boxed(
            f,
            [w / 2.0, d - T / 2.0, h / 2.0],
            [w / 2.0 - T, T / 2.0, h / 2.0 - T],
            0,
        ),
    ]
}

/// A closed door panel covering the opening plus a vertical bar handle at `handle_x`, height
/// `handle_z`; returns the boxes and the grasp point (front of the handle).
fn door(
    f: &Isometry3<f64>,
    w: f64,
    h: f64,
    handle_x: f64,
    handle_z: f64,
    label: usize,
) -> (Vec<SyntheticBox>, Point3<f64>) {
    let boxes = vec![
        boxed(
            f,
            [w / 2.0, -T / 2.0, h / 2.0],
            [w / 2.0 - 0.002, T / 2.0, h / 2.0 - 0.002],
            label,
        ),
        boxed(
            f,
            [handle_x, -T - 0.025, handle_z],
            [0.008, 0.008, 0.06],
            label,
        ),
        boxed(
            f,
            [handle_x, -T - 0.0125, handle_z + 0.05],
            [0.006, 0.0125, 0.006],
            label,
        ),
        boxed(
            f,
            [handle_x, -T - 0.0125, handle_z - 0.05],
            [0.006, 0.0125, 0.006],
            label,
        ),
    ];
    (boxes, f * Point3::new(handle_x, -T - 0.033, handle_z))
}

/// A drawer (front, sides, bottom, back) filling `[x0, x1] × [z0, z1]` of the opening, depth `d`.
fn drawer(
    f: &Isometry3<f64>,
    x0: f64,
    x1: f64,
    z0: f64,
    z1: f64,
    d: f64,
) -> (Vec<SyntheticBox>, Point3<f64>) {
    let (cx, cz, hw, hh) = (
        (x0 + x1) / 2.0,
        (z0 + z1) / 2.0,
        (x1 - x0) / 2.0,
        (z1 - z0) / 2.0,
    );
    let inner = hw - 0.01;
    let boxes = vec![
        boxed(
            f,
            [cx, -T / 2.0, cz],
            [hw - 0.002, T / 2.0, hh - 0.002],
            PART,
        ),
        boxed(
            f,
            [cx - inner + 0.006, d / 2.0, cz - 0.01],
            [0.006, d / 2.0 - 0.01, hh - 0.03],
            PART,
        ),
        boxed(
            f,
            [cx + inner - 0.006, d / 2.0, cz - 0.01],
            [0.006, d / 2.0 - 0.01, hh - 0.03],
            PART,
        ),
        boxed(
            f,
            [cx, d / 2.0, z0 + 0.03],
            [inner, d / 2.0 - 0.01, 0.006],
            PART,
        ),
        boxed(
            f,
            [cx, d - 0.02, cz - 0.01],
            [inner, 0.006, hh - 0.03],
            PART,
        ),
        boxed(f, [cx, -T - 0.025, cz], [0.08, 0.008, 0.008], PART),
        boxed(
            f,
            [cx - 0.07, -T - 0.0125, cz],
            [0.006, 0.0125, 0.006],
            PART,
        ),
        boxed(
            f,
            [cx + 0.07, -T - 0.0125, cz],
            [0.006, 0.0125, 0.006],
            PART,
        ),
    ];
    (boxes, f * Point3::new(cx, -T - 0.033, cz))
}

/// Floor and a wall behind the cabinet (cabinet frame), plus a closed neighbour cabinet to the
/// right.
fn surroundings(f: &Isometry3<f64>, w: f64, d: f64, h: f64) -> Vec<SyntheticBox> {
    let mut out = vec![
        boxed(f, [w / 2.0, 0.0, -0.05], [1.5, 1.8, 0.05], 0),
        boxed(f, [w / 2.0, d + 0.05, 1.0], [1.5, 0.05, 1.0], 0),
    ];
    let right = f * Isometry3::translation(w + 0.004, 0.0, 0.0);
    out.extend(cabinet_body(&right, 0.5, d, h));
    out.extend(door(&right, 0.5, h, 0.08, h * 0.6, 0).0);
    out
}

/// Cameras in front of the cabinet (cabinet frame offsets), looking at its centre; the post
/// observation is taken from a small step back and aside (as the paper does).
fn cameras(f: &Isometry3<f64>, w: f64, h: f64, side: f64) -> (DepthCamera, DepthCamera) {
    let target = f * Point3::new(w / 2.0, 0.1, h / 2.0);
    let cam = |offset: Vector3<f64>| DepthCamera {
        origin: f * Point3::new(w / 2.0 + offset.x, offset.y, h / 2.0 + offset.z),
        target,
        up: Vector3::z(),
        horizontal_fov: 60f64.to_radians(),
        width: 200,
        height: 150,
        max_range: 4.0,
    };
    (
        cam(Vector3::new(side, -1.1, 0.45)),
        cam(Vector3::new(side * 1.6, -1.3, 0.55)),
    )
}

/// The gripper approaching the handle along the cabinet's +y, fingers vertical.
fn grasp_pose(f: &Isometry3<f64>, contact: Point3<f64>) -> Isometry3<f64> {
    let approach = f.rotation * Vector3::y();
    let rotation = UnitQuaternion::face_towards(&approach, &Vector3::z());
    Isometry3::from_parts(Translation3::from(contact.coords), rotation)
}

fn frame(x: f64, y: f64, yaw_deg: f64) -> Isometry3<f64> {
    Isometry3::new(Vector3::new(x, y, 0.0), Vector3::z() * yaw_deg.to_radians())
}

fn scenarios() -> Vec<Scenario> {
    let mut out = Vec::new();
    let (w, d, h) = (0.5, 0.55, 0.75);

    // Left-hinged door: hinge line at the front-left edge; opening turns it about −z.
    {
        let f = frame(-0.25, 0.0, 0.0);
        let (part, contact) = door(&f, w, h, w - 0.06, 0.6 * h, PART);
        let mut statics = cabinet_body(&f, w, d, h);
        statics.extend(surroundings(&f, w, d, h));
        let axis = Unit::new_normalize(f.rotation * -Vector3::z());
        let truth = Truth::Revolute {
            axis,
            pivot: f * Point3::new(0.0, -T, 0.0),
            angle: 40f64.to_radians(),
        };
        let (camera_pre, camera_post) = cameras(&f, w, h, 0.15);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name: "door left hinge",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Right-hinged door in a cabinet turned 30°: hinge at the front-right edge, about +z.
    {
        let f = frame(0.3, 0.2, 30.0);
        let (part, contact) = door(&f, w, h, 0.06, 0.6 * h, PART);
        let mut statics = cabinet_body(&f, w, d, h);
        statics.extend(surroundings(&f, w, d, h));
        let axis = Unit::new_normalize(f.rotation * Vector3::z());
        let truth = Truth::Revolute {
            axis,
            pivot: f * Point3::new(w, -T, 0.3),
            angle: 35f64.to_radians(),
        };
        let (camera_pre, camera_post) = cameras(&f, w, h, -0.15);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name: "door right hinge, yaw 30°",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Dishwasher-like door: hinge along the bottom front edge, about +x; handle near the top.
    {
        let f = frame(0.0, -0.4, -20.0);
        let (hw, hh) = (0.6, 0.8);
        let (part, contact) = door(&f, hw, hh, hw / 2.0, hh - 0.08, PART);
        // The dishwasher's handle is horizontal: a bar along x instead of the vertical one.
        let part = part
            .into_iter()
            .enumerate()
            .map(|(k, mut b)| {
                if k == 1 {
                    b.half_extents = Vector3::new(0.1, 0.008, 0.008);
                }
                b
            })
            .collect();
        let mut statics = cabinet_body(&f, hw, d, hh);
        statics.extend(surroundings(&f, hw, d, hh));
        let axis = Unit::new_normalize(f.rotation * Vector3::x());
        let truth = Truth::Revolute {
            axis,
            pivot: f * Point3::new(0.2, -T, 0.0),
            angle: 45f64.to_radians(),
        };
        let (camera_pre, camera_post) = cameras(&f, hw, hh, 0.1);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name: "dishwasher door",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Drawer pulled straight out of a cabinet turned 35°.
    for (name, yaw, distance) in [("drawer", 0.0, 0.18), ("drawer yaw 35°", 35.0, 0.12)] {
        let f = frame(0.1, 0.0, yaw);
        let (part, contact) = drawer(&f, T, w - T, h - 0.2, h - T, d);
        let mut statics = cabinet_body(&f, w, d, h);
        // A fixed lower front (panel and handle) below the drawer.
        statics.extend(door(&f, w, h - 0.22, w - 0.06, 0.35, 0).0);
        statics.extend(surroundings(&f, w, d, h));
        let axis = Unit::new_normalize(f.rotation * -Vector3::y());
        let truth = Truth::Prismatic { axis, distance };
        let (camera_pre, camera_post) = cameras(&f, w, h, 0.0);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name,
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Sliding panel moving sideways (along the cabinet's −x) in front of an open cabinet.
    {
        let f = frame(0.2, 0.1, 10.0);
        let (part, contact) = door(&f, w, h, w - 0.08, 0.5 * h, PART);
        let mut statics = cabinet_body(&f, w, d, h);
        statics.extend(surroundings(&f, w, d, h));
        let axis = Unit::new_normalize(f.rotation * -Vector3::x());
        let truth = Truth::Prismatic {
            axis,
            distance: 0.2,
        };
        let (camera_pre, camera_post) = cameras(&f, w, h, -0.1);
        let world_from_grasp = grasp_pose(&f, contact);
        out.push(Scenario {
            name: "sliding panel",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    // Nested: a drawer in a box mounted on a door that stands open at 50° (the door is static
    // in this interaction); the drawer slides along the opened door's outward normal.
    {
        let f = frame(-0.2, 0.0, 0.0);
        let door_motion = Screw {
            axis: -Vector3::z_axis(),
            point: f * Point3::new(0.0, -T, 0.0),
            angle: 50f64.to_radians(),
            translation: 0.0,
        }
        .to_isometry();
        let mut statics = cabinet_body(&f, w, d, h);
        statics.extend(surroundings(&f, w, d, h));
        let (door_boxes, _) = door(&f, w, h, w - 0.06, 0.6 * h, 0);
        statics.extend(door_boxes.into_iter().take(1).map(|mut b| {
            b.world_from_box = door_motion * b.world_from_box;
            b
        }));
        // The drawer's frame: on the door's outer face, its opening facing out of the door.
        let g = door_motion * f * Isometry3::translation(0.1, -T - 0.25, 0.3);
        let housing = [
            boxed(&g, [0.15, 0.125, -0.006], [0.15, 0.125, 0.006], 0),
            boxed(&g, [0.15, 0.125, 0.2], [0.15, 0.125, 0.006], 0),
        ];
        statics.extend(housing);
        let (part, contact) = drawer(&g, 0.01, 0.29, 0.0, 0.19, 0.24);
        let axis = Unit::new_normalize(g.rotation * -Vector3::y());
        let truth = Truth::Prismatic {
            axis,
            distance: 0.1,
        };
        let (camera_pre, camera_post) = cameras(&f, w, h, -0.2);
        let world_from_grasp = grasp_pose(&g, contact);
        out.push(Scenario {
            name: "drawer on opened door",
            statics,
            part,
            truth,
            contact,
            world_from_grasp,
            camera_pre,
            camera_post,
        });
    }
    out
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
    Observation {
        pre: pre.cloud,
        post: post.cloud,
        pre_labels: pre.labels,
        contact_pre,
        contact_post,
        ee_poses,
    }
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

// ---------------------------------------------------------------------------------------------
// Metrics on hand-computed cases.

#[test]
fn axis_angle_error_hand_cases() {
    // Perpendicular: arccos(0) = 90°.
    assert!((axis_angle_error(&Vector3::x(), &Vector3::z()) - 90.0).abs() < 1e-12);
    // Anti-parallel: min(arccos(−1), arccos(1)) = 0°, and unnormalised inputs are normalised.
    assert_eq!(
        axis_angle_error(&Vector3::new(0.0, 0.0, 3.0), &Vector3::new(0.0, 0.0, -0.5)),
        0.0
    );
    // 45° apart in the xy plane; the flipped estimate is 45° too (135° folds to 45°).
    let d = Vector3::new(1.0, 1.0, 0.0);
    assert!((axis_angle_error(&d, &Vector3::x()) - 45.0).abs() < 1e-12);
    assert!((axis_angle_error(&-d, &Vector3::x()) - 45.0).abs() < 1e-12);
    // Nearly parallel: the clamped dot product keeps the result finite (no NaN from acos(1+ε)).
    let e = axis_angle_error(&Vector3::new(1.0, 1e-9, 0.0), &Vector3::x());
    assert!(e.is_finite() && e < 1e-6);
    // A zero vector has no direction.
    assert!(axis_angle_error(&Vector3::zeros(), &Vector3::x()).is_nan());
}

#[test]
fn axis_position_error_hand_cases() {
    // Skew: the x axis and the line through (0, 0, 2) along y are 2 m apart (common normal z).
    let d = axis_position_error(
        &Point3::new(3.0, 0.0, 0.0),
        &Vector3::x(),
        &Point3::new(-1.0, 7.0, 2.0),
        &Vector3::y(),
    );
    assert!((d - 2.0).abs() < 1e-12, "{d}");
    // Skew at an angle: line 2 through (0, 0, 1.5) along (1, 1, 0); common normal z, 1.5 m.
    let d = axis_position_error(
        &Point3::origin(),
        &Vector3::x(),
        &Point3::new(0.0, 0.0, 1.5),
        &Vector3::new(1.0, 1.0, 0.0),
    );
    assert!((d - 1.5).abs() < 1e-12, "{d}");
    // Intersecting lines: 0.
    let d = axis_position_error(
        &Point3::new(1.0, 1.0, 1.0),
        &Vector3::x(),
        &Point3::new(1.0, 1.0, 1.0),
        &Vector3::z(),
    );
    assert!(d.abs() < 1e-12);
    // Parallel (and anti-parallel): vertical lines through (0,0) and (0.3, 0.4) are 0.5 m apart.
    let d = axis_position_error(
        &Point3::origin(),
        &Vector3::z(),
        &Point3::new(0.3, 0.4, 9.0),
        &Vector3::z(),
    );
    assert!((d - 0.5).abs() < 1e-12, "{d}");
    let d = axis_position_error(
        &Point3::origin(),
        &Vector3::z(),
        &Point3::new(0.3, 0.4, -2.0),
        &(-2.0 * Vector3::z()),
    );
    assert!((d - 0.5).abs() < 1e-12, "{d}");
    // Degenerate direction.
    assert!(
        axis_position_error(
            &Point3::origin(),
            &Vector3::zeros(),
            &Point3::origin(),
            &Vector3::z()
        )
        .is_nan()
    );
}

#[test]
fn joint_type_accuracy_counts() {
    use JointKindEstimate::*;
    assert_eq!(
        joint_type_accuracy([
            (Revolute, Revolute),
            (Prismatic, Revolute),
            (Prismatic, Prismatic),
            (Unknown, Unknown)
        ]),
        Some(0.5)
    );
    assert_eq!(joint_type_accuracy(std::iter::empty()), None);
}

// ---------------------------------------------------------------------------------------------
// Estimators against ground truth.

/// The renderer puts noise-free points on the surfaces it reports, and only on faces that face
/// the camera (a partial view).
#[test]
fn renderer_gives_partial_exact_views() {
    let s = &scenarios()[0];
    let o = observe(s, 0.0, 0.0, 1, 1.0);
    let mut boxes = s.statics.clone();
    boxes.extend(s.part.iter().copied());
    assert!(o.pre.points.len() > 10_000, "{}", o.pre.points.len());
    for p in &o.pre.points {
        // Each point lies on the boundary of some box (distance to the nearest box surface ≈ 0).
        let on_surface = boxes.iter().any(|b| {
            let l = b.world_from_box.inverse() * p;
            let inside = (0..3).all(|k| l[k].abs() <= b.half_extents[k] + 1e-9);
            inside && (0..3).any(|k| (l[k].abs() - b.half_extents[k]).abs() < 1e-9)
        });
        assert!(on_surface, "{p}");
    }
    // The cabinet's back panel is hidden behind the closed door before the interaction.
    let back = &s.statics[4];
    let behind = o.pre.points.iter().filter(|p| {
        let l = back.world_from_box.inverse() * *p;
        (0..3).all(|k| l[k].abs() <= back.half_extents[k] + 1e-9)
    });
    assert_eq!(behind.count(), 0);
}

/// Targets of the issue at σ = 5 mm, 5 % outliers, partial views: the right joint type,
/// ≤ 2° axis error for both types, ≤ 2 cm pivot (axis line) error for revolute joints, for both
/// estimators on every scenario. Travel (angle or distance) within 3° / 2 cm: the proprioceptive
/// travel comes from the first and last inlier poses, σ√2 ≈ 7 mm (≈ 0.9° at a 0.45 m radius)
/// per estimate, so these are 3σ bounds. The two-view segmentation is ≥ 80 % precise (its points
/// are on the part; the documented leak is the floor the opened door hides from the post view,
/// 10–15 % for the doors) and overlaps the part with IoU ≥ 0.7 except where the geometry cannot tell (the sliding panel's face slides along itself; the nested drawer's front stays
/// within τ of its housing), which the module documents.
#[test]
fn estimators_meet_targets_at_5mm() {
    for s in &scenarios() {
        let o = observe(s, 0.005, 0.05, 7, 1.0);
        for est in estimators() {
            let e = est.estimate(&o.interaction()).expect("valid input");
            let err = errors(s, &o, &e, 1.0);
            let ctx = format!("{} / {}: {err:?}\n{}", s.name, est.name(), e.details);
            assert!(err.kind_ok, "wrong type: {ctx}");
            assert!(err.axis_deg <= 2.0, "axis: {ctx}");
            if let Some(p) = err.pivot_m {
                assert!(p <= 0.02, "pivot: {ctx}");
            }
            let travel_tol = if matches!(s.truth, Truth::Revolute { .. }) {
                3.0
            } else {
                0.02
            };
            assert!(err.travel <= travel_tol, "travel: {ctx}");
            if let Some((iou, precision)) = err.iou.zip(err.precision) {
                assert!(precision >= 0.8, "segmentation precision: {ctx}");
                let ambiguous = matches!(s.name, "sliding panel" | "drawer on opened door");
                assert!(ambiguous || iou >= 0.7, "segmentation IoU: {ctx}");
            }
            assert!((0.0..=1.0).contains(&e.score), "{ctx}");
        }
    }
}

/// The two-view estimator returns the moving part's points in the pre pose.
#[test]
fn two_view_part_points_are_the_segmented_pre_points() {
    let s = &scenarios()[3];
    let o = observe(s, 0.002, 0.0, 3, 1.0);
    let e = TwoView::default().estimate(&o.interaction()).unwrap();
    assert_eq!(e.part_points.len(), e.moving.len());
    for (k, p) in e.moving.iter().zip(&e.part_points) {
        assert_eq!(o.pre.points[*k], *p);
    }
    // The returned segmentation contains (almost) no static points: ≥ 95 % of it is the part.
    let on_part = e
        .moving
        .iter()
        .filter(|&&k| o.pre_labels[k] == Some(PART))
        .count();
    assert!(
        on_part as f64 >= 0.95 * e.moving.len() as f64,
        "{on_part}/{}",
        e.moving.len()
    );
}

// ---------------------------------------------------------------------------------------------
// Proprioceptive model fitting on plain arcs and lines.

fn arc_poses(
    axis: Unit<Vector3<f64>>,
    pivot: Point3<f64>,
    radius_dir: Vector3<f64>,
    angle: f64,
    n: usize,
    sigma: f64,
    seed: u64,
) -> Vec<(f64, Isometry3<f64>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let start = Isometry3::from_parts(
        Translation3::from(pivot.coords + radius_dir),
        UnitQuaternion::identity(),
    );
    (0..n)
        .map(|k| {
            let m = Screw {
                axis,
                point: pivot,
                angle: angle * k as f64 / (n - 1) as f64,
                translation: 0.0,
            }
            .to_isometry();
            let mut p = m * start;
            p.translation.vector += Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            ) * sigma;
            (k as f64 * 0.1, p)
        })
        .collect()
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

/// An arc of a tilted axis with uniform ±5 mm noise (positions and orientations from the
/// rotation) gives a revolute joint with the arc's axis, centre and angle; positions alone
/// (orientation off) too.
#[test]
fn proprioceptive_arc_and_line() {
    let axis = Unit::new_normalize(Vector3::new(0.2, -0.1, 1.0));
    let pivot = Point3::new(1.0, 2.0, 0.5);
    let radial = axis.cross(&Vector3::x()).normalize() * 0.45;
    let poses = arc_poses(axis, pivot, radial, 1.0, 25, 0.005, 11);
    for orientation in [
        OrientationModel::Rigid,
        OrientationModel::ApproachAxis,
        OrientationModel::Ignored,
    ] {
        let e = proprio(orientation)
            .estimate(&proprio_only(&poses))
            .unwrap();
        let JointEstimate::Revolute {
            axis: a,
            pivot: q,
            angle,
        } = e.joint
        else {
            panic!("{e:?}")
        };
        let tol = if orientation == OrientationModel::Ignored {
            4.0
        } else {
            2.0
        };
        assert!(axis_angle_error(&a, &axis) < tol, "{orientation:?} {e:?}");
        assert!(axis_position_error(&q, &a, &pivot, &axis) < 0.02, "{e:?}");
        assert!((angle - 1.0).abs() < 0.05, "{e:?}");
        assert!(
            a.dot(&axis) > 0.0,
            "the sweep is right-handed about the true axis"
        );
    }
    // A straight pull with a fixed orientation.
    let dir = Unit::new_normalize(Vector3::new(1.0, -2.0, 0.3));
    let line = arc_poses(
        Vector3::z_axis(),
        Point3::origin(),
        Vector3::x(),
        0.0,
        20,
        0.005,
        5,
    )
    .into_iter()
    .enumerate()
    .map(|(k, (t, mut p))| {
        p.translation.vector += dir.into_inner() * 0.01 * k as f64;
        (t, p)
    })
    .collect::<Vec<_>>();
    let e = Proprioceptive::default()
        .estimate(&proprio_only(&line))
        .unwrap();
    let JointEstimate::Prismatic { axis: a, distance } = e.joint else {
        panic!("{e:?}")
    };
    assert!(axis_angle_error(&a, &dir) < 2.0, "{e:?}");
    assert!(a.dot(&dir) > 0.0);
    assert!((distance - 0.19).abs() < 0.01, "{e:?}");
}

/// A compliant grasp on a door: the approach (tool z) stays normal to the front, up to a
/// 1° tilt, while the wrist rolls about it at random (±20°) and the tool sits 2 mm off the grasp
/// point (uniform per axis). The approach-axis model recovers the hinge generated here to
/// within 1° and 1 cm; the rigid model, which reads the roll as the part turning, is off by more
/// than the approach model and, here, by more than 2°.
#[test]
fn proprioceptive_compliant_grasp_needs_only_the_approach_axis() {
    let axis = Unit::new_normalize(Vector3::new(0.03, -0.02, 1.0));
    let pivot = Point3::new(1.0, 2.0, 0.5);
    let radial = axis.cross(&Vector3::x()).normalize() * 0.4;
    // The front's normal at the handle, the approach: perpendicular to the axis and the radius.
    let approach = axis.cross(&radial).normalize();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let n = 25;
    let poses: Vec<(f64, Isometry3<f64>)> = (0..n)
        .map(|k| {
            let turn = UnitQuaternion::from_axis_angle(&axis, 0.6 * k as f64 / (n - 1) as f64);
            let z = turn * approach;
            let tilt = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            let tilted = UnitQuaternion::from_scaled_axis(tilt.cross(&z) * 1f64.to_radians()) * z;
            let roll = rng.random_range(-20.0f64..20.0).to_radians();
            let onto = UnitQuaternion::rotation_between(&Vector3::z(), &tilted).unwrap();
            let rotation =
                UnitQuaternion::from_axis_angle(&Unit::new_normalize(tilted), roll) * onto;
            let noise = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            ) * 0.002;
            let p = pivot + turn * radial + noise;
            (
                k as f64 * 0.1,
                Isometry3::from_parts(p.coords.into(), rotation),
            )
        })
        .collect();
    let error = |orientation| {
        let e = proprio(orientation)
            .estimate(&proprio_only(&poses))
            .unwrap();
        let JointEstimate::Revolute {
            axis: a, pivot: q, ..
        } = e.joint
        else {
            panic!("{orientation:?}: {e:?}")
        };
        (
            axis_angle_error(&a, &axis),
            axis_position_error(&q, &a, &pivot, &axis),
        )
    };
    let (approach_angle, approach_position) = error(OrientationModel::ApproachAxis);
    let (rigid_angle, _) = error(OrientationModel::Rigid);
    assert!(approach_angle < 1.0, "{approach_angle}°");
    assert!(approach_position < 0.01, "{approach_position} m");
    assert!(
        rigid_angle > 2.0 && rigid_angle > approach_angle,
        "rigid {rigid_angle}° vs approach {approach_angle}°"
    );
}

// ---------------------------------------------------------------------------------------------
// Degenerate and bad input.

#[test]
fn degenerate_input_gives_unknown() {
    let s = &scenarios()[0];
    // No motion at all.
    let still = observe(s, 0.005, 0.05, 2, 0.0);
    for est in estimators() {
        let e = est.estimate(&still.interaction()).unwrap();
        assert!(
            matches!(e.joint, JointEstimate::Unknown { .. }),
            "{}: {e:?}",
            est.name()
        );
    }
    // Too little motion: the door moves 0.5° (the handle 4 mm, below both noise-level thresholds).
    let nudge = observe(s, 0.005, 0.0, 2, 0.5 / 40.0);
    for est in estimators() {
        let e = est.estimate(&nudge.interaction()).unwrap();
        assert!(
            matches!(e.joint, JointEstimate::Unknown { .. }),
            "{}: {e:?}",
            est.name()
        );
    }
    // Too few points and too few poses.
    let few = PointCloud::new(still.pre.points[..20].to_vec(), still.pre.origin, 0.0);
    let i = Interaction {
        pre: &few,
        post: &few,
        ee_poses: &still.ee_poses[..3],
        ..still.interaction()
    };
    for est in estimators() {
        let e = est.estimate(&i).unwrap();
        assert!(
            matches!(e.joint, JointEstimate::Unknown { .. }),
            "{}: {e:?}",
            est.name()
        );
    }
    // Collinear end-effector positions while the orientation turns by 60°: neither a line (the
    // orientation changes) nor a circle (no curvature) explains it, when the turn moves what
    // the orientation model trusts. A turn about the tool's z axis (the approach) is a wrist
    // roll to the approach-axis model: a straight slide with a rolling wrist.
    let twist = |about: Vector3<f64>| -> Vec<(f64, Isometry3<f64>)> {
        (0..20)
            .map(|k| {
                let f = k as f64 / 19.0;
                let p = Isometry3::new(
                    Vector3::new(0.3 * f, 0.0, 0.8),
                    about * (FRAC_PI_2 * 2.0 / 3.0) * f,
                );
                (f, p)
            })
            .collect()
    };
    for (orientation, about, slide) in [
        (OrientationModel::Rigid, Vector3::z(), false),
        (OrientationModel::Rigid, Vector3::y(), false),
        (OrientationModel::ApproachAxis, Vector3::y(), false),
        (OrientationModel::ApproachAxis, Vector3::z(), true),
    ] {
        let e = proprio(orientation)
            .estimate(&proprio_only(&twist(about)))
            .unwrap();
        if slide {
            let JointEstimate::Prismatic { axis, .. } = e.joint else {
                panic!("{orientation:?}: {e:?}")
            };
            assert!(axis_angle_error(&axis, &Vector3::x_axis()) < 0.1, "{e:?}");
        } else {
            assert!(
                matches!(e.joint, JointEstimate::Unknown { .. }),
                "{orientation:?} about {about:?}: {e:?}"
            );
        }
    }
}

#[test]
fn bad_input_is_an_error() {
    let s = &scenarios()[3];
    let o = observe(s, 0.002, 0.0, 4, 1.0);
    let mut nan = o.pre.clone();
    nan.points[17].y = f64::NAN;
    let i = Interaction {
        pre: &nan,
        ..o.interaction()
    };
    for est in estimators() {
        let err = est.estimate(&i).unwrap_err();
        assert_eq!(
            err,
            ArticulationError::NonFinite {
                input: InputKind::PreCloud,
                what: "point",
                index: 17
            }
        );
    }
    let mut colored = o.post.clone();
    colored.colors = Some(vec![[0.5; 3]; colored.points.len() - 1]);
    let i = Interaction {
        post: &colored,
        ..o.interaction()
    };
    let err = TwoView::default().estimate(&i).unwrap_err();
    assert!(
        matches!(
            err,
            ArticulationError::ColorCountMismatch {
                input: InputKind::PostCloud,
                ..
            }
        ),
        "{err}"
    );
    let mut poses = o.ee_poses.clone();
    poses[5].0 = poses[4].0;
    let i = Interaction {
        ee_poses: &poses,
        ..o.interaction()
    };
    let err = Proprioceptive::default().estimate(&i).unwrap_err();
    assert!(
        matches!(err, ArticulationError::TimeNotIncreasing { index: 5, .. }),
        "{err}"
    );
    let i = Interaction {
        contact_post: Point3::new(f64::INFINITY, 0.0, 0.0),
        ..o.interaction()
    };
    assert!(matches!(
        TwoView::default().estimate(&i),
        Err(ArticulationError::NonFinite {
            input: InputKind::ContactPost,
            ..
        })
    ));
    let bad = TwoView {
        settings: TwoViewSettings {
            trim_fraction: 0.0,
            ..Default::default()
        },
    };
    assert!(matches!(
        bad.estimate(&o.interaction()),
        Err(ArticulationError::InvalidSetting(s)) if s.field == "trim_fraction"
    ));
}

// ---------------------------------------------------------------------------------------------
// The error table of the closing note.

/// Prints errors per estimator and noise level over all scenarios and 3 seeds:
/// `cargo test --test lib articulation_error_table -- --ignored --nocapture`
/// (`KS_TABLE_ROWS=two-view:5` in the environment prints one row only).
#[test]
#[ignore = "measurement table; run with --ignored --nocapture"]
fn articulation_error_table() {
    let scenarios = scenarios();
    println!(
        "| estimator | σ (mm) | type acc. | axis err. mean / max (°) | pivot err. mean / max (cm) | travel err. rev (°) / pri (cm) | IoU mean |"
    );
    println!("|---|---|---|---|---|---|---|");
    // `KS_TABLE_ROWS=two-view:5` limits the table to one estimator and noise level.
    let only = std::env::var("KS_TABLE_ROWS").ok();
    for est in estimators() {
        for sigma in [0.002, 0.005, 0.010] {
            let row = format!("{}:{}", est.name(), (sigma * 1000.0f64).round());
            if only.as_ref().is_some_and(|o| *o != row) {
                continue;
            }
            let mut kinds = Vec::new();
            let (mut axis, mut pivot, mut rev, mut pri, mut iou) =
                (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for s in &scenarios {
                for seed in 0..3 {
                    let o = observe(s, sigma, 0.05, 100 + seed, 1.0);
                    let e = est.estimate(&o.interaction()).expect("valid input");
                    let err = errors(s, &o, &e, 1.0);
                    kinds.push((e.joint.kind(), s.truth.kind()));
                    if !err.kind_ok || err.axis_deg > 2.0 || err.pivot_m.is_some_and(|p| p > 0.02) {
                        eprintln!(
                            "miss: {} σ {sigma} seed {seed} {}: {err:?}\n  {}",
                            est.name(),
                            s.name,
                            e.details
                        );
                    }
                    if err.axis_deg.is_finite() {
                        axis.push(err.axis_deg);
                    }
                    pivot.extend(err.pivot_m.map(|p| p * 100.0));
                    if err.kind_ok {
                        match s.truth {
                            Truth::Revolute { .. } => rev.push(err.travel),
                            Truth::Prismatic { .. } => pri.push(err.travel * 100.0),
                        }
                    }
                    iou.extend(err.iou);
                }
            }
            let mean = |v: &[f64]| {
                if v.is_empty() {
                    f64::NAN
                } else {
                    v.iter().sum::<f64>() / v.len() as f64
                }
            };
            let max = |v: &[f64]| v.iter().copied().fold(f64::NAN, f64::max);
            println!(
                "| {} | {:.0} | {:.2} | {:.2} / {:.2} | {:.2} / {:.2} | {:.2} / {:.2} | {} |",
                est.name(),
                sigma * 1000.0,
                joint_type_accuracy(kinds).unwrap_or(f64::NAN),
                mean(&axis),
                max(&axis),
                mean(&pivot),
                max(&pivot),
                mean(&rev),
                mean(&pri),
                if iou.is_empty() {
                    "–".to_string()
                } else {
                    format!("{:.2}", mean(&iou))
                },
            );
        }
    }
}

/// Time per two-view estimate with and without the voxel thinning of the ICP points, run
/// interleaved (the minimum of 5 runs each, robust to other load on the machine):
/// `cargo test --test lib two_view_timing -- --ignored --nocapture`.
#[test]
#[ignore = "timing; run with --ignored --nocapture"]
fn two_view_timing() {
    let thinned = TwoView::default();
    let unthinned = TwoView {
        settings: TwoViewSettings {
            icp_voxel: 0.0,
            ..Default::default()
        },
    };
    for s in &scenarios() {
        let o = observe(s, 0.005, 0.05, 100, 1.0);
        let mut best = [f64::INFINITY; 2];
        for _ in 0..5 {
            for (k, est) in [&thinned, &unthinned].iter().enumerate() {
                let t = std::time::Instant::now();
                let e = est.estimate(&o.interaction()).expect("valid input");
                best[k] = best[k].min(t.elapsed().as_secs_f64());
                assert!(e.joint.kind() == s.truth.kind(), "{}", s.name);
            }
        }
        println!(
            "{}: {} + {} points, {:.0} ms thinned, {:.0} ms unthinned",
            s.name,
            o.pre.points.len(),
            o.post.points.len(),
            best[0] * 1e3,
            best[1] * 1e3
        );
    }
}
