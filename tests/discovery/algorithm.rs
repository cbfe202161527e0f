//! Algorithm 1 against the test world: one door, one drawer, an injected grasp failure, a
//! handle with nothing behind it, a mapped handle that is not there, and the URDF round trip of
//! the discovered scene.

use std::f64::consts::FRAC_PI_2;

use kinscene::articulation::{
    ArticulationEstimator, Proprioceptive, TwoView, axis_angle_error, axis_position_error,
};
use kinscene::discovery::{
    AttemptEnd, Discovery, DiscoveryError, DiscoverySettings, Exploration, FusionSettings,
    HardwareFailure, MappedHandle, MotionClass, Perception, RegistrationSettings, Stage, discover,
    fuse_detections, register_handles,
};
use kinscene::scene::{JointKind, SceneModel, Shape, urdf};
use nalgebra::{Isometry2, Point2, Point3, Vector2, Vector3};

use super::scenes::{
    DOOR_AXIS, DOOR_PIVOT, DRAWER_AXIS, door_cabinet, door_with_tray, drawer_cabinet,
    hollow_drawer_cabinet,
};
use super::world::{World, WorldSettings};

/// The robot starts 1.5 m in front of the cabinet, facing it (+y).
pub(super) fn start() -> Isometry2<f64> {
    Isometry2::new(Vector2::new(0.3, -1.5), FRAC_PI_2)
}

/// Mapping from the start pose: one view, fused and registered.
pub(super) fn map(world: &mut World) -> Vec<MappedHandle> {
    let view = world.detect_handles().unwrap();
    let fused = fuse_detections(&[view], &FusionSettings::default()).unwrap();
    register_handles(&fused, world.model.base(), &RegistrationSettings::default())
        .unwrap()
        .handles
}

fn run(
    truth: SceneModel,
    estimator: &dyn ArticulationEstimator,
    seed: u64,
    setup: impl FnOnce(&mut World),
) -> (World, Discovery) {
    // Without the gravity prior, so that the axis checks measure the estimator (the test
    // scenes' axes are level, so the prior would make every one exact).
    let settings = DiscoverySettings {
        axis_snap: 0.0,
        ..DiscoverySettings::default()
    };
    run_with(truth, estimator, seed, setup, &settings)
}

pub(super) fn run_with(
    truth: SceneModel,
    estimator: &dyn ArticulationEstimator,
    seed: u64,
    setup: impl FnOnce(&mut World),
    settings: &DiscoverySettings,
) -> (World, Discovery) {
    let mut world = World::new(truth, start(), WorldSettings::default(), seed);
    setup(&mut world);
    let handles = map(&mut world);
    assert_eq!(handles.len(), 1 + world.fixed_handles.len());
    let base = world.model.base().clone();
    let d = discover(&mut world, &base, &handles, estimator, settings).unwrap();
    (world, d)
}

/// Checks the one registered joint against the truth: kind, axis within `max_deg` degrees, and
/// for a revolute joint the axis line within `max_pivot` metres.
pub(super) fn check_joint(
    d: &Discovery,
    kind: JointKind,
    axis: [f64; 3],
    pivot: Option<[f64; 3]>,
    max_deg: f64,
    max_pivot: f64,
) {
    assert!(d.log[0].succeeded(), "{:#?}", d.log[0]);
    assert_eq!(d.model.nq(), 1);
    let joint = &d.model.joints()[0];
    assert_eq!(joint.kind, kind, "{:#?}", d.log[0]);
    // Parts on the base: the joint frame is the world frame translated, so axis and origin
    // are map-frame quantities.
    let est_axis = joint.parent_from_joint.rotation * joint.axis;
    let err = axis_angle_error(&est_axis, &Vector3::from(axis));
    assert!(
        err <= max_deg,
        "axis error {err}° > {max_deg}°: {:#?}",
        d.log[0]
    );
    // Opening is positive: the estimated axis points the same way as the truth (both open
    // towards the robot).
    assert!(est_axis.dot(&Vector3::from(axis)) > 0.0);
    if let Some(p) = pivot {
        let origin = Point3::from(joint.parent_from_joint.translation.vector);
        let e = axis_position_error(&origin, &est_axis, &Point3::from(p), &Vector3::from(axis));
        assert!(e <= max_pivot, "axis position error {e} m > {max_pivot} m");
    }
    assert_eq!(joint.limits.lower, 0.0);
    let default_upper = match kind {
        JointKind::Revolute => 1.57,
        JointKind::Prismatic => 0.4,
    };
    assert!(joint.limits.upper >= default_upper);
    // The registered handle is at the contact, with an outward normal facing the robot (-y)
    // in the closed pose.
    let part = &d.model.parts()[0];
    assert_eq!(part.handles().len(), 1);
    assert!(part.handles()[0].normal.dot(&-Vector3::y()) > 0.95);
    assert_eq!(part.colliders().len(), 1);
}

// Tolerances: the estimators' targets at σ = 5 mm are ≤ 2° axis error and ≤ 2 cm pivot
// error; the test world's depth noise is 2 mm, so 3° and 3 cm leave margin for the
// exploration (the post-interaction view is taken from farther back than the pre view).

#[test]
fn one_door_is_discovered_as_revolute_two_view() {
    let (world, d) = run(door_cabinet(), &TwoView::default(), 7, |_| {});
    check_joint(
        &d,
        JointKind::Revolute,
        DOOR_AXIS,
        Some(DOOR_PIVOT),
        3.0,
        0.03,
    );
    // The door is hinged on the robot's left: the tracked plane turns clockwise seen from
    // above.
    assert_eq!(d.log[0].attempts[0].motion, MotionClass::RevoluteLeft);
    // The door was really opened, and the model's state says by about as much.
    let truth = world.state.as_slice()[0];
    assert!(truth > 0.3, "door opened {truth} rad");
    assert!(
        (d.state.as_slice()[0] - truth).abs() < 0.05,
        "{} vs {truth}",
        d.state.as_slice()[0]
    );
    assert!(d.log[0].pull_distance >= DiscoverySettings::default().target_pull - 1e-9);
}

/// With the default gravity prior (10°) the same door's registered hinge is exactly
/// vertical, pointing the way the estimate did (down: the truth, −z), through the same foot
/// point; the log keeps the estimator's own, tilted axis and the note says how far off it was.
#[test]
fn the_gravity_prior_makes_a_nearly_vertical_hinge_vertical() {
    let (_, d) = run_with(
        door_cabinet(),
        &TwoView::default(),
        7,
        |_| {},
        &DiscoverySettings::default(),
    );
    check_joint(
        &d,
        JointKind::Revolute,
        DOOR_AXIS,
        Some(DOOR_PIVOT),
        1e-9,
        0.03,
    );
    let joint = &d.model.joints()[0];
    let axis = joint.parent_from_joint.rotation * joint.axis;
    assert_eq!(axis, Vector3::new(0.0, 0.0, -1.0));
    let raw = d.log[0].estimate.as_ref().and_then(|e| e.axis).unwrap();
    let off = axis_angle_error(&raw, &Vector3::from(DOOR_AXIS));
    assert!(off > 0.0 && off < 3.0, "the estimate is {off}° off");
    let note = d.log[0]
        .notes
        .iter()
        .find(|n| n.contains("gravity prior"))
        .expect("the levelling is noted");
    assert!(note.contains(&format!("{off:.1}°")), "{note} vs {off}");
}

#[test]
fn one_door_is_discovered_as_revolute_proprioceptive() {
    let (_, d) = run(door_cabinet(), &Proprioceptive::default(), 8, |_| {});
    check_joint(
        &d,
        JointKind::Revolute,
        DOOR_AXIS,
        Some(DOOR_PIVOT),
        3.0,
        0.03,
    );
    // Proprioception gives no segmentation: the collider comes from the motion-consistency
    // fallback, noted in the log.
    assert!(!d.log[0].notes.is_empty());
}

#[test]
fn one_drawer_is_discovered_as_prismatic() {
    for (k, est) in [
        &TwoView::default() as &dyn ArticulationEstimator,
        &Proprioceptive::default(),
    ]
    .into_iter()
    .enumerate()
    {
        let (world, d) = run(drawer_cabinet(), est, 11 + k as u64, |_| {});
        check_joint(&d, JointKind::Prismatic, DRAWER_AXIS, None, 3.0, 0.0);
        assert_eq!(d.log[0].attempts[0].motion, MotionClass::Prismatic);
        let truth = world.state.as_slice()[0];
        assert!(
            (d.state.as_slice()[0] - truth).abs() < 0.03,
            "{} vs {truth}",
            d.state.as_slice()[0]
        );
    }
}

/// In a hollow carcass the registered drawer gets a body behind its front (the camera never
/// sees it): as deep as the upper limit (0.4 m), inside the cavity (x in [0.02, 0.58], y in
/// [0, 0.46], z in [0.05, 0.75], from the scene's panels), so the closed scene stays
/// collision-free; in the solid carcass of the other drawer tests there is no room for one,
/// and the log says so.
#[test]
fn a_drawer_in_a_hollow_carcass_gets_a_body() {
    let (_, d) = run_with(
        hollow_drawer_cabinet(),
        &TwoView::default(),
        11,
        |_| {},
        &DiscoverySettings::default(),
    );
    assert!(d.log[0].succeeded(), "{:#?}", d.log[0]);
    assert!(
        d.log[0]
            .notes
            .iter()
            .any(|n| n.contains("drawer body modelled")),
        "{:#?}",
        d.log[0].notes
    );
    let part = &d.model.parts()[0];
    let joint = &d.model.joints()[0];
    assert!(joint.limits.upper >= 0.4);
    // Parts on the base: world = joint frame at value 0.
    let world_from_part = joint.parent_from_joint;
    let body = part
        .colliders()
        .iter()
        .map(|c| {
            let Shape::Cuboid { half_extents } = c.shape else {
                panic!("a box part: {:?}", c.shape)
            };
            let pose = world_from_part * c.part_from_shape;
            let r = pose.rotation.to_rotation_matrix();
            let ext: Vector3<f64> = r.matrix().abs() * half_extents;
            (pose.translation.vector - ext, pose.translation.vector + ext)
        })
        .find(|(lo, _)| lo.y > 0.0)
        .expect("a box behind the front");
    let (lo, hi) = body;
    assert!(hi.y - lo.y > 0.39, "body {lo:?}..{hi:?}");
    assert!(lo.x >= 0.02 && hi.x <= 0.58, "body {lo:?}..{hi:?}");
    assert!(lo.y >= 0.0 && hi.y <= 0.46, "body {lo:?}..{hi:?}");
    assert!(lo.z >= 0.05 && hi.z <= 0.75, "body {lo:?}..{hi:?}");
    assert!(d.reconciliation.unresolved.is_empty());

    let (_, solid) = run_with(
        drawer_cabinet(),
        &TwoView::default(),
        11,
        |_| {},
        &DiscoverySettings::default(),
    );
    assert!(
        solid.log[0]
            .notes
            .iter()
            .any(|n| n.contains("no drawer body modelled")),
        "{:#?}",
        solid.log[0].notes
    );
    assert_eq!(solid.model.parts()[0].colliders().len(), 1);
}

#[test]
fn an_injected_grasp_failure_is_repositioned_and_retried() {
    // Algorithm 1's attempts alone: no further pulls after the successful one (the two-view
    // drawer estimate's 95 % regions are wider than the confidence limits).
    let settings = DiscoverySettings {
        axis_snap: 0.0,
        max_extra_pulls: 0,
        ..DiscoverySettings::default()
    };
    let (world, d) = run_with(
        drawer_cabinet(),
        &TwoView::default(),
        21,
        |w| w.grasp_failures = 1,
        &settings,
    );
    let log = &d.log[0];
    assert!(log.succeeded(), "{log:#?}");
    assert_eq!(log.attempts.len(), 2);
    assert_eq!(
        log.attempts[0].end,
        AttemptEnd::Grasp {
            failure: HardwareFailure::GraspLost
        }
    );
    assert!(log.attempts[1].end.is_success());
    assert_eq!(world.grasps, 2);
    assert_eq!(d.model.joints()[0].kind, JointKind::Prismatic);
}

#[test]
fn a_refused_navigation_goal_is_not_tried_again() {
    // A chair the base map does not hold stands 0.55 m in front of the drawer's handle (world
    // (0.3, -0.05), scenes.rs), where the robot would stand to pull (interaction distance
    // 0.6 m): the test world's navigation refuses every goal within 0.02 + 0.25 m of it. The
    // global approach (0.9 m out) is 0.35 m from it and free. Hand-derived: PlanBase's
    // candidates at the same 0.6 m are turned in 10° steps, 2 · 0.6 · sin(θ/2) from the
    // refused goal: 0.10 and 0.21 m at 10° and 20° (within the 0.3 m robot radius of
    // discovery's settings), 0.31 m at 30°, which lies (±0.30, -0.52) from the handle against
    // the chair's (0, -0.55): 0.30 m > 0.27 m, free. Before refused goals were avoided, all
    // three attempts went to the same goal and the drawer was a navigation failure.
    let settings = DiscoverySettings {
        axis_snap: 0.0,
        max_extra_pulls: 0,
        ..DiscoverySettings::default()
    };
    let (_, d) = run_with(
        drawer_cabinet(),
        &TwoView::default(),
        23,
        |w| w.unmapped.push((Point2::new(0.3, -0.6), 0.02)),
        &settings,
    );
    let log = &d.log[0];
    assert!(log.succeeded(), "{log:#?}");
    assert!(
        matches!(log.attempts[0].end, AttemptEnd::Navigation { .. }),
        "{:?}",
        log.attempts[0].end
    );
    let first = log.attempts[0].world_from_base.translation.vector;
    let second = log.attempts[1].world_from_base.translation.vector;
    assert!((second - first).norm() >= settings.robot_radius - 1e-9);
    assert!(
        log.attempts[1].end.is_success(),
        "{:?}",
        log.attempts[1].end
    );
    assert!(log.notes.iter().any(|n| n.contains("navigation refused")));
    assert_eq!(d.model.joints()[0].kind, JointKind::Prismatic);
}

/// The drawer discovered (two-view, seed 22) by an arm that cannot bring the gripper closer
/// than 45 cm to the base centre.
fn reach_limited_drawer(settings: &DiscoverySettings) -> Discovery {
    run_with(
        drawer_cabinet(),
        &TwoView::default(),
        22,
        |w| w.settings.min_reach = 0.45,
        settings,
    )
    .1
}

/// The arm cannot bring the gripper closer than 45 cm to the base centre: pulling the drawer
/// towards the robot standing 60 cm away stops after 15 cm with `SelfCollision`. With
/// `sufficient_pull` at 20 cm that is a failure; the motion seen is prismatic, so Reposition
/// moves the base 30 cm straight back and the second attempt completes the 30 cm pull.
#[test]
fn a_prismatic_self_collision_repositions_the_base_back() {
    // Algorithm 1's attempts alone, without further pulls (as above).
    let settings = DiscoverySettings {
        sufficient_pull: 0.2,
        max_extra_pulls: 0,
        ..DiscoverySettings::default()
    };
    let d = reach_limited_drawer(&settings);
    let log = &d.log[0];
    assert!(log.succeeded(), "{log:#?}");
    assert_eq!(log.attempts.len(), 2, "{log:#?}");
    let (a, b) = (&log.attempts[0], &log.attempts[1]);
    assert_eq!(
        a.end,
        AttemptEnd::Pull {
            failure: HardwareFailure::SelfCollision
        }
    );
    assert_eq!(a.motion, MotionClass::Prismatic);
    // The first attempt got 0.60 - 0.45 = 0.15 m, less one step's rounding.
    assert!(
        a.pull_distance > 0.12 && a.pull_distance <= 0.15 + 1e-9,
        "{}",
        a.pull_distance
    );
    // Straight back: 0.3 m along the negative heading (the base faced +y, so -y).
    let shift = b.world_from_base.translation.vector - a.world_from_base.translation.vector;
    assert!((shift - Vector2::new(0.0, -0.3)).norm() < 0.02, "{shift:?}");
    assert!(b.end.is_success());
    assert!(log.pull_distance >= settings.target_pull - 1e-9);
    check_joint(&d, JointKind::Prismatic, DRAWER_AXIS, None, 3.0, 0.0);
}

/// The same drawer and reach at the default `sufficient_pull` (12 cm): the first attempt's
/// 15 cm is a success after `SelfCollision`, short of the 30 cm target, so the robot
/// Repositions 30 cm back and pulls on to the target with `resume_short_pulls`; without it
/// (the default) the short pull is accepted at once.
#[test]
fn a_short_success_is_pulled_on_to_the_target() {
    for resume in [true, false] {
        let settings = DiscoverySettings {
            resume_short_pulls: resume,
            max_extra_pulls: 0,
            ..DiscoverySettings::default()
        };
        let d = reach_limited_drawer(&settings);
        let log = &d.log[0];
        assert!(log.succeeded(), "{log:#?}");
        assert_eq!(
            log.attempts[0].end,
            AttemptEnd::SuccessAfter {
                failure: HardwareFailure::SelfCollision
            },
            "{log:#?}"
        );
        if resume {
            assert_eq!(log.attempts.len(), 2, "{log:#?}");
            let shift = log.attempts[1].world_from_base.translation.vector
                - log.attempts[0].world_from_base.translation.vector;
            assert!((shift - Vector2::new(0.0, -0.3)).norm() < 0.02, "{shift:?}");
            assert!(log.pull_distance >= settings.target_pull - 1e-9);
        } else {
            assert_eq!(log.attempts.len(), 1, "{log:#?}");
            assert!(log.pull_distance <= 0.15 + 1e-9, "{}", log.pull_distance);
        }
        check_joint(&d, JointKind::Prismatic, DRAWER_AXIS, None, 3.0, 0.0);
    }
}

/// Nesting: the door is explored first and left open; the tray's mapped handle (on the door
/// when closed) is carried along with the door's estimated motion, re-detected where it now is,
/// explored, and registered as a child of the door with its slide axis in the door frame.
#[test]
fn a_tray_in_a_door_is_registered_nested_on_the_door() {
    let truth = door_with_tray();
    let mut world = World::new(truth, start(), WorldSettings::default(), 71);
    let mut handles = map(&mut world);
    assert_eq!(handles.len(), 2);
    // The handle selector: the door's handle (larger x) first.
    handles.sort_by(|a, b| b.position.x.total_cmp(&a.position.x));
    let base = world.model.base().clone();
    let d = discover(
        &mut world,
        &base,
        &handles,
        &TwoView::default(),
        &DiscoverySettings::default(),
    )
    .unwrap();
    assert!(d.log.iter().all(|l| l.succeeded()), "{:#?}", d.log);
    assert!(d.log[0].notes.iter().any(|n| n.contains("carried")));
    assert_eq!(
        d.log[1].outcome,
        Exploration::Registered {
            part: "part1".into(),
            joint: "part1_slide".into(),
            parent: Some("part0".into()),
        }
    );
    let door = d.model.part_id("part0").unwrap();
    let tray = d.model.part_id("part1").unwrap();
    assert_eq!(
        d.model.part(tray).unwrap().parent(),
        kinscene::scene::Parent::Part(door)
    );
    // The tray's axis in the door's frame. Both door frames are aligned with the map frame
    // when the door is closed, so the truth is the tray's axis -y.
    let j = &d.model.joints()[tray.index()];
    assert_eq!(j.kind, JointKind::Prismatic);
    let axis = j.parent_from_joint.rotation * j.axis;
    let err = axis_angle_error(&axis, &-Vector3::y());
    assert!(err <= 3.0, "tray axis error {err}°");
    // Both parts really moved.
    assert!(
        world.state.as_slice().iter().all(|&q| q > 0.05),
        "{:?}",
        world.state
    );
}

#[test]
fn a_handle_with_no_part_behind_it_is_an_exploration_failure() {
    // A knob fixed on the carcass front below the drawer (x = 0.1, z = 0.3, 3 cm proud of
    // the face y = 0): graspable, but nothing moves when pulled.
    let (world, d) = run(drawer_cabinet(), &TwoView::default(), 31, |w| {
        w.fixed_handles
            .push((Point3::new(0.1, -0.03, 0.3), -Vector3::y()));
    });
    assert_eq!(d.log.len(), 2);
    let fixed = d
        .log
        .iter()
        .find(|l| (l.mapped - Point3::new(0.1, -0.03, 0.3)).norm() < 0.05)
        .expect("the fixed handle was mapped");
    match &fixed.outcome {
        Exploration::Failed { stage, .. } => assert_eq!(*stage, Stage::Exploration, "{fixed:#?}"),
        other => panic!("expected an exploration failure, got {other:?}"),
    }
    assert!(fixed.passed(Stage::Navigation) && !fixed.passed(Stage::Exploration));
    let settings = DiscoverySettings::default();
    assert_eq!(fixed.attempts.len(), settings.max_attempts);
    assert!(
        fixed
            .attempts
            .iter()
            .all(|a| matches!(a.end, AttemptEnd::NoDisplacement { .. }))
    );
    // The drawer is still discovered, and only it.
    assert_eq!(d.model.nq(), 1);
    assert_eq!(d.log.iter().filter(|l| l.succeeded()).count(), 1);
    assert!(world.state.as_slice()[0] > 0.1);
}

#[test]
fn a_mapped_handle_that_is_not_there_is_a_mapping_failure() {
    let truth = door_cabinet();
    let mut world = World::new(truth, start(), WorldSettings::default(), 41);
    let mut handles = map(&mut world);
    // Move the mapped handle 30 cm along the front: the detector finds nothing there.
    handles[0].position.x -= 0.3;
    let base = world.model.base().clone();
    let d = discover(
        &mut world,
        &base,
        &handles,
        &TwoView::default(),
        &DiscoverySettings::default(),
    )
    .unwrap();
    assert!(matches!(
        d.log[0].outcome,
        Exploration::Failed {
            stage: Stage::Mapping,
            ..
        }
    ));
    assert!(!d.log[0].passed(Stage::Mapping));
    assert_eq!(d.model.nq(), 0);
    assert!(world.grasps == 0);
}

#[test]
fn bad_input_is_an_error() {
    let truth = door_cabinet();
    let mut world = World::new(truth, start(), WorldSettings::default(), 51);
    let handles = map(&mut world);
    let base = world.model.base().clone();
    let mut unregistered = handles.clone();
    unregistered[0].attachment = None;
    let s = DiscoverySettings::default();
    let est = TwoView::default();
    assert_eq!(
        discover(&mut world, &base, &unregistered, &est, &s).unwrap_err(),
        DiscoveryError::UnregisteredHandle { index: 0 }
    );
    let bad = DiscoverySettings {
        max_attempts: 0,
        ..DiscoverySettings::default()
    };
    assert!(matches!(
        discover(&mut world, &base, &handles, &est, &bad),
        Err(DiscoveryError::InvalidSetting(s)) if s.field == "max_attempts"
    ));
    let mut nan = handles.clone();
    nan[0].position.x = f64::NAN;
    assert!(matches!(
        discover(&mut world, &base, &nan, &est, &s),
        Err(DiscoveryError::NonFinite { .. })
    ));
}

#[test]
fn the_discovered_scene_exports_to_urdf_and_loads_back() {
    let (_, d) = run(door_cabinet(), &TwoView::default(), 61, |_| {});
    assert_eq!(d.model.nq(), 1);
    let xml = urdf::write_string(&d.model, &urdf::ExportOptions::default()).unwrap();
    let back = urdf::read_str(&xml, &urdf::ImportOptions::default()).unwrap();
    assert_eq!(back.nq(), 1);
    let (a, b) = (&d.model.joints()[0], &back.joints()[0]);
    assert_eq!((a.kind, &a.name), (b.kind, &b.name));
    // Rotations are written as rpy on a 1e-12 grid (the exporter's documented round trip).
    assert!(
        (a.parent_from_joint.rotation * a.axis - b.parent_from_joint.rotation * b.axis).norm()
            < 1e-9
    );
    assert!(
        (a.parent_from_joint.translation.vector - b.parent_from_joint.translation.vector).norm()
            < 1e-9
    );
    assert_eq!(a.limits, b.limits);
    assert_eq!(back.handles().count(), 1);
    assert_eq!(back.base().shapes.len(), d.model.base().shapes.len());
    // The log serialises (the kitchen report uses it).
    let json = serde_json::to_string(&d.log).unwrap();
    assert!(json.contains("Registered"));
}

/// The drawer at 5 mm depth noise (the target noise level) with the two-view
/// estimator, over three seeds. The post view (from a step back) sees the drawer pulled 30 cm
/// towards it hiding the carcass face below it; those static points are segmented with the
/// drawer, and without the contact-path check a ~90–120° rotation mapping them onto the
/// drawer's top won on BIC in 6 of 6 seeds. Now: prismatic, axis within 2° (the estimator's
/// target at 5 mm), the path check named in the details.
#[test]
fn the_drawer_at_5mm_noise_is_prismatic_two_view() {
    for seed in 0..3 {
        let mut world = World::new(
            drawer_cabinet(),
            start(),
            WorldSettings {
                depth_noise: 0.005,
                ..WorldSettings::default()
            },
            100 + seed,
        );
        let handles = map(&mut world);
        let base = world.model.base().clone();
        let d = discover(
            &mut world,
            &base,
            &handles,
            &TwoView::default(),
            &DiscoverySettings::default(),
        )
        .unwrap();
        check_joint(&d, JointKind::Prismatic, DRAWER_AXIS, None, 2.0, 0.0);
        let details = &d.log[0].estimate.as_ref().expect("estimated").details;
        assert!(details.contains("path residual"), "{details}");
    }
}
