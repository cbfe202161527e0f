//! The sampled sweep check against dense brute-force sampling on generated scenes.

use std::cell::Cell;
use std::f64::consts::PI;

use kinscene::scene::collision::{
    CollisionSettings, SweepSettings, SweepStatus, check_joint_motion, collisions, distances,
};
use kinscene::scene::{
    BaseShape, Joint, JointKind, Limits, PartSpec, SceneData, SceneModel, SceneModelBuilder, Shape,
    State, forward_kinematics,
};
use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

use super::generators::{isometry, joint_kind, rotation};

/// Dense brute-force samples per motion.
const BRUTE_SAMPLES: usize = 2000;

/// A small obstacle (a thin plate, a small box or a ball) with a random orientation, and three
/// uniform numbers placing it in the door's swept region (see [`place`]).
fn obstacle() -> impl Strategy<Value = (Shape, UnitQuaternion<f64>, [f64; 3])> {
    let shape = prop_oneof![
        (0.02..0.3f64, 0.0005..0.002f64, 0.02..0.3f64)
            .prop_map(|(x, y, z)| Shape::cuboid(Vector3::new(x, y, z))),
        (0.005..0.05f64, 0.005..0.05f64, 0.005..0.05f64)
            .prop_map(|(x, y, z)| Shape::cuboid(Vector3::new(x, y, z))),
        (0.003..0.05f64).prop_map(Shape::sphere),
    ];
    let u = 0.0..=1.0f64;
    (shape, rotation(), (u.clone(), u.clone(), u)).prop_map(|(s, r, (u, v, w))| (s, r, [u, v, w]))
}

/// Maps three uniform numbers to a point of the joint frame near the door's sweep: polar
/// (radius 0.02–0.85 m, angle -0.3–π+0.3) for a revolute door, a slab along x for a
/// prismatic one; height 0–0.6 m.
fn place(kind: JointKind, [u, v, w]: [f64; 3]) -> Vector3<f64> {
    match kind {
        JointKind::Revolute => {
            let (r, a) = (0.02 + 0.83 * u, -0.3 + (PI + 0.6) * v);
            Vector3::new(r * a.cos(), r * a.sin(), 0.6 * w)
        }
        JointKind::Prismatic => Vector3::new(-0.1 + 1.5 * u, -0.05 + 0.15 * v, 0.6 * w),
    }
}

/// A door (revolute about z or prismatic along x of a random joint frame) with a child knob
/// riding on it, and 1–5 obstacles on the base; plus a start value and a motion `a → b`.
fn door_scene() -> impl Strategy<Value = (SceneModel, State, f64, f64)> {
    (
        joint_kind(),
        isometry(0.5),
        (0.15..0.4f64, 0.003..0.02f64, 0.1..0.4f64),
        prop::collection::vec(obstacle(), 1..=5),
        (0.0..=1.0f64, 0.0..=1.0f64, 0.0..=1.0f64),
    )
        .prop_map(
            |(kind, origin, (half_len, half_thick, half_h), obstacles, (t0, ta, tb))| {
                let (axis, upper) = match kind {
                    JointKind::Revolute => (Vector3::z(), PI),
                    JointKind::Prismatic => (Vector3::x(), 0.6),
                };
                let mut b = SceneModelBuilder::new();
                b.add_part(
                    PartSpec::on_base(
                        "door",
                        Joint::new("hinge", kind, origin, axis, Limits::new(0.0, upper)),
                    )
                    .with_collider(
                        Shape::cuboid(Vector3::new(half_len, half_thick, half_h)),
                        Isometry3::translation(half_len, half_thick + 0.002, half_h),
                    ),
                );
                b.add_part(
                    PartSpec::on_part(
                        "knob",
                        "door",
                        Joint::prismatic(
                            "knob_slide",
                            Point3::new(1.6 * half_len, -0.03, half_h),
                            Vector3::y(),
                            Limits::new(0.0, 0.02),
                        ),
                    )
                    .with_collider(Shape::sphere(0.02), Isometry3::identity()),
                );
                for (k, (shape, rot, u)) in obstacles.into_iter().enumerate() {
                    let local = Isometry3::from_parts(place(kind, u).into(), rot);
                    b.add_base_shape(BaseShape::new(
                        format!("obstacle{k}"),
                        shape,
                        origin * local,
                    ));
                }
                let model = b.build().unwrap();
                let state =
                    State::from_values(&model, [("hinge", t0 * upper), ("knob_slide", 0.01)])
                        .unwrap();
                (model, state, ta * upper, tb * upper)
            },
        )
}

#[test]
fn sampled_check_never_misses_a_brute_force_collision() {
    let collided = Cell::new(0usize);
    let free = Cell::new(0usize);
    // A fixed seed keeps the verdict counts below stable from run to run.
    let config = Config {
        cases: 200,
        ..Config::default()
    };
    let mut runner =
        TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha));
    runner
        .run(
            &(door_scene(), 0.005..0.3f64, 1e-5..1e-2f64),
            |((model, state, a, b), margin, min_margin)| {
                let hinge = model.joint_id("hinge").unwrap();
                let mut data = SceneData::new(&model);
                // Coarse margins space the first samples up to 0.6 m of travel apart: only the
                // Lipschitz certificate and the subdivision keep the check sound.
                let settings = SweepSettings {
                    margin,
                    min_margin: min_margin.min(margin),
                    ..Default::default()
                };
                let out =
                    check_joint_motion(&model, &mut data, &state, hinge, a, b, &settings).unwrap();

                let mut s = state.clone();
                let first_hit = (0..=BRUTE_SAMPLES)
                    .map(|k| a + (b - a) * k as f64 / BRUTE_SAMPLES as f64)
                    .find(|&t| {
                        s.set(&model, hinge, t).unwrap();
                        forward_kinematics(&model, &mut data, &s).unwrap();
                        !collisions(&model, &data, &CollisionSettings::default())
                            .unwrap()
                            .is_empty()
                    });
                if let Some(t) = first_hit {
                    collided.set(collided.get() + 1);
                    prop_assert!(
                        !out.is_free(),
                        "brute force found a collision at {t} the sweep missed"
                    );
                    // The certified prefix [a, free_until] holds no brute-force collision either.
                    if let Some(f) = out.free_until {
                        prop_assert!(
                            (t - a).abs() > (f - a).abs(),
                            "collision at {t} inside [{a}, {f}]"
                        );
                    }
                }
                if out.is_free() {
                    free.set(free.get() + 1);
                }
                // A reported collision is real: at that value the pair is in contact (1e-7 m
                // allows for the sweep moving poses rigidly while FK recomputes them).
                if let SweepStatus::Collision { value, contacts } = &out.status {
                    s.set(&model, hinge, *value).unwrap();
                    forward_kinematics(&model, &mut data, &s).unwrap();
                    let near =
                        distances(&model, &data, &CollisionSettings::default(), 1e-7).unwrap();
                    for c in contacts {
                        prop_assert!(
                            near.iter().any(|n| n.a == c.a && n.b == c.b),
                            "{c:?} not in contact"
                        );
                    }
                }
                Ok(())
            },
        )
        .unwrap();
    // The generator must exercise both verdicts for the property to mean anything.
    assert!(
        collided.get() >= 40,
        "only {} colliding cases",
        collided.get()
    );
    assert!(free.get() >= 40, "only {} free cases", free.get());
}
