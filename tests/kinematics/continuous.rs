//! The continuous motion check of `ArmCheck` (the default, `with_continuous`) never accepts a
//! motion that touches anything, thin obstacles included, against dense sampling of the
//! exact check.

use kinscene::kinematics::robot::{ArmCheck, RobotCollision, RobotSpheres, SphereSettings};
use kinscene::scene::{BaseShape, Shape};
use nalgebra::{Isometry3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::spheres::{edge_scene, exact_free, motion_from_free, robots, scene_builder, zero_data};

/// On 60 seeded motions per robot (Gen3, Panda, TIAGo; from a free configuration, 0.3 to
/// 2 rad long) among the sphere tests' obstacles and three thin ones (a 1 mm plate, a 1 mm
/// rod and a 2 mm slab), at margin 0: every motion the continuous check accepts is free at
/// each of 2000 evenly spaced states (parry's exact check, self and scene), and it rejects
/// every motion dense sampling finds touching, among them motions a discrete check at
/// 0.3 rad accepts (something falls between its states; measured: 3 over the three
/// robots, at least one asserted). Not vacuous the other way: it accepts at least 80 % of the motions dense
/// sampling finds free.
#[test]
fn the_continuous_check_accepts_no_motion_that_touches() {
    const RESOLUTION: f64 = 0.02;
    const COARSE: f64 = 0.3;
    const SAMPLES: usize = 2000;
    let mut builder = scene_builder();
    for (name, shape, pose) in [
        (
            "plate",
            Shape::cuboid(Vector3::new(0.15, 0.15, 0.0005)),
            Isometry3::new(Vector3::new(0.45, -0.2, 0.9), Vector3::new(0.4, 0.0, 0.0)),
        ),
        (
            "rod",
            Shape::cylinder(0.001, 0.4),
            Isometry3::new(Vector3::new(-0.35, -0.4, 0.7), Vector3::new(0.0, 0.6, 0.3)),
        ),
        (
            "slab",
            Shape::cuboid(Vector3::new(0.001, 0.25, 0.2)),
            Isometry3::translation(-0.5, 0.3, 0.5),
        ),
    ] {
        builder.add_base_shape(BaseShape::new(name, shape, pose));
    }
    let model = builder.build().unwrap();
    let data = zero_data(&model);
    let edge_scene = edge_scene(&model, &data, 0.0);
    let mut jumped_by_discrete = 0;
    for (name, robot) in robots() {
        let collision = RobotCollision::new(&robot).unwrap();
        let spheres = RobotSpheres::new(&robot, &collision, &SphereSettings::default()).unwrap();
        let discrete = ArmCheck::new(&robot, &collision, &spheres, edge_scene, [0.0; 3])
            .unwrap()
            .with_continuous(false);
        // The default.
        let continuous = ArmCheck::new(&robot, &collision, &spheres, edge_scene, [0.0; 3]).unwrap();
        let exact = exact_free(&robot, &collision, &model, &data, 0.0);
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        let (mut free, mut accepted_free, mut touching) = (0, 0, 0);
        let mut motions = 0;
        while motions < 60 {
            let Some((a, b, _)) = motion_from_free(&robot, &mut rng, &exact, 0.3..=2.0, 1) else {
                continue;
            };
            motions += 1;
            let (a, b) = (a.as_slice(), b.as_slice());
            let dense_free = (1..=SAMPLES).all(|j| {
                let t = j as f64 / SAMPLES as f64;
                let q: Vec<f64> = a.iter().zip(b).map(|(x, y)| x + (y - x) * t).collect();
                exact(&q)
            });
            let certified = continuous.check_motion(a, b, RESOLUTION);
            if dense_free {
                free += 1;
                accepted_free += usize::from(certified);
            } else {
                touching += 1;
                assert!(
                    !certified,
                    "{name}: the continuous check accepts {a:?} -> {b:?}, which touches"
                );
                if discrete.check_motion(a, b, COARSE) {
                    jumped_by_discrete += 1;
                }
            }
        }
        eprintln!(
            "{name}: continuous check accepts {accepted_free} of {free} free motions, rejects \
             all {touching} touching ones"
        );
        assert!(
            accepted_free * 5 >= free * 4,
            "{name}: only {accepted_free} of {free} free motions accepted"
        );
    }
    eprintln!("motions the discrete check accepts but that touch: {jumped_by_discrete}");
    assert!(
        jumped_by_discrete > 0,
        "no thin obstacle fell between states"
    );
}
