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

#[test]
fn collisions_of_reports_the_pair_from_the_moving_side() {
    let m = double_door();
    let mut data = SceneData::new(&m);
    // `a` opened by 0.02 rad: its free corner (0.6, 0.025) moves to (0.6 cos 0.02 -
    // 0.025 sin 0.02, 0.6 sin 0.02 + 0.025 cos 0.02) = (0.5994, 0.0370), inside `b`
    // (x ∈ [0.4, 1], y ∈ [0.03, 0.05]).
    let s = State::from_values(&m, [("a_hinge", 0.02)]).unwrap();
    forward_kinematics(&m, &mut data, &s).unwrap();
    let settings = CollisionSettings::default();
    let (a, b) = (m.part_id("a").unwrap(), m.part_id("b").unwrap());
    let all = collisions(&m, &data, &settings).unwrap();
    assert_eq!(all.len(), 1);
    let of_a = kinscene::scene::collision::collisions_of(&m, &data, &settings, a).unwrap();
    let of_b = kinscene::scene::collision::collisions_of(&m, &data, &settings, b).unwrap();
    assert_eq!(
        (of_a.len(), of_a[0].a, of_a[0].b),
        (1, Body::Part(a), Body::Part(b))
    );
    assert_eq!(
        (of_b.len(), of_b[0].a, of_b[0].b),
        (1, Body::Part(b), Body::Part(a))
    );
    assert_eq!(of_a[0].distance, all[0].distance);
    assert_eq!(of_b[0].distance, all[0].distance);
    // An id from a larger model is rejected, not a panic.
    let mut bigger = m.to_builder();
    bigger.add_part(PartSpec::on_base(
        "c",
        Joint::prismatic(
            "c_slide",
            Point3::origin(),
            Vector3::x(),
            Limits::new(0.0, 0.1),
        ),
    ));
    let foreign = bigger.build().unwrap().part_id("c").unwrap();
    assert!(matches!(
        kinscene::scene::collision::collisions_of(&m, &data, &settings, foreign),
        Err(kinscene::scene::Error::UnknownId { .. })
    ));
}

/// [`collisions_of`] against [`collisions`] on generated scenes, and the pre-filters of both
/// (bounding spheres, world boxes) against unfiltered distances.
mod subtree {
    use kinscene::scene::collision::{
        Body, CollisionSettings, collisions, collisions_of, distances,
    };
    use kinscene::scene::{SceneData, SceneModel, forward_kinematics};
    use proptest::prelude::*;
    use proptest::sample::Index;

    use super::super::generators::scene_and_state;

    /// Every body of `model`: parts first, then base shapes.
    fn bodies(model: &SceneModel) -> Vec<Body> {
        model
            .parts()
            .iter()
            .map(|p| Body::Part(p.id()))
            .chain(
                model
                    .base()
                    .shapes
                    .iter()
                    .map(|s| Body::Base(model.base_shape_id(&s.name).unwrap())),
            )
            .collect()
    }

    /// Contact distances: 0 (the default) or up to 0.2 m, which makes near pairs collide.
    fn contact_distance() -> impl Strategy<Value = f64> {
        prop_oneof![Just(0.0), 0.0..0.2f64]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

        /// Same pairs (the subtree's body first), same distances (bit for bit), in the
        /// documented order.
        #[test]
        fn collisions_of_is_collisions_restricted_to_the_subtree(
            (model, state) in scene_and_state(8),
            root in any::<Index>(),
            contact in contact_distance(),
            check_parent_child in any::<bool>(),
            allowed in prop::collection::vec((any::<Index>(), any::<Index>()), 0..3),
        ) {
            let root = model.parts()[root.index(model.parts().len())].id();
            let all = bodies(&model);
            let mut settings = CollisionSettings {
                contact_distance: contact,
                check_parent_child,
                ..Default::default()
            };
            for (x, y) in allowed {
                let (x, y) = (all[x.index(all.len())], all[y.index(all.len())]);
                settings.allowed.allow(x, y);
            }
            let mut data = SceneData::new(&model);
            forward_kinematics(&model, &mut data, &state).unwrap();
            let part = &model.parts()[root.index()];
            let inside = |b: Body| matches!(b, Body::Part(p) if part.subtree_contains(p));
            let mut expected: Vec<(Body, Body, f64)> = collisions(&model, &data, &settings)
                .unwrap()
                .into_iter()
                .filter(|c| inside(c.a) != inside(c.b))
                .map(|c| if inside(c.a) { (c.a, c.b, c.distance) } else { (c.b, c.a, c.distance) })
                .collect();
            expected.sort_by_key(|&(a, b, _)| (a, b));
            let got: Vec<(Body, Body, f64)> = collisions_of(&model, &data, &settings, root)
                .unwrap()
                .into_iter()
                .map(|c| (c.a, c.b, c.distance))
                .collect();
            // Documented order: subtree part by id, then other parts, then base shapes, which
            // is `Body`'s order.
            prop_assert!(got.is_sorted_by_key(|&(a, b, _)| (a, b)), "{got:?}");
            prop_assert_eq!(got, expected);
        }

        /// The sphere and box pre-filters never change the answer: `collisions` equals the
        /// pairs whose distance, computed with both filters inactive (`distances` with a
        /// 1 km threshold, beyond every gap in these scenes of a few metres), is within the
        /// contact distance.
        #[test]
        fn pre_filters_do_not_change_collisions(
            (model, state) in scene_and_state(8),
            contact in contact_distance(),
        ) {
            let settings = CollisionSettings { contact_distance: contact, ..Default::default() };
            let mut data = SceneData::new(&model);
            forward_kinematics(&model, &mut data, &state).unwrap();
            let unfiltered: Vec<_> = distances(&model, &data, &settings, 1e3)
                .unwrap()
                .into_iter()
                .filter(|c| c.distance <= contact)
                .collect();
            prop_assert_eq!(collisions(&model, &data, &settings).unwrap(), unfiltered);
        }
    }
}

/// The box pre-filter at its tightest: a shape with a random orientation a known gap away
/// from a large wall. The world box of a cuboid or a sphere touches the shape along every
/// axis, so a filter that cut even slightly into the shape would miss contacts here.
mod wall {
    use kinscene::scene::collision::{Body, CollisionSettings, collisions, collisions_of};
    use kinscene::scene::{
        BaseShape, Joint, Limits, PartSpec, SceneData, SceneModelBuilder, Shape, forward_kinematics,
    };
    use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
    use proptest::prelude::*;

    use super::super::generators::{rotation, shape};

    /// The wall's face (m): the wall is `x ∈ [WALL_X, WALL_X + 1]`, `|y|, |z| <= 5`.
    const WALL_X: f64 = 1.0;

    /// The largest x of `shape` rotated by `r` about its origin (its support along +x),
    /// computed from the shape's definition, independently of the scene layer's boxes.
    fn support_x(shape: &Shape, r: &UnitQuaternion<f64>) -> f64 {
        let m = r.to_rotation_matrix();
        let row = m.matrix().row(0);
        // Direction of the shape's z axis in the world.
        let a_x = row[2];
        match shape {
            Shape::Cuboid { half_extents: h } => {
                row[0].abs() * h.x + row[1].abs() * h.y + row[2].abs() * h.z
            }
            Shape::Sphere { radius } => *radius,
            // A disc of radius r perpendicular to a reaches r·√(1 − a_x²) along x.
            Shape::Cylinder { radius, length } => {
                a_x.abs() * length / 2.0 + radius * (1.0 - a_x * a_x).max(0.0).sqrt()
            }
            Shape::Capsule { radius, length } => a_x.abs() * length / 2.0 + radius,
            Shape::ConvexMesh { vertices, .. } => vertices
                .iter()
                .map(|v| (r * v).x)
                .fold(f64::NEG_INFINITY, f64::max),
            _ => unreachable!("the generators make only these shapes"),
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

        #[test]
        fn a_shape_collides_with_a_wall_iff_its_gap_is_within_the_contact_distance(
            shape in shape(),
            r in prop_oneof![Just(UnitQuaternion::identity()), rotation()],
            contact in 0.001..0.1f64,
            // Half of the gaps within 0.1 % of the contact distance, where a filter cutting
            // into the shape by 0.1 mm would already drop contacts.
            t in prop_oneof![0.0..2.0f64, 0.999..1.001f64],
            (y, z) in (-0.5..0.5f64, -0.5..0.5f64),
        ) {
            let gap = t * contact;
            // Parry's exact distance is accurate to about 5e-8 relative: stay clear of the
            // threshold by far more.
            prop_assume!((gap - contact).abs() > 1e-6);
            let x = WALL_X - gap - support_x(&shape, &r);
            let mut b = SceneModelBuilder::new();
            b.add_base_shape(BaseShape::new(
                "wall",
                Shape::cuboid(Vector3::new(0.5, 5.0, 5.0)),
                Isometry3::translation(WALL_X + 0.5, 0.0, 0.0),
            ));
            let slide =
                Joint::prismatic("slide", Point3::origin(), Vector3::y(), Limits::new(0.0, 0.1));
            b.add_part(PartSpec::on_base("probe", slide).with_collider(
                shape,
                Isometry3::from_parts(Translation3::new(x, y, z), r),
            ));
            let model = b.build().unwrap();
            let mut data = SceneData::new(&model);
            forward_kinematics(&model, &mut data, &model.zero_state()).unwrap();
            let settings = CollisionSettings { contact_distance: contact, ..Default::default() };
            let probe = model.part_id("probe").unwrap();
            let all = collisions(&model, &data, &settings).unwrap();
            let of = collisions_of(&model, &data, &settings, probe).unwrap();
            prop_assert_eq!(&all, &of);
            if gap <= contact {
                prop_assert_eq!(all.len(), 1, "gap {} within {}", gap, contact);
                prop_assert_eq!(all[0].a, Body::Part(probe));
                let d = all[0].distance;
                prop_assert!((d - gap).abs() < 1e-6, "{} vs {}", d, gap);
            } else {
                prop_assert!(all.is_empty(), "gap {} beyond {}: {:?}", gap, contact, all);
            }
        }
    }
}
