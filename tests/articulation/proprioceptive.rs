//! Proprioceptive model fitting on plain arcs and lines.

use super::*;

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
        let e = proprio(orientation).estimate_poses(&poses).unwrap();
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
    let e = Proprioceptive::default().estimate_poses(&line).unwrap();
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
        let e = proprio(orientation).estimate_poses(&poses).unwrap();
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

/// The poses-only entry point is the trait's rule without clouds: on an arc, the trait call
/// with two empty clouds and the contact at the first pose gives the same estimate; a NaN pose
/// is a typed error naming the pose.
#[test]
fn proprioceptive_needs_only_poses() {
    let axis = Unit::new_normalize(Vector3::new(0.1, 0.1, 1.0));
    let radial = axis.cross(&Vector3::y()).normalize() * 0.4;
    let poses = arc_poses(axis, Point3::new(0.5, 0.0, 0.3), radial, 0.8, 25, 0.003, 4);
    let est = Proprioceptive::default();
    let alone = est.estimate_poses(&poses).unwrap();
    let with_contact = Interaction {
        contact_pre: Point3::from(poses[0].1.translation.vector),
        ..proprio_only(&poses)
    };
    let via_trait = est.estimate(&with_contact).unwrap();
    assert!(
        matches!(alone.joint, JointEstimate::Revolute { .. }),
        "{alone:?}"
    );
    assert_eq!(alone.joint, via_trait.joint);
    assert_eq!(alone.uncertainty, via_trait.uncertainty);
    let mut bad = poses.clone();
    bad[3].1.translation.vector.x = f64::NAN;
    assert_eq!(
        est.estimate_poses(&bad),
        Err(ArticulationError::NonFinite {
            input: InputKind::EePoses,
            what: "pose",
            index: 3
        })
    );
}

/// `n` poses along a smooth path `at(u)`, `u` from 0 to 1 in equal steps, with Gaussian
/// noise of σ `sigma_p` (m) per position axis and `sigma_o` (rad) per axis of the rotation
/// vector (Box–Muller from a seeded generator).
fn noisy_path(
    at: impl Fn(f64) -> Isometry3<f64>,
    n: usize,
    sigma_p: f64,
    sigma_o: f64,
    seed: u64,
) -> Vec<(f64, Isometry3<f64>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut gauss = move || {
        let u1: f64 = rng.random::<f64>().max(1e-300);
        let u2: f64 = rng.random::<f64>();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    };
    (0..n)
        .map(|k| {
            let p = at(k as f64 / (n - 1) as f64);
            let dp = Vector3::new(gauss(), gauss(), gauss()) * sigma_p;
            let dr = Vector3::new(gauss(), gauss(), gauss()) * sigma_o;
            let noisy = Isometry3::from_parts(
                Translation3::from(p.translation.vector + dp),
                UnitQuaternion::from_scaled_axis(dr) * p.rotation,
            );
            (k as f64 * 0.1, noisy)
        })
        .collect()
}

/// The pose noise estimated from the path's smoothness recovers the σ it was drawn with:
/// 40 poses on a 0.3 m arc turning 1.5 rad (1.2 cm apart) and on a 0.8 m line (2.1 cm apart), σ 2 and 5 mm,
/// 1° and 3°, 10 seeds each. Tolerances: the median of 37 correlated χ² samples scatters by
/// about 15 % in σ (measured: worst seed within 30 %), so each seed within 35 % and the mean
/// over the seeds within 10 %; the true path's own third differences (0.3 mm on the arc) are
/// negligible (`s³ / r²` = 0.02 mm).
#[test]
fn path_noise_recovers_the_drawn_sigma() {
    let axis = Unit::new_normalize(Vector3::new(0.1, 0.0, 1.0));
    let pivot = Point3::new(1.0, 0.5, 0.7);
    let radial = axis.cross(&Vector3::y()).normalize() * 0.3;
    let arc = move |u: f64| {
        let turn = UnitQuaternion::from_axis_angle(&axis, 1.5 * u);
        Isometry3::from_parts(Translation3::from(pivot.coords + turn * radial), turn)
    };
    let line = |u: f64| {
        Isometry3::from_parts(
            Translation3::new(0.2 + 0.8 * u, -0.3 * u, 0.6),
            UnitQuaternion::from_euler_angles(0.2, -0.1, 0.4),
        )
    };
    let paths: [&dyn Fn(f64) -> Isometry3<f64>; 2] = [&arc, &line];
    for (which, path) in paths.iter().enumerate() {
        for (sigma_p, sigma_o) in [(0.002, 1f64.to_radians()), (0.005, 3f64.to_radians())] {
            let (mut sum_p, mut sum_o) = (0.0, 0.0);
            for seed in 0..10 {
                let poses = noisy_path(path, 40, sigma_p, sigma_o, 900 + seed);
                let n = path_noise(&poses).expect("enough poses");
                let ctx = format!("path {which} σ {sigma_p}/{sigma_o} seed {seed}: {n:?}");
                assert!((n.position / sigma_p - 1.0).abs() < 0.35, "{ctx}");
                assert!((n.orientation / sigma_o - 1.0).abs() < 0.35, "{ctx}");
                sum_p += n.position;
                sum_o += n.orientation;
            }
            let (mean_p, mean_o) = (sum_p / 10.0, sum_o / 10.0);
            println!("path {which}: σ {sigma_p} → {mean_p:.5}, {sigma_o:.5} → {mean_o:.5}");
            assert!(
                (mean_p / sigma_p - 1.0).abs() < 0.1,
                "{mean_p} vs {sigma_p}"
            );
            assert!(
                (mean_o / sigma_o - 1.0).abs() < 0.1,
                "{mean_o} vs {sigma_o}"
            );
        }
    }
    // Too short a path: no estimate. With `FromPath` the estimator says it used the path's.
    let short = noisy_path(arc, MIN_NOISE_POSES - 1, 0.002, 0.01, 1);
    assert!(path_noise(&short).is_none());
    let from_path = Proprioceptive {
        settings: ProprioceptiveSettings {
            noise: NoiseSource::FromPath,
            ..ProprioceptiveSettings::default()
        },
    };
    let e = from_path
        .estimate_poses(&noisy_path(arc, 30, 0.002, 0.01, 2))
        .unwrap();
    assert!(e.details.contains("noise from the path"), "{}", e.details);
}
