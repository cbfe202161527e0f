//! Collision queries at a state and along one-joint motions, on hand-built scenes.

use super::fixtures::hinged_door;
use std::f64::consts::{FRAC_PI_2, PI};

use kinscene::scene::collision::{
    Body, CollisionSettings, SweepSettings, SweepStatus, check_joint_motion, collisions, distances,
};
use kinscene::scene::{
    Joint, Limits, PartSpec, SceneData, SceneModel, SceneModelBuilder, Shape, State,
    forward_kinematics,
};
use nalgebra::{Isometry3, Point3, Vector3};

/// Two cabinet doors whose sweeps intersect. `a`: hinge at the origin, axis +z, slab
/// x ∈ [0, 0.6], y ∈ [0.005, 0.025]. `b`: hinge at (1, 0, 0), axis -z, slab x ∈ [0.4, 1],
/// y ∈ [0.03, 0.05], in front of `a`. Both open towards +y; closed, they are 5 mm apart.
fn double_door() -> SceneModel {
    let slab = Shape::cuboid(Vector3::new(0.3, 0.01, 0.4));
    let mut b = SceneModelBuilder::new();
    b.add_part(
        PartSpec::on_base(
            "a",
            Joint::revolute(
                "a_hinge",
                Point3::origin(),
                Vector3::z(),
                Limits::new(0.0, FRAC_PI_2),
            ),
        )
        .with_collider(slab.clone(), Isometry3::translation(0.3, 0.015, 0.4)),
    );
    b.add_part(
        PartSpec::on_base(
            "b",
            Joint::revolute(
                "b_hinge",
                Point3::new(1.0, 0.0, 0.0),
                -Vector3::z(),
                Limits::new(0.0, FRAC_PI_2),
            ),
        )
        .with_collider(slab, Isometry3::translation(-0.3, 0.04, 0.4)),
    );
    b.build().unwrap()
}

pub(super) fn sweep(
    m: &SceneModel,
    s: &State,
    joint: &str,
    a: f64,
    b: f64,
    settings: &SweepSettings,
) -> kinscene::scene::collision::SweepOutcome {
    let mut data = SceneData::new(m);
    check_joint_motion(m, &mut data, s, m.joint_id(joint).unwrap(), a, b, settings).unwrap()
}

#[test]
fn closed_doors_are_apart_unless_the_contact_distance_says_otherwise() {
    let m = double_door();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &m.zero_state()).unwrap();
    assert!(
        collisions(&m, &data, &CollisionSettings::default())
            .unwrap()
            .is_empty()
    );
    let near = distances(&m, &data, &CollisionSettings::default(), 0.01).unwrap();
    assert_eq!(near.len(), 1);
    // Face y = 0.025 of `a` against face y = 0.03 of `b`.
    assert!(
        (near[0].distance - 0.005).abs() < 1e-9,
        "{}",
        near[0].distance
    );
    let loose = CollisionSettings {
        contact_distance: 0.006,
        ..Default::default()
    };
    assert_eq!(collisions(&m, &data, &loose).unwrap().len(), 1);
}

#[test]
fn intersecting_sweeps_collide_at_the_first_contact() {
    let m = double_door();
    let settings = SweepSettings::default();
    let out = sweep(&m, &m.zero_state(), "a_hinge", 0.0, FRAC_PI_2, &settings);
    let SweepStatus::Collision { value, contacts } = &out.status else {
        panic!("expected a collision, got {:?}", out.status)
    };
    assert_eq!(contacts[0].a, Body::Part(m.part_id("a").unwrap()));
    assert_eq!(contacts[0].b, Body::Part(m.part_id("b").unwrap()));
    // First contact: the corner (0.6, 0.025) of `a` reaches y = 0.03, the underside of `b`:
    // 0.6 sin θ + 0.025 cos θ = 0.03.
    let (r, phi) = (0.6f64.hypot(0.025), 0.025f64.atan2(0.6));
    let first = (0.03 / r).asin() - phi;
    // The reported sample lies at most one finest interval (travel 2·min_margin, i.e.
    // Δθ = 2e-4 / L) after the first contact.
    let step = 2.0 * settings.min_margin / out.bound.lipschitz();
    assert!(
        *value >= first - 1e-9 && *value <= first + step + 1e-9,
        "{value} vs {first}"
    );
    // Everything up to `free_until` is certified free, so it ends before the first contact.
    let free_until = out.free_until.unwrap();
    assert!(
        free_until < first && free_until > 0.0,
        "{free_until} vs {first}"
    );
}

#[test]
fn opening_the_front_door_first_makes_the_other_free() {
    let m = double_door();
    let settings = SweepSettings::default();
    // `b` swings away from `a`: free with `a` closed.
    let out = sweep(&m, &m.zero_state(), "b_hinge", 0.0, FRAC_PI_2, &settings);
    assert!(out.is_free(), "{:?}", out.status);
    // With `b` open (it lies at x ∈ [1.03, 1.05]), `a` (reach 0.6 m) swings freely.
    let s = State::from_values(&m, [("b_hinge", FRAC_PI_2)]).unwrap();
    let out = sweep(&m, &s, "a_hinge", 0.0, FRAC_PI_2, &settings);
    assert!(out.is_free(), "{:?}", out.status);
    assert_eq!(out.free_until, Some(FRAC_PI_2));
    // Initial spacing: travel L·π/2 split into 2·margin steps.
    let first = (out.bound.lipschitz() * FRAC_PI_2 / (2.0 * settings.margin)).ceil() as usize + 1;
    assert!(
        out.samples >= first && out.samples < 4 * first,
        "{} samples",
        out.samples
    );
}

#[test]
fn allowed_pairs_are_not_checked() {
    let m = double_door();
    let mut settings = SweepSettings::default();
    let (a, b) = (m.part_id("a").unwrap(), m.part_id("b").unwrap());
    settings
        .collision
        .allowed
        .allow(Body::Part(b), Body::Part(a));
    let out = sweep(&m, &m.zero_state(), "a_hinge", 0.0, FRAC_PI_2, &settings);
    assert!(out.is_free());
    assert_eq!(out.samples, 0, "nothing to check");
}

#[test]
fn parent_child_pairs_are_skipped_unless_asked() {
    // A child overlapping its parent (a rack inside a door).
    let mut b = SceneModelBuilder::new();
    b.add_part(hinged_door(
        PI,
        Vector3::new(0.2, 0.2, 0.2),
        Vector3::new(0.0, 0.0, 0.0),
    ));
    b.add_part(
        PartSpec::on_part(
            "rack",
            "door",
            Joint::prismatic(
                "slide",
                Point3::origin(),
                Vector3::x(),
                Limits::new(0.0, 0.1),
            ),
        )
        .with_collider(Shape::sphere(0.1), Isometry3::identity()),
    );
    let m = b.build().unwrap();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &m.zero_state()).unwrap();
    assert!(
        collisions(&m, &data, &CollisionSettings::default())
            .unwrap()
            .is_empty()
    );
    let strict = CollisionSettings {
        check_parent_child: true,
        ..Default::default()
    };
    assert_eq!(collisions(&m, &data, &strict).unwrap().len(), 1);
}
