//! The kitchen scene of examples/scenes/kitchen.urdf: it loads with the parts and the tree its
//! header comment lists, nothing touches when it is closed, and the interactions designed into
//! it for task sequencing hold (a dishwasher rack riding on its door that only slides out once
//! the door is open, two corner doors whose sweeps cross, a door that blocks the passage
//! between the counter and the island).
//!
//! Expected values come from the numbers in the URDF; each derivation is stated where it is
//! used.

use std::collections::BTreeSet;
use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};

use kinscene::scene::collision::{
    Body, CollisionSettings, SweepSettings, SweepStatus, check_joint_motion, collisions, distances,
    handle_standoff,
};
use kinscene::scene::nav::{NavGrid, footprint, occupancy};
use kinscene::scene::urdf::{self, ExportOptions, ImportOptions};
use kinscene::scene::{
    JointKind, Parent, SceneData, SceneModel, Shape, State, forward_kinematics, world_from_handle,
};
use nalgebra::{Isometry3, Point2, Point3, Translation3, UnitQuaternion, Vector3};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes")
}

fn kitchen() -> SceneModel {
    urdf::read_file(scenes_dir().join("kitchen.urdf"), &ImportOptions::default())
        .expect("examples/scenes/kitchen.urdf loads")
}

/// The zero state with the named joints set.
fn state(model: &SceneModel, values: &[(&str, f64)]) -> State {
    State::from_values(model, values.iter().copied()).unwrap()
}

/// Checks the full stroke (lower to upper limit) of `joint` at `state`.
fn sweep(model: &SceneModel, state: &State, joint: &str) -> SweepStatus {
    let id = model.joint_id(joint).unwrap();
    let limits = model.joints()[id.index()].limits;
    let mut data = SceneData::new(model);
    check_joint_motion(
        model,
        &mut data,
        state,
        id,
        limits.lower,
        limits.upper,
        &SweepSettings::default(),
    )
    .unwrap()
    .status
}

/// The names of the parts in a sweep's first collision.
fn collision_parts(model: &SceneModel, status: &SweepStatus) -> Option<(f64, BTreeSet<String>)> {
    let SweepStatus::Collision { value, contacts } = status else {
        return None;
    };
    let name = |b: Body| match b {
        Body::Part(p) => model.part(p).unwrap().name().to_string(),
        Body::Base(s) => model.base_shape(s).unwrap().name.clone(),
    };
    let names = contacts
        .iter()
        .flat_map(|c| [name(c.a), name(c.b)])
        .collect();
    Some((*value, names))
}

fn set(names: &[&str]) -> BTreeSet<String> {
    names.iter().map(|s| s.to_string()).collect()
}

const DOORS: [&str; 5] = [
    "corner_door_back",
    "corner_door_side",
    "sink_door",
    "wall_door_tall",
    "wall_door_short",
];
const DRAWERS: [&str; 4] = [
    "drawer_top",
    "drawer_pot",
    "island_drawer_left",
    "island_drawer_right",
];

#[test]
fn kitchen_has_the_parts_its_header_lists() {
    let m = kitchen();
    assert_eq!(m.base().name.as_deref(), Some("kitchen_base"));
    assert_eq!(m.nq(), 11);
    // Every part hangs directly off the base except the dishwasher rack, which rides on the
    // dishwasher door (the one nested joint).
    let door = m.part_id("dishwasher_door").unwrap();
    for p in m.parts() {
        let want = if p.name() == "dishwasher_rack" {
            Parent::Part(door)
        } else {
            Parent::Base
        };
        assert_eq!(p.parent(), want, "{}", p.name());
    }
    let kind = |part: &str| {
        let id = m.part_id(part).unwrap();
        let joint = &m.joints()[m.part(id).unwrap().joint().index()];
        (joint.kind, joint.name.clone(), joint.limits)
    };
    for door in DOORS.iter().chain(&["dishwasher_door"]) {
        let (k, name, limits) = kind(door);
        assert_eq!((k, name), (JointKind::Revolute, format!("{door}_hinge")));
        assert_eq!(limits.lower, 0.0);
        // Doors open to 90° or 110° (1.92 rad), no further.
        assert!(
            limits.upper >= FRAC_PI_2 - 1e-12 && limits.upper <= 1.92,
            "{door}"
        );
    }
    for drawer in DRAWERS.iter().chain(&["dishwasher_rack"]) {
        let (k, name, limits) = kind(drawer);
        assert_eq!((k, name), (JointKind::Prismatic, format!("{drawer}_slide")));
        assert!(limits.lower == 0.0 && limits.upper <= 0.45, "{drawer}");
    }
    // One handle per part, named after it.
    for part in m.parts() {
        let names: Vec<_> = part.handles().iter().map(|h| h.name.clone()).collect();
        assert_eq!(names, vec![format!("{}_handle", part.name())]);
    }
    assert_eq!(m.handles().count(), 11);
    // Base: floor, 3 walls, left run (carcass, worktop), back run (corner carcass, 4 drawer
    // cabinet panels, sink cabinet, 5 dishwasher tub panels, end cabinet, worktop, sink
    // bowl), 2 wall cabinets, island (core, plinth, 3 panels, worktop): 28 named shapes.
    assert_eq!(m.base().shapes.len(), 28);
    assert!(m.base_shape_id("dishwasher_tub_floor").is_ok());
}

#[test]
fn mesh_colliders_are_loaded_relative_to_the_urdf() {
    let m = kitchen();
    // The sink bowl (meshes/sink_bowl.obj: rim 0.45 × 0.38 at z = 0, bottom at z = -0.19)
    // placed at (1.925, 2.69, 0.91): world x in [1.70, 2.15], z in [0.72, 0.91].
    let bowl = &m.base().shapes[m.base_shape_id("sink_bowl").unwrap().index()];
    let Shape::ConvexMesh { vertices, source } = &bowl.shape else {
        panic!("sink_bowl is a mesh, got {:?}", bowl.shape);
    };
    assert_eq!(source.as_ref().unwrap().uri, "meshes/sink_bowl.obj");
    let world: Vec<_> = vertices.iter().map(|v| bowl.world_from_shape * v).collect();
    let range = |f: fn(&Point3<f64>) -> f64| {
        let lo = world.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = world.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    // mesh-loader reads vertices as f32: coordinates below 0.25 m are off by at most
    // 0.25 · 2^-24 ≈ 1.5e-8 m.
    let close =
        |(a, b): (f64, f64), (c, d): (f64, f64)| (a - c).abs() < 1e-7 && (b - d).abs() < 1e-7;
    assert!(close(range(|p| p.x), (1.70, 2.15)), "{:?}", range(|p| p.x));
    assert!(close(range(|p| p.z), (0.72, 0.91)), "{:?}", range(|p| p.z));

    // The knob of wall_door_tall (meshes/knob.obj: axis +x from 0 to 0.03) sits on its handle
    // link (origin (0.404, -0.015, 0.06) in the door frame, yaw -π/2, so the knob axis is the
    // door's -y) with collision origin x = -0.015: merged into the door, the knob spans door
    // y in [-0.03, 0] (from the door's outer face outwards) and z within 0.06 ± 0.016.
    let door = m.part(m.part_id("wall_door_tall").unwrap()).unwrap();
    let knobs: Vec<_> = door
        .colliders()
        .iter()
        .filter_map(|c| match &c.shape {
            Shape::ConvexMesh { vertices, source } => Some((c, vertices, source)),
            _ => None,
        })
        .collect();
    assert_eq!(knobs.len(), 1, "one mesh collider on wall_door_tall");
    let (collider, vertices, source) = knobs[0];
    assert_eq!(source.as_ref().unwrap().uri, "meshes/knob.obj");
    let in_door: Vec<_> = vertices
        .iter()
        .map(|v| collider.part_from_shape * v)
        .collect();
    let y_lo = in_door.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    let y_hi = in_door
        .iter()
        .map(|p| p.y)
        .fold(f64::NEG_INFINITY, f64::max);
    // Within f32 rounding of the OBJ's coordinates, as for the bowl.
    assert!(
        (y_lo + 0.03).abs() < 1e-7 && y_hi.abs() < 1e-7,
        "{y_lo} {y_hi}"
    );
    assert!(in_door.iter().all(|p| (p.z - 0.06).abs() <= 0.016 + 1e-7));
}

#[test]
fn closed_kitchen_is_collision_free_with_millimetre_gaps() {
    let m = kitchen();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &m.zero_state()).unwrap();
    let settings = CollisionSettings::default();
    assert_eq!(collisions(&m, &data, &settings).unwrap(), vec![]);
    // Closed fronts stand 3 mm proud of their carcasses and adjacent fronts are at least
    // 3 mm apart: no pair is closer than 3 mm (less 0.1 mm for rounding).
    let near = distances(&m, &data, &settings, 0.0029).unwrap();
    assert!(near.is_empty(), "{near:?}");
    // ...and the 3 mm gap is really there, e.g. door A against its carcass (the gap G = 3 mm
    // between the door's back face y = 2.397 and the carcass front y = 2.4).
    let a = m.part_id("corner_door_back").unwrap();
    let carcass = m.base_shape_id("corner_carcass").unwrap();
    let gap = distances(&m, &data, &settings, 0.0031)
        .unwrap()
        .into_iter()
        .find(|c| c.a == Body::Part(a) && c.b == Body::Base(carcass))
        .expect("door A is within 3.1 mm of its carcass");
    assert!((gap.distance - 0.003).abs() < 1e-6, "{}", gap.distance);
}

#[test]
fn every_joint_but_the_rack_opens_fully_in_the_closed_kitchen() {
    let m = kitchen();
    let zero = m.zero_state();
    for joint in m.joints() {
        let status = sweep(&m, &zero, &joint.name);
        if joint.name == "dishwasher_rack_slide" {
            assert!(
                matches!(status, SweepStatus::Collision { .. }),
                "{status:?}"
            );
        } else {
            assert_eq!(status, SweepStatus::Free, "{}", joint.name);
        }
    }
}

/// The dishwasher door's hinge line: world x through (y, z) = (2.377, 0.1) (the joint origin
/// of `dishwasher_door_hinge`, axis +x).
const DW_HINGE_Y: f64 = 2.377;
const DW_HINGE_Z: f64 = 0.1;

/// The rotation by `angle` about the dishwasher door's hinge line, as a world isometry.
fn about_dw_hinge(angle: f64) -> Isometry3<f64> {
    let to_hinge = Translation3::new(0.0, DW_HINGE_Y, DW_HINGE_Z);
    Isometry3::from_parts(to_hinge, UnitQuaternion::identity())
        * Isometry3::from_parts(
            Translation3::identity(),
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), angle),
        )
        * Isometry3::from_parts(to_hinge.inverse(), UnitQuaternion::identity())
}

fn assert_point_close(what: &str, got: &Point3<f64>, want: [f64; 3]) {
    let want = Point3::from(want);
    assert!((got - want).norm() < 1e-12, "{what}: {got} vs {want}");
}

#[test]
fn dishwasher_rack_rides_on_the_door() {
    let m = kitchen();
    let door = m.part_id("dishwasher_door").unwrap();
    let rack = m.part_id("dishwasher_rack").unwrap();
    let handle = m.handle_id("dishwasher_rack_handle").unwrap();
    let mut data = SceneData::new(&m);
    let at = |data: &mut SceneData, values: &[(&str, f64)]| {
        forward_kinematics(&m, data, &state(&m, values)).unwrap();
        (
            *data.world_from_part(door).unwrap(),
            *data.world_from_part(rack).unwrap(),
            world_from_handle(&m, data, handle).unwrap(),
        )
    };

    // Door closed. The rack's frame is its joint origin (0, 0.125, 0.47) in the door frame,
    // whose origin is (2.5, 2.377, 0.1) with the world's axes: (2.5, 2.502, 0.57). The handle's
    // grasp point (0, 0.07, 0.0125) in the rack frame is world (2.5, 2.572, 0.5825), and its
    // normal, the handle link's +x turned by rpy (0, -π/2, 0) (R_y(-π/2) x = +z), points up.
    let (door_0, rack_0, handle_0) = at(&mut data, &[]);
    assert_point_close(
        "rack, door closed",
        &(rack_0 * Point3::origin()),
        [2.5, 2.502, 0.57],
    );
    assert!(rack_0.rotation.angle() < 1e-12);
    assert_point_close(
        "handle, door closed",
        &handle_0.position,
        [2.5, 2.572, 0.5825],
    );
    assert!((handle_0.normal.into_inner() - Vector3::z()).norm() < 1e-12);

    // Door down (90°): the door and everything on it turn by 90° about the hinge line, so
    // world_from_rack(90°) = H(90°) · world_from_rack(0) with H the rotation about the hinge
    // line, the same relation as for the door itself. A door point (y, z) goes to
    // (2.377 - z, 0.1 + y): the rack's origin (0.125, 0.47) to (1.907, 0.225), the grasp point
    // (0.195, 0.4825) to (1.8945, 0.295), and the normal (door +z) to world -y: it faces the
    // room, where a robot grasps it.
    let (door_90, rack_90, handle_90) = at(&mut data, &[("dishwasher_door_hinge", FRAC_PI_2)]);
    let h = about_dw_hinge(FRAC_PI_2);
    assert_pose_close("door about its hinge", &door_90, &(h * door_0));
    assert_pose_close("rack about the door's hinge", &rack_90, &(h * rack_0));
    assert_point_close(
        "rack, door down",
        &(rack_90 * Point3::origin()),
        [2.5, 1.907, 0.225],
    );
    assert_point_close(
        "handle, door down",
        &handle_90.position,
        [2.5, 1.8945, 0.295],
    );
    assert!((handle_90.normal.into_inner() + Vector3::y()).norm() < 1e-12);
    // The rack really moved: its origin, r = |(0.125, 0.47)| ≈ 0.486 m off the hinge line,
    // travels the chord of a quarter turn, sqrt(2) · r ≈ 0.688 m.
    let travel = (rack_90.translation.vector - rack_0.translation.vector).norm();
    assert!(
        (travel - 2f64.sqrt() * (0.125f64.hypot(0.47))).abs() < 1e-12,
        "{travel}"
    );

    // Sliding with the door down moves it along the door, out towards the room (world -y):
    // fully out (0.30 m) the origin is at y = 1.907 - 0.30 = 1.607 and the grasp point at
    // 1.8945 - 0.30 = 1.5945; with the door closed the same slide is straight up.
    let (_, rack_out, handle_out) = at(
        &mut data,
        &[
            ("dishwasher_door_hinge", FRAC_PI_2),
            ("dishwasher_rack_slide", 0.3),
        ],
    );
    assert_point_close(
        "rack out, door down",
        &(rack_out * Point3::origin()),
        [2.5, 1.607, 0.225],
    );
    assert_point_close("handle out", &handle_out.position, [2.5, 1.5945, 0.295]);
    let (_, rack_up, _) = at(&mut data, &[("dishwasher_rack_slide", 0.1)]);
    assert_point_close(
        "rack up, door closed",
        &(rack_up * Point3::origin()),
        [2.5, 2.502, 0.67],
    );
}

#[test]
fn closed_dishwasher_holds_the_rack_in_its_tub() {
    let m = kitchen();
    let rack = m.part_id("dishwasher_rack").unwrap();
    let door = m.part_id("dishwasher_door").unwrap();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &m.zero_state()).unwrap();
    // Closed, the basket spans world y in [2.402, 2.602], z in [0.21, 0.57] (door y in
    // [0.025, 0.225], z in [0.11, 0.47], plus the door origin (2.377, 0.1)) and x in
    // [2.24, 2.76]; its handle bar reaches z = 0.595. The nearest base shape is the tub
    // floor (top z = 0.20): 10 mm below it; the tub walls (x <= 2.22, x >= 2.78) are 20 mm
    // away and the tub top (z >= 0.82) 0.225 m. Nothing else is within 10 mm.
    let settings = CollisionSettings::default();
    let near: Vec<_> = distances(&m, &data, &settings, 0.0101)
        .unwrap()
        .into_iter()
        .filter(|c| c.a == Body::Part(rack) || c.b == Body::Part(rack))
        .collect();
    let floor = m.base_shape_id("dishwasher_tub_floor").unwrap();
    assert_eq!(near.len(), 1, "{near:?}");
    assert_eq!(
        (near[0].a, near[0].b),
        (Body::Part(rack), Body::Base(floor))
    );
    assert!(
        (near[0].distance - 0.010).abs() < 1e-9,
        "{}",
        near[0].distance
    );
    // It sits behind the closed door: 5 mm behind the door's inner face (basket at door
    // y >= 0.025, the door slab at y <= 0.02). That pair is parent–child, not checked by
    // default; checking it shows the gap.
    let with_parent = CollisionSettings {
        check_parent_child: true,
        ..CollisionSettings::default()
    };
    let gap = distances(&m, &data, &with_parent, 0.0051)
        .unwrap()
        .into_iter()
        .find(|c| [c.a, c.b].contains(&Body::Part(rack)) && [c.a, c.b].contains(&Body::Part(door)))
        .expect("the rack is within 5.1 mm of its door");
    assert!((gap.distance - 0.005).abs() < 1e-9, "{}", gap.distance);
}

#[test]
fn dishwasher_rack_slides_out_only_with_the_door_open() {
    let m = kitchen();
    // Door closed: the rack's slide (door +z) points straight up. Its handle bar is the
    // highest point, top z = 0.1 + 0.47 + 0.025 = 0.595, under the tub's top panel
    // dishwasher_tub_top (underside z = 0.87 - 0.05 = 0.82, spanning x in [2.22, 2.78] and
    // y in [2.40, 2.96], over the bar at x in [2.35, 2.65], y in [2.566, 2.578]). The bar
    // meets it after 0.82 - 0.595 = 0.225 m of the 0.30 m stroke. The sweep reports the
    // first colliding sample, at most one finest interval (2 · min_margin / L = 2e-4 m,
    // L = 1 for a prismatic joint) past it.
    let closed = sweep(&m, &m.zero_state(), "dishwasher_rack_slide");
    let (value, parts) =
        collision_parts(&m, &closed).expect("the tub top blocks the rack behind the closed door");
    assert_eq!(parts, set(&["dishwasher_rack", "dishwasher_tub_top"]));
    assert!(
        (0.225 - 1e-9..=0.225 + 2e-4 + 1e-9).contains(&value),
        "{value}"
    );

    // The door opens fully with the rack in (the rack turns with it): every rack point is at
    // most 0.534 m from the hinge line (handle corner, door (y, z) = (0.201, 0.495)), so it
    // stays below the tub top (0.72 above the hinge line), and it only rises while over the
    // tub floor, which it starts 10 mm above.
    assert_eq!(
        sweep(&m, &m.zero_state(), "dishwasher_door_hinge"),
        SweepStatus::Free
    );

    // Door down (90°): the rack lies on the door, basket z in [0.125, 0.325] (door y in
    // [0.025, 0.225] plus the hinge height 0.1), above the door slab (z <= 0.12) and the
    // floor, and slides out along world -y. The whole stroke is free: fully out its handle
    // reaches y = 2.377 - (0.495 + 0.30) = 1.582, 32 mm short of the island core (y <= 1.55),
    // the only base shape ahead of it at that height.
    let open = state(&m, &[("dishwasher_door_hinge", FRAC_PI_2)]);
    assert_eq!(sweep(&m, &open, "dishwasher_rack_slide"), SweepStatus::Free);
    let out = state(
        &m,
        &[
            ("dishwasher_door_hinge", FRAC_PI_2),
            ("dishwasher_rack_slide", 0.3),
        ],
    );
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &out).unwrap();
    let settings = CollisionSettings::default();
    assert_eq!(collisions(&m, &data, &settings).unwrap(), vec![]);
    let rack = m.part_id("dishwasher_rack").unwrap();
    let core = m.base_shape_id("island_core").unwrap();
    let to_core = distances(&m, &data, &settings, 0.033)
        .unwrap()
        .into_iter()
        .find(|c| c.a == Body::Part(rack) && c.b == Body::Base(core))
        .expect("the rack out is within 33 mm of the island core");
    assert!(
        (to_core.distance - 0.032).abs() < 1e-9,
        "{}",
        to_core.distance
    );

    // Partly open. At 10° the rack fully out would put the basket's far back corner, door
    // (y, z) = (0.225, 0.77), at hinge offsets (0.225 cos 10° - 0.77 sin 10°,
    // 0.225 sin 10° + 0.77 cos 10°) = (0.088, 0.797): world y = 2.465, z = 0.897, inside the
    // worktop (y >= 2.38, z in [0.87, 0.91]); the stroke is blocked by the counter (the tub
    // top or the worktop, whichever the rack reaches first).
    let ten = state(&m, &[("dishwasher_door_hinge", 10f64.to_radians())]);
    let (_, parts) = collision_parts(&m, &sweep(&m, &ten, "dishwasher_rack_slide"))
        .expect("at 10° the counter blocks the rack");
    assert!(parts.contains("dishwasher_rack"), "{parts:?}");
    assert!(
        parts.contains("dishwasher_tub_top") || parts.contains("back_run_worktop"),
        "{parts:?}"
    );
    // At 30° the whole stroke is free. A rack point at door (y, z), y in [0.025, 0.225],
    // z in [0.11, 0.795] over the stroke, is at hinge offsets
    // (dy, dz) = (y cos 30° - z sin 30°, y sin 30° + z cos 30°). Reaching the tub top or the
    // worktop needs dz >= 0.72, i.e. z >= (0.72 - y/2) / cos 30°, and then
    // dy <= y cos 30° - (0.72 - y/2) tan 30° = 1.1547 y - 0.4157 <= -0.156: in front of both
    // (they start at dy >= 0.003). Over the tub floor (dy >= 0.023) dz >= 0.025/2 +
    // 0.11 cos 30° = 0.108 > 0.10, above it; dy >= 0.025 cos 30° - 0.795/2 = -0.376 keeps it
    // off the island core (dy <= -0.827).
    let thirty = state(&m, &[("dishwasher_door_hinge", 30f64.to_radians())]);
    assert_eq!(
        sweep(&m, &thirty, "dishwasher_rack_slide"),
        SweepStatus::Free
    );

    // With the rack out, the door cannot close: the basket's back face (door y = 0.225)
    // swings into the worktop's front bottom edge, hinge offsets (dy, dz) = (2.38 - 2.377,
    // 0.87 - 0.1) = (0.003, 0.77) at radius r = |(0.003, 0.77)|. The face point at that radius
    // is door (0.225, sqrt(r² - 0.225²)), so they meet at the door angle
    // atan2(0.77, 0.003) - atan2(sqrt(r² - 0.225²), 0.225) ≈ 16.77°. Closing from 90°, the
    // sweep reports the first colliding sample, at most one finest interval
    // 2 · min_margin / L <= 2e-4 / 0.77 rad below that (L >= 0.77 m, the radius of the
    // contact point).
    let id = m.joint_id("dishwasher_door_hinge").unwrap();
    let back = check_joint_motion(
        &m,
        &mut data,
        &out,
        id,
        FRAC_PI_2,
        0.0,
        &SweepSettings::default(),
    )
    .unwrap();
    let (value, parts) = collision_parts(&m, &back.status).expect("the rack blocks the door");
    assert_eq!(parts, set(&["dishwasher_rack", "back_run_worktop"]));
    let r = 0.003f64.hypot(0.77);
    let contact = 0.77f64.atan2(0.003) - (r * r - 0.225 * 0.225).sqrt().atan2(0.225);
    assert!(
        (contact - 2e-4 / 0.77 - 1e-9..=contact + 1e-9).contains(&value),
        "{value} vs {contact}"
    );
}

#[test]
fn corner_doors_open_alone_but_not_together() {
    let m = kitchen();
    let zero = m.zero_state();
    // Each alone, the other closed: free (A's sweep stays at x >= 0.75 - 0.035 = 0.715, beyond
    // B's closed handle at x <= 0.658; B's at y <= 2.25 + 0.035 = 2.285, below A's closed
    // handle at y >= 2.342).
    assert_eq!(
        sweep(&m, &zero, "corner_door_back_hinge"),
        SweepStatus::Free
    );
    assert_eq!(
        sweep(&m, &zero, "corner_door_side_hinge"),
        SweepStatus::Free
    );
    // A open at 90° lies along x in [0.75, 0.77], y in [1.977, 2.377]; B open lies along
    // y in [2.23, 2.25], x in [0.623, 1.073]: the two slabs cross, so neither door can open
    // fully while the other is open.
    let a_open = state(&m, &[("corner_door_back_hinge", FRAC_PI_2)]);
    let b_open = state(&m, &[("corner_door_side_hinge", FRAC_PI_2)]);
    let both = set(&["corner_door_back", "corner_door_side"]);
    let b_sweep = sweep(&m, &a_open, "corner_door_side_hinge");
    assert_eq!(
        collision_parts(&m, &b_sweep).map(|c| c.1),
        Some(both.clone())
    );
    let a_sweep = sweep(&m, &b_open, "corner_door_back_hinge");
    assert_eq!(collision_parts(&m, &a_sweep).map(|c| c.1), Some(both));
    let mut data = SceneData::new(&m);
    let both_open = state(
        &m,
        &[
            ("corner_door_back_hinge", FRAC_PI_2),
            ("corner_door_side_hinge", FRAC_PI_2),
        ],
    );
    forward_kinematics(&m, &mut data, &both_open).unwrap();
    assert!(
        !collisions(&m, &data, &CollisionSettings::default())
            .unwrap()
            .is_empty()
    );
}

#[test]
fn sink_door_opens_past_90_degrees_only_with_the_drawers_in() {
    let m = kitchen();
    // D1 pulled out 0.45 m: its front spans y in [1.927, 1.947], x up to 1.647. S (hinge at
    // x = 1.653) stays at x >= 1.653 up to 90°, so that part of its stroke is free; past 90°
    // its free edge swings to x < 1.653 through the drawer's front.
    let d1_out = state(&m, &[("drawer_top_slide", 0.45)]);
    let id = m.joint_id("sink_door_hinge").unwrap();
    let mut data = SceneData::new(&m);
    let settings = SweepSettings::default();
    let to_90 = check_joint_motion(&m, &mut data, &d1_out, id, 0.0, FRAC_PI_2, &settings).unwrap();
    assert_eq!(to_90.status, SweepStatus::Free);
    let full = sweep(&m, &d1_out, "sink_door_hinge");
    let (value, parts) = collision_parts(&m, &full).expect("the open drawer stops the door");
    assert_eq!(parts, set(&["sink_door", "drawer_top"]));
    assert!(value > FRAC_PI_2, "{value}");
}

/// Occupied cells whose centres lie in the passage strip along the island: x in [1.5, 3.0],
/// y in (1.6, 2.3). The strip is clear of the island worktop (back edge y = 1.57) and of the
/// closed back-run fronts with their handles (y >= 2.4 - 0.003 - 0.02 - 0.035 = 2.342), so
/// a part occupies it only when it is open.
fn passage_cells(grid: &NavGrid) -> BTreeSet<(usize, usize)> {
    grid.occupied_cells()
        .filter(|&(i, j)| {
            let c = grid.cell_center(i, j);
            (1.5..=3.0).contains(&c.x) && c.y > 1.6 && c.y < 2.3
        })
        .collect()
}

#[test]
fn open_sink_door_blocks_the_passage() {
    let m = kitchen();
    let mut data = SceneData::new(&m);
    forward_kinematics(&m, &mut data, &m.zero_state()).unwrap();
    let closed_footprint = footprint(&m, &data).unwrap();
    let closed = occupancy(&m, &data).unwrap();
    forward_kinematics(&m, &mut data, &state(&m, &[("sink_door_hinge", FRAC_PI_2)])).unwrap();
    let open_footprint = footprint(&m, &data).unwrap();
    let open = occupancy(&m, &data).unwrap();

    // Open at 90°, S lies along x in [1.653, 1.673] from y = 2.377 down to
    // 2.377 - 0.544 = 1.833 (its handle to x = 1.618): it occupies cells of the passage, all
    // with centres at x in [1.60, 1.70] (the door and its handle touch the columns
    // [1.60, 1.65] and [1.65, 1.70] of the 5 cm grid) and y > 1.8.
    assert_eq!(passage_cells(&closed_footprint), BTreeSet::new());
    let added = passage_cells(&open_footprint);
    assert!(!added.is_empty());
    for &(i, j) in &added {
        let c = open_footprint.cell_center(i, j);
        assert!((1.60..=1.70).contains(&c.x) && c.y > 1.8, "{c:?}");
    }

    // The passage is then too narrow for a disc robot of radius 0.15 m: between the island
    // worktop (y = 1.57) and the open door (y = 1.833) there are 0.263 m < 2 · 0.15 m. With
    // the door closed, the 0.81 m between the worktops leave room.
    let robot_radius = 0.15;
    let column = closed.cell_of(Point2::new(1.663, 2.0)).unwrap().0;
    let free_in_column = |grid: &NavGrid| {
        let inflated = grid.inflate(robot_radius).unwrap();
        (0..grid.height())
            .filter(|&j| {
                let y = grid.cell_center(column, j).y;
                y > 1.57 && y < 2.38 && !inflated.is_occupied(column, j)
            })
            .count()
    };
    assert!(free_in_column(&closed) > 0);
    assert_eq!(free_in_column(&open), 0);
}

/// Poses agree: translations within 1e-12 m (they are written with shortest round-trip
/// formatting, so in practice exactly), rotations within 1e-9 rad (the exporter writes `rpy`
/// on a 1e-12 rad grid, about 1e-11 rad on the rotation; see `scene::urdf`).
fn assert_pose_close(what: &str, a: &Isometry3<f64>, b: &Isometry3<f64>) {
    let dt = (a.translation.vector - b.translation.vector).norm();
    let angle = a.rotation.rotation_to(&b.rotation).angle();
    assert!(dt <= 1e-12 && angle <= 1e-9, "{what}: {a:?} vs {b:?}");
}

/// The two models describe the same scene: names, tree, kinds, limits and shapes exactly;
/// poses, axes and normals within the tolerances of [`assert_pose_close`].
fn assert_same_scene(a: &SceneModel, b: &SceneModel) {
    let (a, b) = (a.to_builder(), b.to_builder());
    assert_eq!(a.base.name, b.base.name);
    assert_eq!(a.base.nav, b.base.nav);
    assert_eq!(a.base.shapes.len(), b.base.shapes.len());
    for (x, y) in a.base.shapes.iter().zip(&b.base.shapes) {
        assert_eq!((&x.name, &x.shape), (&y.name, &y.shape));
        assert_pose_close(&x.name, &x.world_from_shape, &y.world_from_shape);
    }
    assert_eq!(a.parts.len(), b.parts.len());
    for (x, y) in a.parts.iter().zip(&b.parts) {
        let (jx, jy) = (&x.joint, &y.joint);
        assert_eq!((&x.name, &x.parent), (&y.name, &y.parent));
        assert_eq!(
            (&jx.name, jx.kind, jx.limits, jx.continuous),
            (&jy.name, jy.kind, jy.limits, jy.continuous)
        );
        assert!((jx.axis - jy.axis).norm() <= 1e-12, "{}", jx.name);
        assert_pose_close(&jx.name, &jx.parent_from_joint, &jy.parent_from_joint);
        assert_eq!(x.colliders.len(), y.colliders.len());
        for (cx, cy) in x.colliders.iter().zip(&y.colliders) {
            assert_eq!(cx.shape, cy.shape, "{}", x.name);
            assert_pose_close(&x.name, &cx.part_from_shape, &cy.part_from_shape);
        }
        assert_eq!(x.handles.len(), y.handles.len());
        for (hx, hy) in x.handles.iter().zip(&y.handles) {
            assert_eq!(hx.name, hy.name);
            assert!((hx.position - hy.position).norm() <= 1e-12, "{}", hx.name);
            assert!((hx.normal - hy.normal).norm() <= 1e-9, "{}", hx.name);
        }
    }
}

#[test]
fn kitchen_exports_and_reimports_equal() {
    let m = kitchen();
    let xml = urdf::write_string(&m, &ExportOptions::default()).unwrap();
    // The meshes keep their relative references, resolved against the scene directory.
    let options = ImportOptions {
        base_dir: Some(scenes_dir()),
        ..ImportOptions::default()
    };
    let again = urdf::read_str(&xml, &options).unwrap();
    assert_same_scene(&m, &again);
    // The model's behaviour survives too: the designed rack/door interaction, for one (the
    // rack still rides on the door, and behind the closed door the tub top stops it).
    let rack = again
        .part(again.part_id("dishwasher_rack").unwrap())
        .unwrap();
    assert_eq!(
        rack.parent(),
        Parent::Part(again.part_id("dishwasher_door").unwrap())
    );
    let closed = sweep(&again, &again.zero_state(), "dishwasher_rack_slide");
    assert_eq!(
        collision_parts(&again, &closed).map(|c| c.1),
        Some(set(&["dishwasher_rack", "dishwasher_tub_top"]))
    );
    // And the exported text is a fixed point: exporting the re-imported model gives it back.
    assert_eq!(
        urdf::write_string(&again, &ExportOptions::default()).unwrap(),
        xml
    );
}

#[test]
fn path_to_base_follows_the_urdf_tree() {
    // The URDF header's tree: the rack rides on the dishwasher door, which is on the base.
    let model = kitchen();
    let names = |part: &str| -> Vec<String> {
        let id = model
            .parts()
            .iter()
            .find(|p| p.name() == part)
            .expect("the header lists this part")
            .id();
        model
            .path_to_base(id)
            .map(|p| model.part(p).unwrap().name().to_string())
            .collect()
    };
    assert_eq!(
        names("dishwasher_rack"),
        ["dishwasher_rack", "dishwasher_door"]
    );
    assert_eq!(names("sink_door"), ["sink_door"]);
}

#[test]
fn handles_stand_off_their_fronts_by_half_a_bar() {
    // Every bar handle of the kitchen is a box 0.035 m proud of its front, its grasp point (the
    // handle link's origin) at the bar's centre: the front is 0.0175 m behind the grasp point.
    // The bar holds the grasp point 6 mm inside (half its 12 mm width), so it is passed
    // through as the handle's own geometry.
    let m = kitchen();
    for name in [
        "sink_door_handle",
        "drawer_top_handle",
        "corner_door_side_handle",
    ] {
        let h = m.handle_id(name).unwrap();
        let d = handle_standoff(&m, h, 0.2).unwrap();
        assert!(
            d.is_some_and(|d| (d - 0.0175).abs() < 1e-9),
            "{name}: {d:?}"
        );
    }
    // Searched only up to `max`: nothing within 1 cm.
    let h = m.handle_id("sink_door_handle").unwrap();
    assert_eq!(handle_standoff(&m, h, 0.01).unwrap(), None);
}

#[test]
fn a_grasp_point_on_the_face_stands_off_by_nothing_and_a_bare_handle_has_no_front() {
    use kinscene::scene::{Handle, Joint, Limits, PartSpec, SceneModelBuilder};
    // A 2 cm slab spanning x in [-0.01, 0.01] of its part frame. Handle `face` on its -x face
    // (x = -0.01), normal -x: on the surface, standoff 0. Handle `air` 0.02 m in front of the
    // face: standoff 0.02 (no bar to pass through). Part `knob` is only a 2 cm cube around
    // its handle: nothing behind it, `None`.
    let slab = Shape::cuboid(Vector3::new(0.01, 0.2, 0.3));
    let mut b = SceneModelBuilder::new();
    b.add_part(
        PartSpec::on_base(
            "slab",
            Joint::prismatic(
                "slide",
                Point3::origin(),
                -Vector3::x(),
                Limits::new(0.0, 0.3),
            ),
        )
        .with_collider(slab, Isometry3::identity())
        .with_handle(Handle::new(
            "face",
            Point3::new(-0.01, 0.0, 0.0),
            -Vector3::x(),
        ))
        .with_handle(Handle::new(
            "air",
            Point3::new(-0.03, 0.1, 0.0),
            -Vector3::x(),
        )),
    );
    b.add_part(
        PartSpec::on_base(
            "knob",
            Joint::prismatic(
                "knob_slide",
                Point3::new(0.0, 2.0, 0.0),
                -Vector3::x(),
                Limits::new(0.0, 0.1),
            ),
        )
        .with_collider(Shape::cuboid(Vector3::repeat(0.01)), Isometry3::identity())
        .with_handle(Handle::new("knob_handle", Point3::origin(), -Vector3::x())),
    );
    let m = b.build().unwrap();
    let standoff = |name: &str| handle_standoff(&m, m.handle_id(name).unwrap(), 0.2).unwrap();
    assert!(
        standoff("face").is_some_and(|d| d.abs() < 1e-9),
        "{:?}",
        standoff("face")
    );
    assert!(
        standoff("air").is_some_and(|d| (d - 0.02).abs() < 1e-9),
        "{:?}",
        standoff("air")
    );
    assert_eq!(standoff("knob_handle"), None);
}
