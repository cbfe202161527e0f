//! The hard classes of articulation estimation, self-contained (the fusion bench includes
//! this file too): a small door (0.25 m) opened 10°, the same door on a sagging hinge (axis
//! leaning 4° in the door's plane) opened 15°, a drawer pulled 12 cm out of a carcass turned
//! 20°, an oven door hinged at the bottom falling 25° toward the robot, a sliding door moved
//! 20 cm along its own face, and a door opened 20° that the cameras see only in part (not its
//! hinge edge). Clouds are ray-cast partial views with the carcass, a floor and a wall in view;
//! the gripper path has 60 poses with 2 mm / 1° noise and a free wrist roll (a random walk
//! about the approach axis).

use kinscene::articulation::synthetic::{DepthCamera, DepthNoise, SyntheticBox, render};
use kinscene::articulation::{
    ArticulationEstimator, CHI2_2DOF_95, Estimate, Interaction, JointEstimate, JointKindEstimate,
    PointCloud, Screw, axis_angle_error, axis_position_error,
};
use kinscene::discovery::DiscoverySettings;
use std::f64::consts::FRAC_PI_2;

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Panel thickness, m.
const T: f64 = 0.018;

/// A known joint and its full travel.
#[derive(Debug, Clone, Copy)]
pub enum HardTruth {
    /// Rotation by `angle` about the line through `pivot` along `axis`.
    Revolute {
        axis: Unit<Vector3<f64>>,
        pivot: Point3<f64>,
        angle: f64,
    },
    /// Translation by `distance` along `axis`.
    Prismatic {
        axis: Unit<Vector3<f64>>,
        distance: f64,
    },
}

impl HardTruth {
    /// The travel from closed: rad (revolute) or m (prismatic).
    pub fn travel(&self) -> f64 {
        match *self {
            HardTruth::Revolute { angle, .. } => angle,
            HardTruth::Prismatic { distance, .. } => distance,
        }
    }

    /// The part's motion after `fraction` of the travel.
    pub fn motion(&self, fraction: f64) -> Isometry3<f64> {
        match *self {
            HardTruth::Revolute { axis, pivot, angle } => Screw {
                axis,
                point: pivot,
                angle: angle * fraction,
                translation: 0.0,
            }
            .to_isometry(),
            HardTruth::Prismatic { axis, distance } => {
                let t = axis.into_inner() * distance * fraction;
                Isometry3::translation(t.x, t.y, t.z)
            }
        }
    }

    /// How estimate `e` compares with this truth.
    pub fn errors(&self, e: &Estimate) -> HardErrors {
        let inside = |d: Option<f64>| d.is_some_and(|d| d <= CHI2_2DOF_95);
        let u = e.uncertainty;
        match (&e.joint, *self) {
            (
                JointEstimate::Revolute { axis, pivot, .. },
                HardTruth::Revolute {
                    axis: a, pivot: q, ..
                },
            ) => HardErrors {
                kind_ok: true,
                axis_deg: axis_angle_error(axis, &a),
                pivot_m: Some(axis_position_error(pivot, axis, &q, &a)),
                covered: inside(u.map(|u| u.axis_mahalanobis_squared(axis, &a)))
                    && inside(u.and_then(|u| u.pivot_mahalanobis_squared(pivot, axis, &q, &a))),
            },
            (JointEstimate::Prismatic { axis, .. }, HardTruth::Prismatic { axis: a, .. }) => {
                HardErrors {
                    kind_ok: true,
                    axis_deg: axis_angle_error(axis, &a),
                    pivot_m: None,
                    covered: inside(u.map(|u| u.axis_mahalanobis_squared(axis, &a))),
                }
            }
            _ => HardErrors {
                kind_ok: false,
                axis_deg: f64::NAN,
                pivot_m: None,
                covered: false,
            },
        }
    }

    /// The joint type.
    pub fn kind(&self) -> JointKindEstimate {
        match self {
            HardTruth::Revolute { .. } => JointKindEstimate::Revolute,
            HardTruth::Prismatic { .. } => JointKindEstimate::Prismatic,
        }
    }
}

/// An estimate against a hard case's truth.
pub struct HardErrors {
    /// The joint type is right (the other fields are NaN / `None` / false otherwise).
    pub kind_ok: bool,
    /// Axis angle error (°).
    pub axis_deg: f64,
    /// Pivot error (m), revolute joints.
    pub pivot_m: Option<f64>,
    /// The axis (and, revolute, the pivot) inside the estimate's 95 % regions.
    pub covered: bool,
}

/// One hard scene.
pub struct HardCase {
    pub name: &'static str,
    pub statics: Vec<SyntheticBox>,
    pub part: Vec<SyntheticBox>,
    pub truth: HardTruth,
    pub contact: Point3<f64>,
    pub grasp: Isometry3<f64>,
    pub cameras: (DepthCamera, DepthCamera),
    /// The joint's limit from closed: rad (revolute) or m (prismatic).
    pub limit: f64,
}

impl HardCase {
    /// The truth after the robot pulled `extra` (m of contact travel along the part's path)
    /// further than `truth`, stopped at the case's limit: a keep-pulling round.
    pub fn pulled_further(&self, truth: &HardTruth, extra: f64) -> HardTruth {
        match *truth {
            HardTruth::Revolute { axis, pivot, angle } => {
                let offset = self.contact - pivot;
                let radius = (offset - axis.into_inner() * offset.dot(&axis)).norm();
                HardTruth::Revolute {
                    axis,
                    pivot,
                    angle: (angle + extra / radius).min(self.limit),
                }
            }
            HardTruth::Prismatic { axis, distance } => HardTruth::Prismatic {
                axis,
                distance: (distance + extra).min(self.limit),
            },
        }
    }
}

/// One observation of a hard case.
pub struct HardObservation {
    pub pre: PointCloud,
    pub post: PointCloud,
    pub contact_pre: Point3<f64>,
    pub contact_post: Point3<f64>,
    pub ee_poses: Vec<(f64, Isometry3<f64>)>,
}

impl HardObservation {
    pub fn interaction(&self) -> Interaction<'_> {
        Interaction {
            pre: &self.pre,
            post: &self.post,
            contact_pre: self.contact_pre,
            contact_post: self.contact_post,
            ee_poses: &self.ee_poses,
        }
    }
}

fn boxed(f: &Isometry3<f64>, c: [f64; 3], h: [f64; 3], label: usize) -> SyntheticBox {
    SyntheticBox {
        world_from_box: f * Isometry3::translation(c[0], c[1], c[2]),
        half_extents: Vector3::from(h),
        label,
    }
}

/// A carcass open at the front (frame: x right, y in, z up, opening at y = 0 over
/// `[0, w] × [0, h]`), depth `d`, with a floor and a wall behind.
fn carcass(f: &Isometry3<f64>, w: f64, d: f64, h: f64) -> Vec<SyntheticBox> {
    let (t2, d2, h2, w2) = (T / 2.0, d / 2.0, h / 2.0, w / 2.0);
    vec![
        boxed(f, [t2, d2, h2], [t2, d2, h2], 0),
        boxed(f, [w - t2, d2, h2], [t2, d2, h2], 0),
        boxed(f, [w2, d2, t2], [w2 - T, d2, t2], 0),
        boxed(f, [w2, d2, h - t2], [w2 - T, d2, t2], 0),
        boxed(f, [w2, d - t2, h2], [w2 - T, t2, h2 - T], 0),
        boxed(f, [w2, 0.0, -0.05], [1.2, 1.2, 0.05], 0),
        boxed(f, [w2, d + 0.05, 0.8], [1.2, 0.05, 0.8], 0),
    ]
}

/// Cameras 0.9 m in front of the opening, a little above; the post one steps aside.
fn cameras(f: &Isometry3<f64>, w: f64, h: f64) -> (DepthCamera, DepthCamera) {
    let target = f * Point3::new(w / 2.0, 0.05, h / 2.0);
    let cam = |x: f64, y: f64, z: f64| DepthCamera {
        origin: f * Point3::new(w / 2.0 + x, y, h / 2.0 + z),
        target,
        up: Vector3::z(),
        horizontal_fov: 60f64.to_radians(),
        width: 200,
        height: 150,
        max_range: 4.0,
    };
    (cam(0.1, -0.9, 0.35), cam(0.2, -1.0, 0.4))
}

/// The gripper at `contact`, approaching along the carcass's +y, fingers vertical.
fn grasp(f: &Isometry3<f64>, contact: Point3<f64>) -> Isometry3<f64> {
    let rotation = UnitQuaternion::face_towards(&(f.rotation * Vector3::y()), &Vector3::z());
    Isometry3::from_parts(Translation3::from(contact.coords), rotation)
}

/// A left-hinged door panel filling the carcass's front (`w` × `h`), with a vertical handle
/// near the free edge at 60 % of the height (label 1), and the grasp point on the handle.
fn left_door(f: &Isometry3<f64>, w: f64, h: f64) -> (Vec<SyntheticBox>, Point3<f64>) {
    let part = vec![
        boxed(
            f,
            [w / 2.0, -T / 2.0, h / 2.0],
            [w / 2.0 - 0.002, T / 2.0, h / 2.0 - 0.002],
            1,
        ),
        boxed(f, [w - 0.04, -T - 0.025, h * 0.6], [0.008, 0.008, 0.05], 1),
        boxed(
            f,
            [w - 0.04, -T - 0.0125, h * 0.6 + 0.04],
            [0.006, 0.0125, 0.006],
            1,
        ),
        boxed(
            f,
            [w - 0.04, -T - 0.0125, h * 0.6 - 0.04],
            [0.006, 0.0125, 0.006],
            1,
        ),
    ];
    (part, f * Point3::new(w - 0.04, -T - 0.033, h * 0.6))
}

/// The revolute truth of a left hinge at the carcass's front-left edge, leaning `lean_deg`
/// within the door's plane, opened `angle_deg` (the free edge toward the robot).
fn left_hinge(f: &Isometry3<f64>, lean_deg: f64, angle_deg: f64) -> HardTruth {
    let lean = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), lean_deg.to_radians());
    HardTruth::Revolute {
        axis: Unit::new_normalize(f.rotation * (lean * -Vector3::z())),
        pivot: f * Point3::new(0.0, -T, 0.0),
        angle: angle_deg.to_radians(),
    }
}

/// A small left-hinged door (0.25 × 0.4 m) with its handle near the free edge, its hinge
/// leaning `lean_deg` within the door's plane, opened `angle_deg`.
fn small_door(name: &'static str, lean_deg: f64, angle_deg: f64) -> HardCase {
    let (w, d, h) = (0.25, 0.35, 0.4);
    let f = Isometry3::new(Vector3::new(-0.1, 0.0, 0.3), Vector3::zeros());
    let mut statics = carcass(&f, w, d, h);
    statics.push(boxed(&f, [w / 2.0, d / 2.0, -0.15], [0.3, 0.2, 0.15], 0));
    let (part, contact) = left_door(&f, w, h);
    HardCase {
        name,
        statics,
        part,
        truth: left_hinge(&f, lean_deg, angle_deg),
        contact,
        grasp: grasp(&f, contact),
        cameras: cameras(&f, w, h),
        limit: FRAC_PI_2,
    }
}

/// An oven (0.6 × 0.5 m front, in a carcass turned −15°, standing on the floor) whose door is
/// hinged along its bottom front edge and falls toward the robot by 25°, pulled at a
/// horizontal handle bar near its top.
fn oven_door() -> HardCase {
    let (w, d, h) = (0.6, 0.5, 0.5);
    let f = Isometry3::new(
        Vector3::new(0.0, 0.1, 0.0),
        Vector3::z() * -15f64.to_radians(),
    );
    let statics = carcass(&f, w, d, h);
    let hz = h - 0.06;
    let part = vec![
        boxed(
            &f,
            [w / 2.0, -T / 2.0, h / 2.0],
            [w / 2.0 - 0.002, T / 2.0, h / 2.0 - 0.002],
            1,
        ),
        boxed(&f, [w / 2.0, -T - 0.025, hz], [0.2, 0.008, 0.008], 1),
        boxed(
            &f,
            [w / 2.0 - 0.18, -T - 0.0125, hz],
            [0.006, 0.0125, 0.006],
            1,
        ),
        boxed(
            &f,
            [w / 2.0 + 0.18, -T - 0.0125, hz],
            [0.006, 0.0125, 0.006],
            1,
        ),
    ];
    let contact = f * Point3::new(w / 2.0, -T - 0.033, hz);
    HardCase {
        name: "oven door 25°",
        statics,
        part,
        // About +x the top (z = h) moves to −y, toward the robot.
        truth: HardTruth::Revolute {
            axis: Unit::new_normalize(f.rotation * Vector3::x()),
            pivot: f * Point3::new(0.0, -T, 0.0),
            angle: 25f64.to_radians(),
        },
        contact,
        grasp: grasp(&f, contact),
        cameras: cameras(&f, w, h),
        limit: FRAC_PI_2,
    }
}

/// A cupboard (0.8 × 0.5 m front, turned 10°, on a plinth) closed by two sliding panels in
/// two tracks: the left one fixed in the back track, the right one in the front track slid
/// 20 cm left along its own face, pulled at a vertical handle near its right edge. The moving
/// panel stays in its plane, so the clouds' change is only at its edges, the handle and the
/// interior it uncovers.
fn sliding_door() -> HardCase {
    let (w, d, h) = (0.8, 0.4, 0.5);
    let f = Isometry3::new(
        Vector3::new(-0.2, 0.0, 0.2),
        Vector3::z() * 10f64.to_radians(),
    );
    let mut statics = carcass(&f, w, d, h);
    statics.push(boxed(
        &f,
        [w / 2.0, d / 2.0, -0.1],
        [w / 2.0, d / 2.0, 0.1],
        0,
    ));
    let (pw, ph) = (w / 4.0 - 0.002, h / 2.0 - 0.002);
    statics.push(boxed(
        &f,
        [w / 4.0, -T / 2.0, h / 2.0],
        [pw, T / 2.0, ph],
        0,
    ));
    let (hx, hz) = (w - 0.05, h / 2.0);
    let part = vec![
        boxed(&f, [3.0 * w / 4.0, -1.5 * T, h / 2.0], [pw, T / 2.0, ph], 1),
        boxed(&f, [hx, -2.0 * T - 0.025, hz], [0.008, 0.008, 0.05], 1),
        boxed(
            &f,
            [hx, -2.0 * T - 0.0125, hz + 0.04],
            [0.006, 0.0125, 0.006],
            1,
        ),
        boxed(
            &f,
            [hx, -2.0 * T - 0.0125, hz - 0.04],
            [0.006, 0.0125, 0.006],
            1,
        ),
    ];
    let contact = f * Point3::new(hx, -2.0 * T - 0.033, hz);
    HardCase {
        name: "sliding door 20 cm",
        statics,
        part,
        truth: HardTruth::Prismatic {
            axis: Unit::new_normalize(f.rotation * -Vector3::x()),
            distance: 0.2,
        },
        contact,
        grasp: grasp(&f, contact),
        cameras: cameras(&f, w, h),
        // The moving panel covers the fixed one.
        limit: w / 2.0,
    }
}

/// A left-hinged door (0.45 × 0.7 m, carcass turned −10°, on the floor) opened 20°, seen
/// partially: narrow cameras (40°) 0.6 m away aimed at the free edge see the handle half of
/// the door, the carcass's right side, the floor and the wall, but not the hinge edge.
fn partial_view_door() -> HardCase {
    let (w, d, h) = (0.45, 0.5, 0.7);
    let f = Isometry3::new(
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::z() * -10f64.to_radians(),
    );
    let statics = carcass(&f, w, d, h);
    let (part, contact) = left_door(&f, w, h);
    let target = f * Point3::new(w, 0.0, 0.3 * h);
    let cam = |x: f64, y: f64, z: f64| DepthCamera {
        origin: f * Point3::new(w + x, y, 0.3 * h + z),
        target,
        up: Vector3::z(),
        horizontal_fov: 40f64.to_radians(),
        width: 200,
        height: 150,
        max_range: 4.0,
    };
    HardCase {
        name: "partial view door 20°",
        statics,
        part,
        truth: left_hinge(&f, 0.0, 20.0),
        contact,
        grasp: grasp(&f, contact),
        cameras: (cam(0.0, -0.6, 0.3), cam(0.08, -0.65, 0.32)),
        limit: FRAC_PI_2,
    }
}

/// A drawer (front, sides, bottom, handle) in a carcass turned 20°, pulled 12 cm.
fn rotated_drawer() -> HardCase {
    let (w, d, h) = (0.5, 0.5, 0.7);
    let f = Isometry3::new(
        Vector3::new(0.1, 0.0, 0.0),
        Vector3::z() * 20f64.to_radians(),
    );
    let mut statics = carcass(&f, w, d, h);
    // The fixed front below the drawer.
    statics.push(boxed(
        &f,
        [w / 2.0, -T / 2.0, 0.24],
        [w / 2.0 - 0.002, T / 2.0, 0.24],
        0,
    ));
    let (cx, cz, hw, hh) = (w / 2.0, h - 0.11, w / 2.0 - T, 0.09);
    let part = vec![
        boxed(&f, [cx, -T / 2.0, cz], [hw - 0.002, T / 2.0, hh - 0.002], 1),
        boxed(
            &f,
            [T + 0.01, d / 2.0, cz - 0.01],
            [0.006, d / 2.0 - 0.02, hh - 0.03],
            1,
        ),
        boxed(
            &f,
            [w - T - 0.01, d / 2.0, cz - 0.01],
            [0.006, d / 2.0 - 0.02, hh - 0.03],
            1,
        ),
        boxed(
            &f,
            [cx, d / 2.0, cz - hh + 0.03],
            [hw - 0.01, d / 2.0 - 0.02, 0.006],
            1,
        ),
        boxed(&f, [cx, -T - 0.025, cz], [0.08, 0.008, 0.008], 1),
        boxed(&f, [cx - 0.07, -T - 0.0125, cz], [0.006, 0.0125, 0.006], 1),
        boxed(&f, [cx + 0.07, -T - 0.0125, cz], [0.006, 0.0125, 0.006], 1),
    ];
    let contact = f * Point3::new(cx, -T - 0.033, cz);
    HardCase {
        name: "drawer, carcass 20°",
        statics,
        part,
        truth: HardTruth::Prismatic {
            axis: Unit::new_normalize(f.rotation * -Vector3::y()),
            distance: 0.12,
        },
        contact,
        grasp: grasp(&f, contact),
        cameras: cameras(&f, w, h),
        // Out to 5 cm short of its depth.
        limit: d - 0.05,
    }
}

/// The hard cases.
pub fn hard_cases() -> Vec<HardCase> {
    vec![
        small_door("small door 10°", 0.0, 10.0),
        small_door("sagging small door 15°", 4.0, 15.0),
        rotated_drawer(),
        oven_door(),
        sliding_door(),
        partial_view_door(),
    ]
}

/// A standard normal draw.
fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>();
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Clouds at depth noise `sigma` (m) and the path (2 mm / 1°, free roll) of one seed; the
/// contacts have σ/2 noise.
pub fn observe(c: &HardCase, sigma: f64, seed: u64) -> HardObservation {
    observe_to(c, &c.truth, sigma, seed)
}

/// [`observe`] with the part moved by `truth` (the case's own joint, pulled further): the
/// path has 60 poses per the case's own travel, so the same density.
pub fn observe_to(c: &HardCase, truth: &HardTruth, sigma: f64, seed: u64) -> HardObservation {
    let moved = truth.motion(1.0);
    let mut pre_boxes = c.statics.clone();
    pre_boxes.extend(c.part.iter().copied());
    let mut post_boxes = c.statics.clone();
    post_boxes.extend(c.part.iter().map(|b| SyntheticBox {
        world_from_box: moved * b.world_from_box,
        ..*b
    }));
    let noise = |k| DepthNoise {
        sigma,
        outlier_fraction: 0.0,
        seed: seed * 2 + k,
    };
    let pre = render(&pre_boxes, &c.cameras.0, &noise(0), 0.0).expect("valid camera");
    let post = render(&post_boxes, &c.cameras.1, &noise(1), 10.0).expect("valid camera");
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xfa5e);
    let v3 = |s: f64, rng: &mut ChaCha8Rng| Vector3::new(gauss(rng), gauss(rng), gauss(rng)) * s;
    let contact_pre = c.contact + v3(sigma / 2.0, &mut rng);
    let contact_post = moved * c.contact + v3(sigma / 2.0, &mut rng);
    let n = (60.0 * truth.travel() / c.truth.travel()).round().max(2.0) as usize;
    let mut roll = 0.0;
    let ee_poses = (0..n)
        .map(|k| {
            let pose = truth.motion(k as f64 / (n - 1) as f64) * c.grasp;
            roll += 0.5f64.to_radians() * gauss(&mut rng);
            let rolled = pose.rotation * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), roll);
            let tilt = UnitQuaternion::from_scaled_axis(v3(1f64.to_radians(), &mut rng));
            let position = pose.translation.vector + v3(0.002, &mut rng);
            (
                0.05 * k as f64,
                Isometry3::from_parts(position.into(), tilt * rolled),
            )
        })
        .collect();
    HardObservation {
        pre: pre.cloud,
        post: post.cloud,
        contact_pre,
        contact_post,
        ee_poses,
    }
}

/// One seed's kept estimate, the truth it was made at, the further pulls made before it (as
/// discovery's log counts them) and whether it is confident.
pub struct Pulled {
    pub estimate: Estimate,
    pub truth: HardTruth,
    pub pulls: usize,
    pub confident: bool,
}

/// The estimate from the case's own motion: the rule below with no further pull.
pub fn once(
    case: &HardCase,
    est: &dyn ArticulationEstimator,
    s: &DiscoverySettings,
    sigma: f64,
    seed: u64,
) -> Pulled {
    let s = DiscoverySettings {
        max_extra_pulls: 0,
        ..s.clone()
    };
    pull_until_confident(case, est, &s, sigma, seed)
}

/// Discovery's keep-pulling rule (`kinscene::discovery::discover`, step 6) on the case: from
/// its own motion, while the estimate has doubts, the part is short of its limit and fewer
/// than `max_extra_pulls` further pulls were made, the contact moves `extra_pull` further and
/// the estimator sees all the motion so far (the first cloud, the new one, the whole path);
/// the estimate with the least confidence shortfall is kept.
pub fn pull_until_confident(
    case: &HardCase,
    est: &dyn ArticulationEstimator,
    s: &DiscoverySettings,
    sigma: f64,
    seed: u64,
) -> Pulled {
    let mut truth = case.truth;
    let mut best: Option<(f64, Pulled)> = None;
    for pulls in 0..=s.max_extra_pulls {
        let o = observe_to(case, &truth, sigma, seed);
        let estimate = est.estimate(&o.interaction()).expect("valid");
        let confident = s.doubts(&estimate).is_empty();
        let short = s.confidence_shortfall(&estimate);
        if best.as_ref().is_none_or(|b| short < b.0) {
            best = Some((
                short,
                Pulled {
                    estimate,
                    truth,
                    pulls,
                    confident,
                },
            ));
        }
        let further = case.pulled_further(&truth, s.extra_pull);
        if confident || further.travel() <= truth.travel() {
            break;
        }
        truth = further;
    }
    best.expect("at least one round").1
}
