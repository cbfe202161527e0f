//! The reconciliation on hand-computed two-part scenes.

use nalgebra::{Isometry3, Vector3};

use super::conflicts::conflicts;
use super::*;
use crate::scene::{Joint, JointKind, Limits, PartSpec, SceneModelBuilder, Shape};

/// Adds a part on the base with one box (half extents `half`, centre `centre` in the part
/// frame) on a joint at the origin: revolute limits [0, 1.5], prismatic [0, 0.4].
fn add_box_part(
    b: &mut SceneModelBuilder,
    name: &str,
    kind: JointKind,
    axis: Vector3<f64>,
    half: Vector3<f64>,
    centre: Vector3<f64>,
) {
    let (suffix, upper) = match kind {
        JointKind::Revolute => ("hinge", 1.5),
        JointKind::Prismatic => ("slide", 0.4),
    };
    let joint = Joint::new(
        format!("{name}_{suffix}"),
        kind,
        Isometry3::identity(),
        axis,
        Limits::new(0.0, upper),
    );
    b.add_part(PartSpec::on_base(name, joint).with_collider(
        Shape::cuboid(half),
        Isometry3::translation(centre.x, centre.y, centre.z),
    ));
}

/// The world x range of part `k`'s first box, and its y, z half extents.
fn range(m: &SceneModel, k: usize) -> ([f64; 2], [f64; 2]) {
    let c = &m.parts()[k].colliders()[0];
    let Shape::Cuboid { half_extents: h } = &c.shape else {
        panic!("a box")
    };
    let x = c.part_from_shape.translation.x;
    ([x - h.x, x + h.x], [h.y, h.z])
}

/// Two drawer fronts side by side whose estimated boxes overlap by 1.2 cm in x at the closed
/// state (left: x 0 .. 0.50, right: x 0.488 .. 0.79; both 2 cm thick, 0.4 m tall). The
/// cheapest separating cut moves one inner x face by 15 mm, the smallest of CUTS above
/// the overlap (the x face areas are 0.02 × 0.4 m², against 0.5 × 0.4 or 0.302 × 0.4 for
/// the y faces; z faces and outer x faces do not separate the boxes, and any pair of faces
/// that does removes more): after it no pair collides, one box lost 15 mm of x extent on
/// its inner side only and every other extent and face is unchanged.
#[test]
fn overlapping_fronts_are_cut_on_one_face() {
    let mut b = SceneModelBuilder::new();
    for (name, lo, hi) in [("left", 0.0, 0.50), ("right", 0.488, 0.79)] {
        add_box_part(
            &mut b,
            name,
            JointKind::Prismatic,
            -Vector3::y(),
            Vector3::new((hi - lo) / 2.0, 0.01, 0.2),
            Vector3::new((lo + hi) / 2.0, 0.01, 0.5),
        );
    }
    let est = b.build().unwrap();
    let closed = Observation::State(est.zero_state());
    let sweep = SweepSettings::default();
    assert!(!conflicts(&est, &closed, &sweep).unwrap().is_empty());
    let (cut, log) = reconcile(&est, std::slice::from_ref(&closed), &sweep, None).unwrap();
    assert!(log.unresolved.is_empty(), "{log:?}");
    assert_eq!(log.cuts.len(), 1, "{log:?}");
    assert!(conflicts(&cut, &closed, &sweep).unwrap().is_empty());
    let before = [range(&est, 0), range(&est, 1)];
    let after = [range(&cut, 0), range(&cut, 1)];
    let changed: Vec<usize> = (0..2).filter(|&k| before[k] != after[k]).collect();
    assert_eq!(changed.len(), 1, "{before:?} → {after:?}");
    let k = changed[0];
    assert_eq!(before[k].1, after[k].1, "y and z extents kept");
    // The outer face stays; the inner one moves in by one of CUTS.
    let (outer, inner) = if k == 0 { (0, 1) } else { (1, 0) };
    assert!((before[k].0[outer] - after[k].0[outer]).abs() < 1e-12);
    let moved = (before[k].0[inner] - after[k].0[inner]).abs();
    assert!((moved - 0.015).abs() < 1e-12, "moved {moved}");
}

/// A door hinged at the origin about −z (it opens towards −y) whose estimated box reaches
/// 1 cm past its hinge line: x −0.01 .. 0.5, y −0.02 .. 0, z 0 .. 0.6; a drawer front beside
/// it at x −0.41 .. −0.012, same y and z. Closed they are 2 mm apart (no conflict). Turned
/// by θ (R(−θ)), the box corner beyond the hinge, (−0.01, −0.02), goes to
/// (−0.01 cos θ − 0.02 sin θ, 0.01 sin θ − 0.02 cos θ): at the observed 0.5 rad that is
/// (−0.0184, −0.0128), inside the drawer. By hand, the cheapest cut that frees the motion
/// moves an x face by 10 mm: the door's hinge face to x = 0 (the corner then stays at
/// x ≥ −0.02 sin 0.5 = −0.0096 > −0.012), or the drawer's inner face to x = −0.022 (beyond
/// the corner's −0.0184); 3 and 6 mm leave the corner inside (at −0.0157 or −0.0131 for
/// the door, the drawer face at −0.015 or −0.018). The two faces have the same area,
/// 0.02 × 0.6 m²; no z face separates the boxes and a y face costs at least 25 times more.
#[test]
fn observed_door_motion_is_made_free() {
    let mut b = SceneModelBuilder::new();
    add_box_part(
        &mut b,
        "door",
        JointKind::Revolute,
        -Vector3::z(),
        Vector3::new(0.255, 0.01, 0.3),
        Vector3::new(0.245, -0.01, 0.3),
    );
    add_box_part(
        &mut b,
        "drawer",
        JointKind::Prismatic,
        -Vector3::y(),
        Vector3::new(0.199, 0.01, 0.3),
        Vector3::new(-0.211, -0.01, 0.3),
    );
    let est = b.build().unwrap();
    let door = est.joint_id("door_hinge").unwrap();
    let observations = [
        Observation::State(est.zero_state()),
        Observation::Motion {
            state: est.zero_state(),
            joint: door,
            from: 0.0,
            to: 0.5,
        },
    ];
    let sweep = SweepSettings::default();
    assert!(
        conflicts(&est, &observations[0], &sweep)
            .unwrap()
            .is_empty()
    );
    assert!(
        !conflicts(&est, &observations[1], &sweep)
            .unwrap()
            .is_empty()
    );
    let (cut, log) = reconcile(&est, &observations, &sweep, None).unwrap();
    assert!(log.unresolved.is_empty(), "{log:?}");
    assert_eq!(log.cuts.len(), 1, "{log:?}");
    let c = &log.cuts[0];
    assert_eq!((c.axis, c.depth, c.observation), (0, 0.01, 1), "{c:?}");
    for o in &observations {
        assert!(conflicts(&cut, o, &sweep).unwrap().is_empty(), "{log:?}");
    }
    // Either the door's hinge face or the drawer's inner face moved; the door's free edge
    // (x = 0.5) and the drawer's far edge (x = −0.41) are kept.
    let (door_x, drawer_x) = (range(&cut, 0).0, range(&cut, 1).0);
    assert!((door_x[1] - 0.5).abs() < 1e-12 && (drawer_x[0] + 0.41).abs() < 1e-12);
    let door_cut = (door_x[0] - 0.0).abs() < 1e-12 && (drawer_x[1] + 0.012).abs() < 1e-12;
    let drawer_cut = (door_x[0] + 0.01).abs() < 1e-12 && (drawer_x[1] + 0.022).abs() < 1e-12;
    assert!(door_cut ^ drawer_cut, "{door_x:?} {drawer_x:?}");
}
