//! The sphere model is conservative on the shipped robots: every configuration the exact parry
//! model finds in collision (self-collision outside the allowed pairs, and the scene), the
//! spheres find in collision too; sampled points of every link's exact shapes lie inside its
//! spheres; and the spheres are not absurdly loose.

use std::path::Path;

use kinscene::kinematics::robot::{
    ArmCheck, ArmCheckData, EdgeScene, Exempt, RobotCollision, RobotConfig, RobotDescription,
    RobotError, RobotModel, RobotSpheres, Sphere, SphereData, SphereObstacles, SphereSettings,
    Srdf,
};
use kinscene::scene::{
    BaseShape, SceneData, SceneModel, SceneModelBuilder, Shape, forward_kinematics,
};
use nalgebra::{DVector, Isometry3, Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::third_party::{example_robot_data, options};

/// Clearance (m) asked of the arm from the scene in these checks, as a planner would.
const MARGIN: f64 = 0.01;

/// The Gen3 as shipped, the Panda with its SRDF, TIAGo from `robots/tiago.toml`.
pub(super) fn robots() -> Vec<(&'static str, RobotModel)> {
    let root = example_robot_data().join("robots/panda_description");
    let panda =
        RobotModel::from_urdf_file_with(&root.join("urdf/panda.urdf"), &options("panda_hand"))
            .unwrap();
    let srdf = Srdf::parse(&std::fs::read_to_string(root.join("srdf/panda.srdf")).unwrap());
    let panda = panda.with_srdf(&srdf.unwrap()).unwrap();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots");
    let description = RobotDescription::from_file(&dir.join("tiago.toml")).unwrap();
    let vars = |name: &str| {
        (name == "EXAMPLE_ROBOT_DATA").then(|| example_robot_data().display().to_string())
    };
    let tiago = RobotModel::from_description(&description, &dir, &vars).unwrap();
    vec![
        ("gen3", RobotModel::kinova_gen3_mobile()),
        ("panda", panda),
        ("tiago", tiago),
    ]
}

/// A random straight motion from a configuration `exact` accepts (at most `tries` drawn):
/// its start, its end a random direction away, and its joint-space length drawn from
/// `lengths`; `None` when no start drawn is accepted.
pub(super) fn motion_from_free(
    robot: &RobotModel,
    rng: &mut ChaCha8Rng,
    exact: &dyn Fn(&[f64]) -> bool,
    lengths: std::ops::RangeInclusive<f64>,
    tries: usize,
) -> Option<(DVector<f64>, DVector<f64>, f64)> {
    for _ in 0..tries {
        let a = random_arm(robot, rng);
        if !exact(a.as_slice()) {
            continue;
        }
        let step = DVector::from_fn(robot.dof(), |_, _| rng.random_range(-1.0..=1.0));
        let length = rng.random_range(lengths);
        let b = &a + step.normalize() * length;
        return Some((a, b, length));
    }
    None
}

/// The documented states of the discrete motion check from `a` to `b` (joint-space length
/// `length`) all pass `exact`: `b` and `a + (j / n)·(b − a)`, `0 < j < n`,
/// `n = ⌈length / resolution⌉`, recomputed here independently of the check.
fn every_state(
    a: &[f64],
    b: &[f64],
    length: f64,
    resolution: f64,
    exact: &dyn Fn(&[f64]) -> bool,
) -> bool {
    let n = (length / resolution).ceil() as usize;
    exact(b)
        && (1..n).all(|j| {
            let t = j as f64 / n as f64;
            let q: Vec<f64> = a.iter().zip(b).map(|(x, y)| x + (y - x) * t).collect();
            exact(&q)
        })
}

/// Whether arm configuration `q` of `robot` (base at the origin) is free in the exact parry
/// model: no self-collision, no scene shape within `margin`.
pub(super) fn exact_free<'a>(
    robot: &'a RobotModel,
    collision: &'a RobotCollision,
    model: &'a SceneModel,
    data: &'a SceneData,
    margin: f64,
) -> impl Fn(&[f64]) -> bool + 'a {
    move |q: &[f64]| {
        let poses = robot
            .link_poses(&RobotConfig {
                base: [0.0; 3],
                arm: DVector::from_column_slice(q),
            })
            .unwrap();
        collision.self_collision(&poses).is_none()
            && collision
                .scene_collision(&poses, model, data, Exempt::Nothing, margin)
                .is_none()
    }
}

/// A floor slab (top at z = 0), a thin shelf, a post, a ball and a tilted box around a robot
/// at the origin, within the arms' reach.
pub(super) fn scene() -> SceneModel {
    scene_builder().build().unwrap()
}

/// The builder of [`scene`], to add to.
pub(super) fn scene_builder() -> SceneModelBuilder {
    let mut b = SceneModelBuilder::new();
    let tilted = Isometry3::new(Vector3::new(-0.65, 0.25, 1.0), Vector3::new(0.3, 0.5, 0.2));
    for (name, shape, pose) in [
        (
            "floor",
            Shape::cuboid(Vector3::new(3.0, 3.0, 0.05)),
            Isometry3::translation(0.0, 0.0, -0.05),
        ),
        (
            "shelf",
            Shape::cuboid(Vector3::new(0.15, 0.4, 0.01)),
            Isometry3::translation(0.55, 0.0, 0.6),
        ),
        (
            "post",
            Shape::cylinder(0.04, 1.6),
            Isometry3::translation(0.1, 0.55, 0.8),
        ),
        (
            "ball",
            Shape::sphere(0.1),
            Isometry3::translation(0.3, -0.45, 1.0),
        ),
        (
            "tilted",
            Shape::cuboid(Vector3::new(0.1, 0.2, 0.05)),
            tilted,
        ),
    ] {
        b.add_base_shape(BaseShape::new(name, shape, pose));
    }
    b
}

/// `model` placed at its zero state.
pub(super) fn zero_data(model: &SceneModel) -> SceneData {
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, &model.zero_state()).unwrap();
    data
}

/// The whole scene of `data`, nothing exempt, with `margin` (m): what an [`ArmCheck`] checks.
pub(super) fn edge_scene<'a>(
    model: &'a SceneModel,
    data: &'a SceneData,
    margin: f64,
) -> EdgeScene<'a> {
    EdgeScene {
        model,
        data,
        exempt: Exempt::Nothing,
        margin,
    }
}

pub(super) fn random_arm(robot: &RobotModel, rng: &mut ChaCha8Rng) -> DVector<f64> {
    let (lo, hi) = robot.arm_bounds();
    DVector::from_fn(robot.dof(), |i, _| {
        let (l, h) = (
            lo[i].max(-std::f64::consts::PI),
            hi[i].min(std::f64::consts::PI),
        );
        rng.random_range(l..=h)
    })
}

/// On 600 seeded random configurations per robot: an exact self-collision at pair `p` means
/// the spheres report a pair at or before `p` (pairs are checked in the same lexicographic
/// order, so the spheres' first hit cannot come later), and the spheres as a broad phase with
/// the exact pair test find exactly the exact model's pair; an exact scene hit at link `l`
/// means the spheres hit at a link `<= l`. Both kinds of exact collision occur (the test is
/// not vacuous). Looseness is reported and loosely bounded: among link pairs whose exact
/// shapes are apart, the spheres flag under 30 % (measured: Gen3 1.1 %, Panda 11.2 %, TIAGo
/// 20.8 %); among configurations exactly clear of the
/// scene, the spheres flag under 50 % (3.9 %, 8.9 %, 24.7 %).
#[test]
fn every_exact_collision_is_a_sphere_collision() {
    let model = scene();
    let data = zero_data(&model);
    let obstacles = SphereObstacles::new(&model, &data, Exempt::Nothing, MARGIN);
    assert_eq!(obstacles.len(), 5);
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
        let mut sphere_data = SphereData::default();
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        let (mut self_hits, mut scene_hits) = (0, 0);
        let (mut pairs_apart, mut pairs_flagged) = (0, 0);
        let (mut scene_free, mut scene_flagged) = (0, 0);
        for _ in 0..600 {
            let config = RobotConfig {
                base: [0.0; 3],
                arm: random_arm(&robot, &mut rng),
            };
            let poses = robot.link_poses(&config).unwrap();
            spheres.place(&poses, &mut sphere_data);
            let exact_self = collision.self_collision(&poses);
            let sphere_self = spheres.self_collision(&sphere_data);
            if let Some(pair) = exact_self {
                self_hits += 1;
                assert!(
                    sphere_self.is_some_and(|s| s <= pair),
                    "{name}: exact {pair:?}, spheres {sphere_self:?} at {:?}",
                    config.arm
                );
            }
            assert_eq!(
                spheres.self_collision_exact(&sphere_data, &collision, &poses),
                exact_self,
                "{name} at {:?}",
                config.arm
            );
            for &(i, j) in spheres.checked_pairs() {
                if !collision.pair_touches(&poses, i, j) {
                    pairs_apart += 1;
                    pairs_flagged += usize::from(spheres.pair_meets(&sphere_data, i, j));
                }
            }
            let exact_scene =
                collision.scene_collision(&poses, &model, &data, Exempt::Nothing, MARGIN);
            let sphere_scene = obstacles.first_hit(&sphere_data);
            match exact_scene {
                Some((link, _)) => {
                    scene_hits += 1;
                    assert!(
                        sphere_scene.is_some_and(|l| l <= link),
                        "{name}: exact link {link}, spheres {sphere_scene:?} at {:?}",
                        config.arm
                    );
                }
                None => {
                    scene_free += 1;
                    scene_flagged += usize::from(sphere_scene.is_some());
                }
            }
        }
        let pair_rate = pairs_flagged as f64 / pairs_apart.max(1) as f64;
        let scene_rate = scene_flagged as f64 / scene_free.max(1) as f64;
        println!(
            "{name}: {} spheres, {self_hits} self and {scene_hits} scene collisions in 600; \
             spheres flag {pairs_flagged}/{pairs_apart} = {:.1} % of the pairs apart and \
             {scene_flagged}/{scene_free} = {:.1} % of the scene-free configurations",
            spheres.count(),
            100.0 * pair_rate,
            100.0 * scene_rate
        );
        assert!(self_hits > 0 && scene_hits > 0 && scene_free > 0, "{name}");
        assert!(pair_rate < 0.3, "{name}: {pair_rate}");
        assert!(scene_rate < 0.5, "{name}: {scene_rate}");
    }
}

/// Points of the exact shapes, sampled independently of the covering code: for primitives,
/// a parametrisation of their surface (and the centre); for a convex hull, its vertices (its
/// extreme points) and random convex combinations of four of them.
fn shape_points(shape: &Shape, rng: &mut ChaCha8Rng) -> Vec<Point3<f64>> {
    let unit = |rng: &mut ChaCha8Rng| {
        let z: f64 = rng.random_range(-1.0..=1.0);
        let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let s = (1.0 - z * z).sqrt();
        Vector3::new(s * a.cos(), s * a.sin(), z)
    };
    // The centre of a primitive (a mesh's frame origin need not lie in its hull).
    let mut points = vec![];
    if !matches!(shape, Shape::ConvexMesh { .. }) {
        points.push(Point3::origin());
    }
    match shape {
        Shape::Cuboid { half_extents: h } => {
            for _ in 0..200 {
                let mut p = Vector3::from_fn(|i, _| rng.random_range(-h[i]..=h[i]));
                let face = rng.random_range(0..3);
                p[face] = if rng.random_bool(0.5) {
                    h[face]
                } else {
                    -h[face]
                };
                points.push(p.into());
            }
            for k in 0..8 {
                let s = |b: usize| if k & (1 << b) == 0 { -1.0 } else { 1.0 };
                points.push(Point3::new(s(0) * h.x, s(1) * h.y, s(2) * h.z));
            }
        }
        Shape::Sphere { radius } => {
            points.extend((0..200).map(|_| Point3::from(unit(rng) * *radius)));
        }
        Shape::Cylinder { radius, length } | Shape::Capsule { radius, length } => {
            let capsule = matches!(shape, Shape::Capsule { .. });
            for _ in 0..200 {
                let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                let z = rng.random_range(-length / 2.0..=length / 2.0);
                points.push(Point3::new(radius * a.cos(), radius * a.sin(), z));
                let end = if rng.random_bool(0.5) { 0.5 } else { -0.5 } * length;
                let cap = if capsule {
                    let mut u = unit(rng) * *radius;
                    u.z = u.z.abs() * end.signum();
                    u
                } else {
                    let r = radius * rng.random::<f64>().sqrt();
                    Vector3::new(r * a.cos(), r * a.sin(), 0.0)
                };
                points.push(Point3::new(cap.x, cap.y, end + cap.z));
            }
        }
        Shape::ConvexMesh { vertices, .. } => {
            points.extend(vertices.iter().copied());
            for _ in 0..200 {
                let w: [f64; 4] = std::array::from_fn(|_| rng.random::<f64>());
                let total: f64 = w.iter().sum();
                let p = w.iter().fold(Vector3::zeros(), |acc, wi| {
                    acc + vertices[rng.random_range(0..vertices.len())].coords * (wi / total)
                });
                points.push(p.into());
            }
        }
        other => panic!("a shape kind this test does not sample: {other:?}"),
    }
    points
}

/// Every sampled point of every link's exact shapes (link frame) lies inside one of the link's
/// spheres, for small and default budgets without padding; a link with no more shapes than
/// the budget gets at most the budget. Tolerance 1e-9 m (round-off of the transforms).
#[test]
fn sampled_points_of_every_link_lie_in_its_spheres() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        for max_per_link in [1, 4, 12] {
            let settings = SphereSettings {
                padding: 0.0,
                max_per_link,
            };
            let spheres = RobotSpheres::new(&robot, &collision, &settings).unwrap();
            for (link, covering) in robot.links().iter().zip(spheres.links()) {
                if link.colliders.len() <= max_per_link {
                    assert!(covering.len() <= max_per_link, "{name} {}", link.name);
                }
                for collider in &link.colliders {
                    for p in shape_points(&collider.shape, &mut rng) {
                        let q = collider.part_from_shape * p;
                        assert!(
                            covering.iter().any(|s: &Sphere| s.contains(&q, 1e-9)),
                            "{name} {} budget {max_per_link}: {q} uncovered",
                            link.name
                        );
                    }
                }
            }
        }
    }
}

/// Padding grows every radius by exactly its value; bad settings are typed errors.
#[test]
fn padding_grows_radii_and_bad_settings_are_errors() {
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let plain = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
    let padded = SphereSettings {
        padding: 0.02,
        ..SphereSettings::default()
    };
    let padded = RobotSpheres::new(&robot, &collision, &padded).unwrap();
    for (a, b) in plain
        .links()
        .iter()
        .flatten()
        .zip(padded.links().iter().flatten())
    {
        assert_eq!(a.center, b.center);
        assert!((b.radius - a.radius - 0.02).abs() < 1e-12);
    }
    for settings in [
        SphereSettings {
            padding: f64::NAN,
            ..SphereSettings::default()
        },
        SphereSettings {
            padding: -0.01,
            ..SphereSettings::default()
        },
        SphereSettings {
            max_per_link: 0,
            ..SphereSettings::default()
        },
    ] {
        assert!(matches!(
            RobotSpheres::new(&robot, &collision, &settings),
            Err(RobotError::InvalidSetting(_))
        ));
    }
}

/// [`ArmCheck`] gives the exact check's answer: on 600 seeded random configurations per robot
/// (base at the origin, the scene above with [`MARGIN`]), `is_valid` equals "no exact
/// self-collision and no exact scene collision" of [`RobotCollision`], with per-thread and
/// with caller-owned scratch; both answers occur. A configuration of the wrong length or with
/// NaN is invalid.
#[test]
fn arm_check_gives_the_exact_answer() {
    let model = scene();
    let data = zero_data(&model);
    let edge_scene = edge_scene(&model, &data, MARGIN);
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
        let check = ArmCheck::new(&robot, &collision, &spheres, edge_scene, [0.0; 3]).unwrap();
        let mut scratch = ArmCheckData::default();
        let mut rng = ChaCha8Rng::seed_from_u64(31);
        let (mut free, mut blocked) = (0, 0);
        for _ in 0..600 {
            let arm = random_arm(&robot, &mut rng);
            let poses = robot
                .link_poses(&RobotConfig {
                    base: [0.0; 3],
                    arm: arm.clone(),
                })
                .unwrap();
            let exact = collision.self_collision(&poses).is_none()
                && collision
                    .scene_collision(&poses, &model, &data, Exempt::Nothing, MARGIN)
                    .is_none();
            assert_eq!(check.is_valid(arm.as_slice()), exact, "{name} at {arm:?}");
            assert_eq!(
                check.is_valid_with(arm.as_slice(), &mut scratch),
                exact,
                "{name} at {arm:?}"
            );
            if exact {
                free += 1;
            } else {
                blocked += 1;
            }
        }
        println!("{name}: ArmCheck agrees on {free} free and {blocked} blocked configurations");
        assert!(free > 0 && blocked > 0, "{name}");
        let neutral = robot.neutral();
        assert!(!check.is_valid(&neutral.as_slice()[1..]), "{name}");
        let mut nan = neutral.as_slice().to_vec();
        nan[0] = f64::NAN;
        assert!(!check.is_valid(&nan), "{name}");
    }
}

/// [`ArmCheck::check_motion`] accepts a straight motion exactly when the exact check accepts
/// every state it is documented to visit: `b` and `a + (j / n)·(b − a)`, `0 < j < n`,
/// `n = ⌈‖b − a‖ / resolution⌉`, recomputed here independently. 300 seeded motions per robot
/// from a free configuration, of joint-space length up to 0.8 rad, resolution 0.01; both
/// verdicts occur. Bad input is rejected.
#[test]
fn arm_motion_check_matches_the_exact_check_of_its_states() {
    const RESOLUTION: f64 = 0.01;
    let model = scene();
    let data = zero_data(&model);
    let edge_scene = edge_scene(&model, &data, MARGIN);
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
        let check = ArmCheck::new(&robot, &collision, &spheres, edge_scene, [0.0; 3])
            .unwrap()
            .with_continuous(false);
        let exact = exact_free(&robot, &collision, &model, &data, MARGIN);
        let mut rng = ChaCha8Rng::seed_from_u64(37);
        let (mut accepted, mut rejected) = (0, 0);
        while accepted + rejected < 300 {
            let Some((a, b, length)) = motion_from_free(&robot, &mut rng, &exact, 0.05..=0.8, 1)
            else {
                continue;
            };
            let expected = every_state(a.as_slice(), b.as_slice(), length, RESOLUTION, &exact);
            let got = check.check_motion(a.as_slice(), b.as_slice(), RESOLUTION);
            assert_eq!(got, expected, "{name}: {a:?} -> {b:?}");
            if got {
                accepted += 1;
            } else {
                rejected += 1;
            }
        }
        println!("{name}: check_motion agrees on {accepted} free and {rejected} blocked motions");
        assert!(accepted > 0 && rejected > 0, "{name}");
        let a = robot.neutral();
        for resolution in [0.0, -1.0, f64::NAN] {
            assert!(!check.check_motion(a.as_slice(), a.as_slice(), resolution));
        }
        assert!(!check.check_motion(&a.as_slice()[1..], &a.as_slice()[1..], RESOLUTION));
    }
}

/// The certified spans of [`ArmCheck::check_motion`] (states near a free state skipped) keep
/// its answer: on 120 seeded long motions per robot (joint-space length 0.3 to 3 rad, from a
/// free configuration, resolution 0.02, so up to 150 states each) the default check, the
/// check with [`ArmCheck::with_spans`] off, and the exact check of every documented state
/// (`b` and `a + (j / n)·(b − a)`, recomputed here) agree; both verdicts occur. The default
/// check runs with caller-owned scratch that a planner-like sequence shares (the end state
/// asked first, an unrelated configuration asked in between), so a state reused from the
/// scratch is the one asked.
#[test]
fn arm_motion_spans_keep_the_exact_answer() {
    const RESOLUTION: f64 = 0.02;
    let model = scene();
    let data = zero_data(&model);
    let edge_scene = edge_scene(&model, &data, MARGIN);
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
        let check = ArmCheck::new(&robot, &collision, &spheres, edge_scene, [0.0; 3])
            .unwrap()
            .with_continuous(false);
        let dense = ArmCheck::new(&robot, &collision, &spheres, edge_scene, [0.0; 3])
            .unwrap()
            .with_continuous(false)
            .with_spans(false);
        let exact = exact_free(&robot, &collision, &model, &data, MARGIN);
        let mut scratch = ArmCheckData::default();
        let mut rng = ChaCha8Rng::seed_from_u64(41);
        let (mut accepted, mut rejected) = (0, 0);
        while accepted + rejected < 120 {
            let Some((a, b, length)) = motion_from_free(&robot, &mut rng, &exact, 0.3..=3.0, 1)
            else {
                continue;
            };
            let expected = every_state(a.as_slice(), b.as_slice(), length, RESOLUTION, &exact);
            let other = random_arm(&robot, &mut rng);
            let _ = check.is_valid_with(other.as_slice(), &mut scratch);
            let end = check.is_valid_with(b.as_slice(), &mut scratch);
            assert_eq!(end, exact(b.as_slice()), "{name}: {b:?}");
            let got = check.check_motion_with(a.as_slice(), b.as_slice(), RESOLUTION, &mut scratch);
            assert_eq!(got, expected, "{name}: {a:?} -> {b:?}");
            assert_eq!(
                dense.check_motion(a.as_slice(), b.as_slice(), RESOLUTION),
                expected,
                "{name}: {a:?} -> {b:?} without spans"
            );
            if got {
                accepted += 1;
            } else {
                rejected += 1;
            }
        }
        println!("{name}: spans keep the answer on {accepted} free and {rejected} blocked motions");
        assert!(accepted > 0 && rejected > 0, "{name}");
    }
}

/// [`ArmCheck::with_self_margin`] gives the exact answer with that clearance between the
/// robot's links: on 400 seeded configurations per robot, `is_valid` equals "no pair within
/// 1 cm" ([`RobotCollision::self_collision_within`]) and no exact scene collision; on up to
/// 100 seeded motions per robot (0.3 to 2 rad, resolution 0.02, from a configuration valid
/// under the clearance) `check_motion`, with its spans, equals that check at every documented state
/// (recomputed here). Not vacuous: some configurations are free of contact but within the
/// clearance (the margin decides them), and both motion verdicts occur on the Gen3 and the
/// Panda (no TIAGo configuration drawn keeps 1 cm between all its checked links).
#[test]
fn arm_check_with_a_self_margin_gives_the_exact_answer() {
    const SELF: f64 = 0.01;
    const RESOLUTION: f64 = 0.02;
    let model = scene();
    let data = zero_data(&model);
    let edge_scene = edge_scene(&model, &data, MARGIN);
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
        let check = ArmCheck::new(&robot, &collision, &spheres, edge_scene, [0.0; 3])
            .unwrap()
            .with_continuous(false)
            .with_self_margin(SELF);
        let poses = |q: &[f64]| {
            robot
                .link_poses(&RobotConfig {
                    base: [0.0; 3],
                    arm: DVector::from_column_slice(q),
                })
                .unwrap()
        };
        let scene_free = |q: &[f64]| {
            collision
                .scene_collision(&poses(q), &model, &data, Exempt::Nothing, MARGIN)
                .is_none()
        };
        let exact =
            |q: &[f64]| collision.self_collision_within(&poses(q), SELF).is_none() && scene_free(q);
        let mut rng = ChaCha8Rng::seed_from_u64(43);
        let mut decided_by_margin = 0;
        for _ in 0..400 {
            let q = random_arm(&robot, &mut rng);
            let expected = exact(q.as_slice());
            assert_eq!(check.is_valid(q.as_slice()), expected, "{name} at {q:?}");
            let touching = collision.self_collision(&poses(q.as_slice())).is_some();
            if !expected && !touching && scene_free(q.as_slice()) {
                decided_by_margin += 1;
            }
        }
        assert!(decided_by_margin > 0, "{name}");
        let (mut accepted, mut rejected) = (0, 0);
        // Starts drawn until 100 motions (a robot whose links sit close together has few
        // configurations clear by the margin).
        while accepted + rejected < 100 {
            let Some((a, b, length)) =
                motion_from_free(&robot, &mut rng, &exact, 0.3..=2.0, 20_000)
            else {
                break;
            };
            let expected = every_state(a.as_slice(), b.as_slice(), length, RESOLUTION, &exact);
            let got = check.check_motion(a.as_slice(), b.as_slice(), RESOLUTION);
            assert_eq!(got, expected, "{name}: {a:?} -> {b:?}");
            if got {
                accepted += 1;
            } else {
                rejected += 1;
            }
        }
        println!(
            "{name}: with a {SELF} m self margin, {decided_by_margin} configurations decided by \
             the margin; motions {accepted} free, {rejected} blocked"
        );
        // TIAGo's links sit within 1 cm of each other in every configuration drawn (the
        // planner caps the clearance by a phase's ends for this reason): no motion starts.
        if name != "tiago" {
            assert!(accepted > 0 && rejected > 0, "{name}");
        }
    }
}

/// [`RobotSpheres::pair_distance_bound`] (the distance tables of pairs one or two joints
/// apart) never exceeds the exact distance: on 3000 seeded random configurations per robot
/// (joints within their limits, continuous ones over one turn and beyond it, so that the
/// tables' wrapping is exercised), for every checked pair, the bound is at most parry's
/// distance (`pair_distance`, which is `<= 0` for touching pairs, so a touching pair is never
/// certified apart). Not vacuous: the Panda's `link5`–`link7` pair has a table, and its bound
/// is positive (certifies the pair apart) on most of the configurations, and on over a
/// quarter of them where its spheres meet (the table decides what the spheres cannot).
#[test]
fn pair_distance_tables_bound_the_exact_distance() {
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        let (mut tabled, mut certified, mut spheres_meet, mut samples) = (0, 0, 0, 0);
        let panda_pair = spheres.checked_pairs().iter().position(|&(i, k)| {
            robot.links()[i].name == "panda_link5" && robot.links()[k].name == "panda_link7"
        });
        let mut placed = SphereData::default();
        for _ in 0..3000 {
            let mut q = random_arm(&robot, &mut rng);
            // Continuous joints: also values beyond one turn.
            for (v, joint) in q.iter_mut().zip(robot.arm_joints()) {
                if !joint.lower.is_finite() && rng.random_bool(0.3) {
                    *v += 2.0 * std::f64::consts::PI * f64::from(rng.random_range(-2..=2));
                }
            }
            let poses = robot
                .link_poses(&RobotConfig {
                    base: [0.0; 3],
                    arm: q.clone(),
                })
                .unwrap();
            spheres.place(&poses, &mut placed);
            samples += 1;
            for (p, &(i, k)) in spheres.checked_pairs().iter().enumerate() {
                let bound = spheres.pair_distance_bound(p, q.as_slice());
                if bound == f64::NEG_INFINITY {
                    continue;
                }
                tabled += 1;
                let exact = collision.pair_distance(&poses, i, k);
                assert!(
                    bound <= exact + 1e-9,
                    "{name} pair ({i}, {k}) at {q:?}: bound {bound} above the exact {exact}"
                );
                if Some(p) == panda_pair {
                    certified += usize::from(bound > 0.0);
                    spheres_meet += usize::from(bound > 0.0 && spheres.pair_meets(&placed, i, k));
                }
            }
        }
        println!(
            "{name}: {tabled} table bounds checked; link5-link7 certified apart on {certified} \
             of {samples} ({spheres_meet} of them with its spheres meeting)"
        );
        if name == "panda" {
            assert!(panda_pair.is_some(), "the Panda checks link5-link7");
            assert!(certified > samples / 2, "panda: {certified} of {samples}");
            assert!(
                spheres_meet > samples / 4,
                "panda: {spheres_meet} of {samples}"
            );
        }
    }
}

/// The exact distances the checks compute ([`RobotCollision::pair_distance`] between links,
/// [`RobotCollision::link_scene_distance`] to the scene) are parry's `query::distance` over
/// the shape pairs, bit for bit, two boxes excepted, which are parry's GJK (the crate finds a
/// hull's support points by walking its edges rather than parry's scan of every vertex; the
/// answer must not change by a single bit): on
/// 200 seeded configurations per robot, every link pair and every arm link against the test
/// scene, the crate's value equals the least of parry's own distances of the shapes, placed as
/// the crate places them. Not vacuous: most link pairs of the Panda and TIAGo are mesh hulls.
#[test]
fn exact_distances_are_parrys_bit_for_bit() {
    use kinscene::scene::collision::parry::math::{Pose, Rotation, Vector};
    use kinscene::scene::collision::{parry, parry_shape};

    let pose = |iso: &Isometry3<f64>| {
        let (t, q) = (iso.translation.vector, iso.rotation.quaternion());
        Pose::from_parts(
            Vector::new(t.x, t.y, t.z),
            Rotation::from_xyzw(q.i, q.j, q.k, q.w),
        )
    };
    let model = scene();
    let data = zero_data(&model);
    // The scene's base shapes in the world, as parry shapes.
    let obstacles: Vec<_> = model
        .base()
        .shapes
        .iter()
        .map(|b| {
            let (shape, shape_from_parry) = parry_shape(&b.shape).unwrap();
            let world = Isometry3::identity() * (b.world_from_shape * shape_from_parry);
            (shape, pose(&world))
        })
        .collect();
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        let compiled: Vec<Vec<_>> = robot
            .links()
            .iter()
            .map(|l| {
                l.colliders
                    .iter()
                    .map(|c| (parry_shape(&c.shape).unwrap(), c.part_from_shape))
                    .collect()
            })
            .collect();
        let mut rng = ChaCha8Rng::seed_from_u64(43);
        let (mut pairs, mut hull_pairs) = (0, 0);
        for _ in 0..200 {
            let arm = random_arm(&robot, &mut rng);
            let poses = robot
                .link_poses(&RobotConfig {
                    base: [0.0; 3],
                    arm,
                })
                .unwrap();
            let placed: Vec<Vec<_>> = compiled
                .iter()
                .zip(&poses)
                .map(|(shapes, world_from_link)| {
                    shapes
                        .iter()
                        .map(|((shape, shape_from_parry), part_from_shape)| {
                            let iso = world_from_link * (part_from_shape * shape_from_parry);
                            (shape, pose(&iso))
                        })
                        .collect()
                })
                .collect();
            // `skip(x, y)`: collider pair exempt (the SRDF disables the pair of URDF links
            // they come from, `RobotModel::exempt_colliders`).
            let parrys = |a: &[(&parry::shape::SharedShape, Pose)],
                          b: &[(&parry::shape::SharedShape, Pose)],
                          skip: &dyn Fn(usize, usize) -> bool| {
                let mut least = f64::INFINITY;
                for (x, (sa, pa)) in a.iter().enumerate() {
                    for (y, (sb, pb)) in b.iter().enumerate() {
                        if skip(x, y) {
                            continue;
                        }
                        // Two boxes: parry's GJK, not its box–box distance (wrong near
                        // contact; see `Placed::distance`).
                        let d = match (sa.as_cuboid(), sb.as_cuboid()) {
                            (Some(ca), Some(cb)) => {
                                parry::query::details::distance_support_map_support_map(
                                    &pa.inv_mul(pb),
                                    ca,
                                    cb,
                                )
                            }
                            _ => {
                                parry::query::distance(pa, &***sa, pb, &***sb)
                                    .unwrap()
                                    .distance
                            }
                        };
                        least = least.min(d.max(0.0));
                    }
                }
                least
            };
            let hull = |l: &[(&parry::shape::SharedShape, Pose)]| {
                l.iter().any(|(s, _)| s.as_convex_polyhedron().is_some())
            };
            for i in 0..placed.len() {
                for j in i + 1..placed.len() {
                    if placed[i].is_empty() || placed[j].is_empty() {
                        continue;
                    }
                    let exempt = robot
                        .exempt_colliders()
                        .iter()
                        .find(|e| (e.link1, e.link2) == (i, j));
                    let skip =
                        |x: usize, y: usize| exempt.is_some_and(|e| e.colliders.contains(&(x, y)));
                    let expected = parrys(&placed[i], &placed[j], &skip);
                    let got = collision.pair_distance(&poses, i, j);
                    assert_eq!(
                        got.to_bits(),
                        expected.to_bits(),
                        "{name} links ({i}, {j}): {got} against parry's {expected}"
                    );
                    pairs += 1;
                    hull_pairs += usize::from(hull(&placed[i]) && hull(&placed[j]));
                }
            }
            let scene: Vec<_> = obstacles.iter().map(|(s, p)| (s, *p)).collect();
            for (l, link) in placed.iter().enumerate().skip(1) {
                if link.is_empty() {
                    continue;
                }
                let expected = parrys(link, &scene, &|_, _| false);
                let got = collision.link_scene_distance(&poses, l, &model, &data, Exempt::Nothing);
                assert_eq!(
                    got.to_bits(),
                    expected.to_bits(),
                    "{name} link {l} to the scene: {got} against parry's {expected}"
                );
            }
        }
        println!("{name}: {pairs} link pair distances, {hull_pairs} between hulls, bit for bit");
        if name != "gen3" {
            assert!(hull_pairs > pairs / 2, "{name}: {hull_pairs} of {pairs}");
        }
    }
}

/// Two [`ArmCheck`]s used one after the other on the same thread (as a planner does: one per
/// phase, base pose and scene state) answer each for its own scene: a configuration and a
/// motion free at one base pose but blocked at another (found by the exact check at both, on
/// seeded random configurations of the Gen3) get each check's own answer, in either order,
/// through the per-thread scratch and through one caller-owned scratch.
#[test]
fn checks_on_one_thread_answer_each_for_its_own_scene() {
    let model = scene();
    let data = zero_data(&model);
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
    let bases = [[0.0, 0.0, 0.0], [0.25, 0.1, 0.4]];
    let exact = |base: [f64; 3], q: &[f64]| {
        let poses = robot
            .link_poses(&RobotConfig {
                base,
                arm: DVector::from_column_slice(q),
            })
            .unwrap();
        collision.self_collision(&poses).is_none()
            && collision
                .scene_collision(&poses, &model, &data, Exempt::Nothing, MARGIN)
                .is_none()
    };
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let mut found = 0;
    for _ in 0..2000 {
        let Some((a, b, _)) =
            motion_from_free(&robot, &mut rng, &|q| exact(bases[0], q), 0.05..=0.3, 50)
        else {
            continue;
        };
        // Free at the first base pose (end state and motion), blocked at the second at `a`.
        if !exact(bases[0], b.as_slice()) || exact(bases[1], a.as_slice()) {
            continue;
        }
        let checks = bases.map(|base| {
            ArmCheck::new(
                &robot,
                &collision,
                &spheres,
                edge_scene(&model, &data, MARGIN),
                base,
            )
            .unwrap()
        });
        if !checks[0].check_motion(a.as_slice(), b.as_slice(), 0.01) {
            continue;
        }
        found += 1;
        let mut scratch = ArmCheckData::default();
        for order in [[0, 1], [1, 0], [0, 1]] {
            for k in order {
                let free = k == 0;
                assert_eq!(checks[k].is_valid(a.as_slice()), free, "check {k} at {a:?}");
                assert_eq!(
                    checks[k].is_valid_with(a.as_slice(), &mut scratch),
                    free,
                    "check {k} at {a:?}"
                );
            }
            for k in order {
                let free = k == 0;
                assert_eq!(
                    checks[k].check_motion(b.as_slice(), a.as_slice(), 0.01),
                    free,
                    "check {k} from {b:?}"
                );
                assert_eq!(
                    checks[k].check_motion_with(b.as_slice(), a.as_slice(), 0.01, &mut scratch),
                    free,
                    "check {k} from {b:?}"
                );
            }
        }
        if found == 5 {
            break;
        }
    }
    assert!(
        found >= 3,
        "{found} configurations free at one base pose only"
    );
}
