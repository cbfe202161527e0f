//! The robot's speed bounds (`SpeedBound`) and the continuous contact walk (`ContactWalk`),
//! against exact distances sampled densely.

use kinscene::kinematics::robot::{
    ContactWalk, Exempt, RobotCollision, RobotConfig, RobotModel, WalkBase, WalkOutcome,
};
use kinscene::scene::{
    BaseShape, SceneData, SceneModel, SceneModelBuilder, Shape, State, forward_kinematics,
};
use nalgebra::{DVector, Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::spheres::{random_arm, robots, scene};

fn poses(robot: &RobotModel, q: &DVector<f64>) -> Vec<Isometry3<f64>> {
    poses_at(robot, [0.0; 3], q)
}

fn poses_at(robot: &RobotModel, base: [f64; 3], q: &DVector<f64>) -> Vec<Isometry3<f64>> {
    robot
        .link_poses(&RobotConfig {
            base,
            arm: q.clone(),
        })
        .unwrap()
}

fn data_of(model: &SceneModel) -> SceneData {
    let mut data = SceneData::new(model);
    forward_kinematics(model, &mut data, &State::from_slice(model, &[]).unwrap()).unwrap();
    data
}

/// Along straight motions `a + t·(b − a)`, `t ∈ [0, 1]`, of the Gen3, the Panda and TIAGo
/// among the shelf, post, ball and tilted box of the sphere tests, every link's exact
/// distance to the scene and every checked pair's exact distance change between samples
/// `1/200` apart by no more than the bound's speed times that (joint speeds `|b − a|`):
/// parry's distances, sampled, against the levers, derived from the joint geometry. First
/// with the base still, then with the base moving too, straight from `[0, 0, 0]` to a
/// random pose within 0.5 m and 1 rad (a link's speed gains `|Δxy| + |Δyaw|·ρ_l`, `ρ_l` its
/// `link_radius`; the pairs' distances do not depend on the base).
#[test]
fn distances_change_no_faster_than_the_motion_bound() {
    use rand::Rng;
    let model = scene();
    let data = data_of(&model);
    let n = 200;
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        let bound = collision.speed_bound(&robot);
        let pairs: Vec<(usize, usize)> = bound.pairs().collect();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for moving in [false, true] {
            let mut worst: f64 = 0.0;
            for _ in 0..10 {
                let (a, b) = (random_arm(&robot, &mut rng), random_arm(&robot, &mut rng));
                let end = if moving {
                    [
                        rng.random_range(-0.5..0.5),
                        rng.random_range(-0.5..0.5),
                        rng.random_range(-1.0..1.0),
                    ]
                } else {
                    [0.0; 3]
                };
                let v: Vec<f64> = (&b - &a).iter().copied().collect();
                let distances = |t: f64| -> Vec<f64> {
                    let base = end.map(|e| e * t);
                    let p = poses_at(&robot, base, &(&a + (&b - &a) * t));
                    (0..robot.links().len())
                        .map(|l| {
                            collision.link_scene_distance(&p, l, &model, &data, Exempt::Nothing)
                        })
                        .chain(
                            pairs
                                .iter()
                                .map(|&(i, j)| collision.pair_distance(&p, i, j)),
                        )
                        .collect()
                };
                let planar = end[0].hypot(end[1]);
                let speed: Vec<f64> = (0..robot.links().len())
                    .map(|l| bound.link_speed(l, &v) + planar + end[2].abs() * bound.link_radius(l))
                    .chain((0..pairs.len()).map(|p| bound.pair_speed(p, &v)))
                    .collect();
                let mut before = distances(0.0);
                for i in 1..=n {
                    let now = distances(i as f64 / n as f64);
                    for k in 0..now.len() {
                        if !(before[k].is_finite() && now[k].is_finite()) {
                            continue;
                        }
                        let change = (now[k] - before[k]).abs();
                        let allowed = speed[k] / n as f64;
                        assert!(
                            change <= allowed + 1e-9,
                            "{name} (base moving: {moving}): item {k} changed {change} in \
                             1/{n}, bound {allowed}"
                        );
                        if allowed > 0.0 {
                            worst = worst.max(change / allowed);
                        }
                    }
                    before = now;
                }
            }
            // How much of the bound the sampled changes use (printed: a bound is only useful
            // when it is not far above what happens).
            eprintln!("{name} (base moving: {moving}): largest change / bound {worst:.3}");
        }
    }
}

/// A plate 0.5 mm thick across the sweep of the Gen3's wrist (its first joint turning
/// 0.8 rad in 1 s, the rest of the arm reaching out): the walk stops at or before the first
/// contact that dense sampling (every 0.1 ms, parry at margin 0) finds, and not long before
/// it; on the motion up to 10 ms before that contact it certifies the arm free.
#[test]
fn the_walk_stops_at_a_thin_plate_across_the_sweep() {
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let bound = collision.speed_bound(&robot);
    let dof = robot.dof();
    // An outstretched, self-clear posture: the wrist 0.45 m or more off the first joint's
    // axis, at least 1 cm between checked links all along the sweep.
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let wrist = dof - 1;
    let (start, end) = loop {
        let c = random_arm(&robot, &mut rng);
        let (mut a, mut b) = (c.clone(), c.clone());
        a[0] = c[0] - 0.4;
        b[0] = c[0] + 0.4;
        let clear = (0..=20).all(|i| {
            let q = &a + (&b - &a) * (i as f64 / 20.0);
            let p = poses(&robot, &q);
            collision.self_clearance(&p, 0.01) >= 0.01
                && p[wrist].translation.vector.xy().norm() >= 0.45
                && p.iter().skip(1).all(|x| x.translation.z > 0.1)
        });
        if clear {
            break (a, b);
        }
    };
    let at = |t: f64| -> DVector<f64> { &start + (&end - &start) * t };
    // The plate: centred on the wrist link's origin at t = 0.53, its thin side along the
    // origin's motion there.
    let p0 = poses(&robot, &at(0.53))[wrist].translation.vector;
    let p1 = poses(&robot, &at(0.531))[wrist].translation.vector;
    let along = (p1 - p0).normalize();
    let plate = Isometry3::from_parts(
        Translation3::from(p0),
        UnitQuaternion::rotation_between(&Vector3::z(), &along).unwrap(),
    );
    let mut builder = SceneModelBuilder::new();
    builder.add_base_shape(BaseShape::new(
        "plate",
        Shape::cuboid(Vector3::new(0.03, 0.03, 0.00025)),
        plate,
    ));
    let model = builder.build().unwrap();
    let data = data_of(&model);
    // Dense sampling: the first contact.
    let touches = |t: f64| {
        collision
            .scene_collision(&poses(&robot, &at(t)), &model, &data, Exempt::Nothing, 0.0)
            .is_some()
    };
    let first = first_sampled(&touches, "the plate is across the sweep");
    let speed = vec![0.8; dof];
    let walk = ContactWalk {
        robot: &robot,
        collision: &collision,
        bound: &bound,
        model: &model,
        data: &data,
        exempt: Exempt::Nothing,
        base: WalkBase::Still([0.0; 3]),
        joint_speed: &speed,
        max_steps: 1_000_000,
        scene_at: None,
        scene_speed: 0.0,
    };
    let trajectory = |t: f64| at(t).iter().copied().collect::<Vec<f64>>();
    assert_stops_at(&walk, &trajectory, first);
    let before = first - 0.01;
    assert!((0..=1000).all(|i| !touches(before * i as f64 / 1000.0)));
}

/// The Gen3 stowed and still, a door slab 0.5 mm thick and 0.4 m wide on a vertical hinge
/// 0.55 m in front of it, turning π rad in 1 s through the robot (`scene_at`; its points move
/// at most π · 0.4 m/s, the `scene_speed`): the walk stops at or before the first contact
/// dense sampling finds (every 0.1 ms, parry at margin 0), not long before, and certifies the
/// motion up to 10 ms before it.
#[test]
fn the_walk_stops_at_a_thin_door_turning_into_the_robot() {
    use kinscene::scene::{Joint, Limits, PartSpec};
    use nalgebra::Point3;
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let bound = collision.speed_bound(&robot);
    let mut builder = SceneModelBuilder::new();
    builder.add_part(
        PartSpec::on_base(
            "door",
            Joint::revolute(
                "hinge",
                Point3::new(0.55, 0.0, 0.0),
                Vector3::z(),
                Limits::new(0.0, 2.0 * std::f64::consts::PI),
            ),
        )
        .with_collider(
            Shape::cuboid(Vector3::new(0.2, 0.00025, 0.4)),
            Isometry3::translation(0.2, 0.0, 0.5),
        ),
    );
    let model = builder.build().unwrap();
    let hinge = model.joint_id("hinge").unwrap();
    let angle = |t: f64| std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * t;
    let data_at = |t: f64, data: &mut SceneData| {
        let mut s = model.zero_state();
        s.set(&model, hinge, angle(t)).is_ok() && forward_kinematics(&model, data, &s).is_ok()
    };
    let stow = robot.neutral();
    let touches = |t: f64| {
        let mut data = SceneData::new(&model);
        assert!(data_at(t, &mut data));
        collision
            .scene_collision(&poses(&robot, &stow), &model, &data, Exempt::Nothing, 0.0)
            .is_some()
    };
    let first = first_sampled(&touches, "the door turns into the robot");
    let mut data = SceneData::new(&model);
    assert!(data_at(0.0, &mut data));
    let still = vec![0.0; robot.dof()];
    // The slab's farthest corner from the axis: √(0.4² + 0.00025²) m, below 0.4001.
    let walk = ContactWalk {
        robot: &robot,
        collision: &collision,
        bound: &bound,
        model: &model,
        data: &data,
        exempt: Exempt::Nothing,
        base: WalkBase::Still([0.0; 3]),
        joint_speed: &still,
        max_steps: 1_000_000,
        scene_at: Some(&data_at),
        scene_speed: std::f64::consts::PI * 0.4001,
    };
    let trajectory = |_: f64| stow.iter().copied().collect::<Vec<f64>>();
    assert_stops_at(&walk, &trajectory, first);
}

/// The Gen3 stowed, its base turning 1 rad and driving 0.36 m in 1 s, a plate 0.5 mm thick
/// across the sweep of the link farthest from the base's axis (centred on its origin at
/// t = 0.53, its thin side along the origin's motion there): the walk (`WalkBase::Moving`,
/// the arm still) stops at or before the first contact dense sampling finds (every 0.1 ms,
/// parry at margin 0), not long before, and certifies the motion up to 10 ms before it.
#[test]
fn the_walk_stops_at_a_thin_plate_in_the_base_s_sweep() {
    let robot = RobotModel::kinova_gen3_mobile();
    let collision = RobotCollision::new(&robot).unwrap();
    let bound = collision.speed_bound(&robot);
    let stow = robot.neutral();
    let end = [0.3, 0.2, 1.0];
    let base_at = |t: f64| end.map(|e| e * t);
    let at = |t: f64| poses_at(&robot, base_at(t), &stow);
    let far = (1..robot.links().len())
        .max_by(|&i, &j| {
            let r = |l: usize| {
                bound
                    .link_radius(l)
                    .min(at(0.0)[l].translation.vector.xy().norm())
            };
            r(i).total_cmp(&r(j))
        })
        .unwrap();
    let p0 = at(0.53)[far].translation.vector;
    let along = (at(0.531)[far].translation.vector - p0).normalize();
    let mut builder = SceneModelBuilder::new();
    builder.add_base_shape(BaseShape::new(
        "plate",
        Shape::cuboid(Vector3::new(0.03, 0.03, 0.00025)),
        Isometry3::from_parts(
            Translation3::from(p0),
            UnitQuaternion::rotation_between(&Vector3::z(), &along).unwrap(),
        ),
    ));
    let model = builder.build().unwrap();
    let data = data_of(&model);
    let touches = |t: f64| {
        collision
            .scene_collision(&at(t), &model, &data, Exempt::Nothing, 0.0)
            .is_some()
    };
    let first = first_sampled(&touches, "the plate is across the sweep");
    let still = vec![0.0; robot.dof()];
    let walk = ContactWalk {
        robot: &robot,
        collision: &collision,
        bound: &bound,
        model: &model,
        data: &data,
        exempt: Exempt::Nothing,
        base: WalkBase::Moving {
            pose: &base_at,
            linear: end[0].hypot(end[1]),
            angular: end[2],
        },
        joint_speed: &still,
        max_steps: 1_000_000,
        scene_at: None,
        scene_speed: 0.0,
    };
    let trajectory = |_: f64| stow.iter().copied().collect::<Vec<f64>>();
    assert_stops_at(&walk, &trajectory, first);
    let before = first - 0.01;
    assert!((0..=1000).all(|i| !touches(before * i as f64 / 1000.0)));
}

/// The first of the times `0, 0.1 ms, …, 1 s` at which `touches` (dense sampling of the exact
/// check); `expect` names the contact the test set up.
fn first_sampled(touches: &dyn Fn(f64) -> bool, expect: &str) -> f64 {
    (0..=10_000)
        .map(|i| i as f64 * 1e-4)
        .find(|&t| touches(t))
        .expect(expect)
}

/// The walk over `[0, 1]` s stops at a contact at or before `first` (the first contact dense
/// sampling found) and at most 10 ms before it, and certifies `[0, first − 0.01]` free.
fn assert_stops_at(walk: &ContactWalk<'_>, trajectory: &dyn Fn(f64) -> Vec<f64>, first: f64) {
    let WalkOutcome::Contact { t } = walk.first_contact(trajectory, 0.0, 1.0) else {
        panic!("the walk passed the contact at {first}");
    };
    eprintln!("first contact sampled at {first:.4} s, walk stopped at {t:.4} s");
    assert!(
        t <= first,
        "the walk stopped at {t}, after the contact at {first}"
    );
    assert!(
        t >= first - 0.01,
        "the walk stopped at {t}, long before {first}"
    );
    assert!(matches!(
        walk.first_contact(trajectory, 0.0, first - 0.01),
        WalkOutcome::Free { .. }
    ));
}
