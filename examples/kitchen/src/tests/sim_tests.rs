//! Tests of the kitchen simulator (examples/kitchen/sim).
//!
//! Expected values come from the kitchen URDF's geometry (its header states the layout) and
//! from kinscene's own forward kinematics and exact sweep checks, not from the simulator.
//! Geometry used below (examples/scenes/kitchen.urdf):
//! - drawer_top slides along world -y; its handle's grasp point is (1.4, 2.3595, 0.74);
//! - sink_door is hinged about -z through (1.653, 2.377); open at 90° its leaf spans
//!   x 1.653..1.673, y 1.833..2.377 (the header: "reaches y = 1.833");
//! - corner_door_back (A) is hinged about -z through (0.75, 2.377); corner_door_side (B) open
//!   at 90° lies across y 2.23..2.25, which A's sweep crosses.

use std::f64::consts::FRAC_PI_2;

use kinscene::Termination;
use kinscene::discovery::{Camera, Hardware, HardwareFailure, LocalGoal, Perception};
use kinscene::kinematics::ik::{IkSettings, IkSolver, IkTarget};
use kinscene::kinematics::robot::{Exempt, RobotCollision, RobotConfig, RobotModel};
use kinscene::motion::paths::{PathOutcome, PathSettings, plan_arm};
use kinscene::motion::timing::{TimedPath, time_parameterise};
use kinscene::planner::{StepMode, StepMotion, StepTiming};
use kinscene::scene::collision::{SweepSettings, SweepStatus, check_joint_motion};
use kinscene::scene::urdf::{ImportOptions, read_file};
use kinscene::scene::{
    SceneData, SceneModel, State, forward_kinematics, joint_axis, world_from_handle,
};
use nalgebra::{
    DVector, Isometry2, Isometry3, Matrix3, Point3, Rotation3, Translation3, Unit, UnitQuaternion,
    Vector2, Vector3,
};

use crate::sim::sensors::Owner;
use crate::sim::{FailureCategory, Faults, GraspCompliance, SimSettings, SimWorld};

fn kitchen() -> SceneModel {
    let path = crate::repository().join("examples/scenes/kitchen.urdf");
    read_file(&path, &ImportOptions::default()).expect("the shipped kitchen loads")
}

fn pose(x: f64, y: f64, yaw: f64) -> Isometry2<f64> {
    Isometry2::new(Vector2::new(x, y), yaw)
}

fn world_at(truth: &SceneModel, start: Isometry2<f64>, settings: SimSettings) -> SimWorld {
    SimWorld::new(truth, &RobotModel::kinova_gen3_mobile(), start, settings)
        .expect("the kitchen simulator builds")
}

/// A true handle's grasp point and outward normal at `state`.
fn handle_at(truth: &SceneModel, state: &State, name: &str) -> (Point3<f64>, Vector3<f64>) {
    let mut data = SceneData::new(truth);
    forward_kinematics(truth, &mut data, state).expect("valid state");
    let h = world_from_handle(truth, &data, truth.handle_id(name).expect("handle")).expect("pose");
    (h.position, h.normal.into_inner())
}

fn value(truth: &SceneModel, state: &State, joint: &str) -> f64 {
    state.value_by_name(truth, joint).expect("known joint")
}

fn state_with(truth: &SceneModel, values: &[(&str, f64)]) -> State {
    State::from_values(truth, values.iter().copied()).expect("valid state")
}

/// Every part collider's pose in `world.placed()` equals kinscene's forward kinematics of
/// `state` (colliders are placed in model order, part by part).
fn max_collider_error(truth: &SceneModel, world: &SimWorld, state: &State) -> f64 {
    let poses = truth.world_from_parts(state).expect("fk");
    let placed = world.placed();
    let mut worst: f64 = 0.0;
    for (k, part) in truth.parts().iter().enumerate() {
        let mine: Vec<_> = placed
            .iter()
            .filter(|p| p.owner == Owner::Part(k))
            .collect();
        assert_eq!(mine.len(), part.colliders().len(), "part {}", part.name());
        for (c, p) in part.colliders().iter().zip(mine) {
            // Boxes and convex meshes: the parry frame is the collider frame.
            let expected = poses[k] * c.part_from_shape;
            let t = p.pose.translation;
            let got = Vector3::new(t.x, t.y, t.z);
            worst = worst.max((got - expected.translation.vector).norm());
        }
    }
    worst
}

#[test]
fn parts_rest_at_zero_and_bodies_match_forward_kinematics() {
    let truth = kitchen();
    let mut world = world_at(&truth, pose(1.0, -0.5, FRAC_PI_2), SimSettings::default());
    // Let the physics run 1.5 s (retract settles 0.3 s each time).
    for _ in 0..5 {
        world.retract().expect("retract");
    }
    let state = world.true_state();
    let zero = truth.zero_state();
    let drift = state
        .as_slice()
        .iter()
        .zip(zero.as_slice())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(drift < 1e-6, "parts moved at rest by {drift}");
    let err = max_collider_error(&truth, &world, &state);
    assert!(err < 1e-9, "collider poses differ from FK by {err} m");
    // The robot's colliders are in the snapshot too (it occludes the cameras).
    assert!(world.placed().iter().any(|p| p.owner == Owner::Robot));
}

#[test]
fn reset_teleports_and_parts_stay_where_left() {
    let truth = kitchen();
    let mut world = world_at(&truth, pose(1.0, -0.5, FRAC_PI_2), SimSettings::default());
    // The dishwasher door (horizontal hinge: gravity acts on it) half open, its rack out.
    let target = state_with(
        &truth,
        &[
            ("sink_door_hinge", 1.0),
            ("drawer_top_slide", 0.2),
            ("dishwasher_door_hinge", 1.2),
            ("dishwasher_rack_slide", 0.1),
            ("corner_door_side_hinge", FRAC_PI_2),
        ],
    );
    world
        .reset(&target, pose(1.0, -0.6, 0.0))
        .expect("valid reset");
    let now = world.true_state();
    for (a, b) in now.as_slice().iter().zip(target.as_slice()) {
        assert!((a - b).abs() < 1e-9, "teleported to {a}, wanted {b}");
    }
    assert!(max_collider_error(&truth, &world, &target) < 1e-9);
    // The engine's own collider poses (its narrow phase's) moved too: stale ones left a drawer
    // teleported shut "standing out" where it had been, and its contact kicked a door.
    let lag = world.collider_lag();
    assert!(
        lag < 1e-9,
        "a collider lags its body by {lag} m after the teleport"
    );
    assert_eq!(world.base_pose(), pose(1.0, -0.6, 0.0));
    assert_eq!(world.base_trace(), &[pose(1.0, -0.6, 0.0)]);
    for _ in 0..7 {
        world.retract().expect("retract");
    }
    let later = world.true_state();
    for (a, b) in later.as_slice().iter().zip(target.as_slice()) {
        assert!(
            (a - b).abs() < 2e-3,
            "a part drifted from {b} to {a} in 2.1 s"
        );
    }
    // A state outside the limits is bad input.
    let mut bad = truth.zero_state();
    bad.set_unchecked(truth.joint_id("sink_door_hinge").expect("joint"), 5.0);
    assert!(world.reset(&bad, pose(0.0, 0.0, 0.0)).is_err());
}

#[test]
fn pulled_drawer_moves_along_its_true_axis() {
    let truth = kitchen();
    // Beside the drawer in the passage, turned 0.6 rad left of +x towards it: the handle is
    // 0.56 m ahead, 0.11 m left. (Facing +x, 0.41 m to the side, the pull swung the wrist back
    // across the arm, and whether it touched the arm depended on which of the redundant arm's
    // grasp solutions IK returned.) Stiff fingers: the tool stays on the grasp point.
    let stiff = SimSettings {
        grasp: GraspCompliance::none(),
        ..SimSettings::default()
    };
    let mut world = world_at(&truth, pose(1.0, 1.95, 0.6), stiff);
    let zero = truth.zero_state();
    let (p0, n0) = handle_at(&truth, &zero, "drawer_top_handle");
    assert!((p0 - Point3::new(1.4, 2.3595, 0.74)).norm() < 1e-9);
    let ee0 = world
        .grasp(&p0, &Unit::new_normalize(-n0))
        .expect("the drawer handle is reachable");
    assert!((ee0.translation.vector - p0.coords).norm() < 1e-3);
    let arm0 = world.clock().arm;
    let base0 = world.clock().base;
    // Table I's threshold: 5 cm, crossed during the third 2 cm pull (0.3 s each).
    world.watch("drawer_top_slide", 0.05).expect("watch");
    assert!(world.watch("no_such_joint", 0.05).is_err());
    assert!(world.watch("drawer_top_slide", f64::NAN).is_err());
    let started = std::time::Instant::now();
    let steps = 10;
    for _ in 0..steps {
        world
            .pull_step(&Unit::new_normalize(n0), 0.02)
            .expect("pull");
    }
    let per_step = started.elapsed().as_secs_f64() / steps as f64;
    let state = world.true_state();
    let q = value(&truth, &state, "drawer_top_slide");
    let (p1, _) = handle_at(&truth, &state, "drawer_top_handle");
    let mut data = SceneData::new(&truth);
    forward_kinematics(&truth, &mut data, &state).expect("fk");
    let axis = joint_axis(
        &truth,
        &data,
        truth.joint_id("drawer_top_slide").expect("joint"),
    )
    .expect("axis");
    let moved = p1 - p0;
    let angle = moved.angle(&axis.direction.into_inner());
    let ee = world.ee_pose().translation.vector - ee0.translation.vector;
    println!(
        "drawer: {steps} pulls of 2 cm -> {q:.4} m, handle moved {:.4} m at {:.3} deg from \
         the URDF axis; end effector {:.3} deg off; {:.2} ms per pull step; arm time {:.1} s",
        moved.norm(),
        angle.to_degrees(),
        ee.angle(&axis.direction.into_inner()).to_degrees(),
        1e3 * per_step,
        world.clock().arm - arm0
    );
    // The URDF axis is (0, -1, 0): the handle moves straight out.
    assert!((axis.direction.into_inner() - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-12);
    assert!((q - 0.2).abs() < 0.01, "opened to {q}");
    assert!(
        angle.to_degrees() < 0.1,
        "moved {:.3} deg off the axis",
        angle.to_degrees()
    );
    assert!(ee.angle(&axis.direction.into_inner()).to_degrees() < 0.5);
    // The compliant arm followed the grasp point.
    assert!((world.ee_pose().translation.vector - p1.coords).norm() < 2e-3);
    assert!((world.clock().arm - arm0 - steps as f64 * 0.3).abs() < 1e-9);
    let at = world.threshold_reached().expect("the drawer moved 5 cm");
    assert_eq!(at.base, base0);
    assert!(
        at.arm > arm0 + 0.6 && at.arm <= arm0 + 0.9 + 1e-9,
        "5 cm reached at {} s after the grasp",
        at.arm - arm0
    );
}

/// Soft fingers (σ 5 mm per axis, 3° tilt per perpendicular axis, drawn per pull step) leave
/// the tool off the drawer handle it holds by about σ·E|χ₃| = 8.0 mm and tilt its approach
/// axis off the front's normal by about 3°·E|χ₂| = 3.8° on average (the means of a
/// 3-d and a 2-d Gaussian's norms); the bounds below are half and twice those.
#[test]
fn soft_fingers_leave_the_tool_off_the_grasp_point() {
    let truth = kitchen();
    let soft = SimSettings {
        grasp: GraspCompliance {
            deflection: 0.005,
            tilt: 3f64.to_radians(),
        },
        ..SimSettings::default()
    };
    // The base pose of `pulled_drawer_moves_along_its_true_axis`.
    let mut world = world_at(&truth, pose(1.0, 1.95, 0.6), soft);
    let (p0, n0) = handle_at(&truth, &truth.zero_state(), "drawer_top_handle");
    world
        .grasp(&p0, &Unit::new_normalize(-n0))
        .expect("the drawer handle is reachable");
    let (mut offset, mut tilt) = (0.0, 0.0);
    let steps = 8;
    for _ in 0..steps {
        let ee = world
            .pull_step(&Unit::new_normalize(n0), 0.02)
            .expect("pull");
        let (p, n) = handle_at(&truth, &world.true_state(), "drawer_top_handle");
        offset += (ee.translation.vector - p.coords).norm() / steps as f64;
        tilt += (ee.rotation * Vector3::z()).angle(&-n).to_degrees() / steps as f64;
    }
    assert!((0.004..0.016).contains(&offset), "mean offset {offset} m");
    assert!((1.9..7.6).contains(&tilt), "mean tilt {tilt}°");
    assert!(value(&truth, &world.true_state(), "drawer_top_slide") > 0.1);
}

#[test]
fn pulled_door_turns_about_its_true_hinge() {
    let truth = kitchen();
    // In the passage right of the sink door, turned towards it.
    let mut world = world_at(&truth, pose(2.6, 1.9, 2.8), SimSettings::default());
    let zero = truth.zero_state();
    let (p0, n0) = handle_at(&truth, &zero, "sink_door_handle");
    world
        .grasp(&p0, &Unit::new_normalize(-n0))
        .expect("the sink door handle is reachable");
    // Pull along the door's current outward normal: the tangent of the handle's arc.
    let first_tool = world.ee_pose();
    let mut ee_points = vec![Point3::from(first_tool.translation.vector)];
    for _ in 0..15 {
        let (_, n) = handle_at(&truth, &world.true_state(), "sink_door_handle");
        match world.pull_step(&Unit::new_normalize(n), 0.02) {
            Ok(ee) => ee_points.push(Point3::from(ee.translation.vector)),
            Err(e) => panic!(
                "pull failed after {} steps at {:.3}: {e}",
                ee_points.len(),
                value(&truth, &world.true_state(), "sink_door_hinge")
            ),
        }
    }
    let q = value(&truth, &world.true_state(), "sink_door_hinge");
    // The hinge from the URDF header: vertical through (1.653, 2.377).
    let pivot = Vector2::new(1.653, 2.377);
    let radius = |p: &Point3<f64>| (Vector2::new(p.x, p.y) - pivot).norm();
    let r0 = radius(&p0);
    let worst = ee_points
        .iter()
        .map(|p| (radius(p) - r0).abs().max((p.z - p0.z).abs()))
        .fold(0.0, f64::max);
    // The tool's approach axis turned with the door (about the vertical).
    let z0 = first_tool.rotation * Vector3::z();
    let z1 = world.ee_pose().rotation * Vector3::z();
    let tool_turn = z0.angle(&z1);
    println!(
        "sink door: 15 pulls of 2 cm -> {:.1} deg; end effector within {:.2} mm of the \
         hinge circle (r = {r0:.4} m); tool axis turned {:.1} deg",
        q.to_degrees(),
        1e3 * worst,
        tool_turn.to_degrees()
    );
    assert!(
        (tool_turn - q).abs() < 0.02,
        "tool turned {tool_turn}, door {q}"
    );
    // 15 × 2 cm of arc at r ≈ 0.505 m is about 34°; the door follows most of it.
    assert!(q > 0.45, "the door opened only {q} rad");
    assert!(
        worst < 2e-3,
        "the end effector left the hinge circle by {worst} m"
    );
}

/// Pulls `handle` along its current true outward normal (the tangent of a door's arc) up to
/// `pulls` times; the joint value after each successful pull.
fn pull_open(
    world: &mut SimWorld,
    truth: &SceneModel,
    handle: &str,
    joint: &str,
    pulls: usize,
) -> Vec<f64> {
    let mut values = Vec::new();
    for _ in 0..pulls {
        let (_, n) = handle_at(truth, &world.true_state(), handle);
        if world.pull_step(&Unit::new_normalize(n), 0.02).is_err() {
            break;
        }
        values.push(value(truth, &world.true_state(), joint));
    }
    values
}

/// The deepest interpenetration (m, ≥ 0) between the colliders of parts `a` and `b` in the
/// world's snapshot (parry contact queries).
fn penetration(world: &SimWorld, a: usize, b: usize) -> f64 {
    let placed = world.placed();
    let mut deepest: f64 = 0.0;
    for x in placed.iter().filter(|p| p.owner == Owner::Part(a)) {
        for y in placed.iter().filter(|p| p.owner == Owner::Part(b)) {
            if let Ok(Some(c)) = parry3d_f64::query::contact(
                &x.pose,
                x.shape.as_ref(),
                &y.pose,
                y.shape.as_ref(),
                0.0,
            ) {
                deepest = deepest.max(-c.dist);
            }
        }
    }
    deepest
}

#[test]
fn door_swung_into_an_open_door_stops_at_the_contact() {
    let truth = kitchen();
    let b_open = state_with(&truth, &[("corner_door_side_hinge", FRAC_PI_2)]);
    // Where A first touches open B: kinscene's exact sweep check (parry distances).
    let mut data = SceneData::new(&truth);
    let a = truth.joint_id("corner_door_back_hinge").expect("joint");
    let sweep = check_joint_motion(
        &truth,
        &mut data,
        &b_open,
        a,
        0.0,
        FRAC_PI_2,
        &SweepSettings::default(),
    )
    .expect("sweep");
    let SweepStatus::Collision { value: contact, .. } = sweep.status else {
        panic!("A's sweep must hit open B: {:?}", sweep.status);
    };
    let base = pose(1.0, 1.55, 1.8);
    let (p0, n0) = handle_at(&truth, &b_open, "corner_door_back_handle");
    let run = |start: &State| {
        let mut world = world_at(&truth, base, SimSettings::default());
        world.reset(start, base).expect("reset");
        world
            .grasp(&p0, &Unit::new_normalize(-n0))
            .expect("A's handle is reachable");
        let angles = pull_open(
            &mut world,
            &truth,
            "corner_door_back_handle",
            "corner_door_back_hinge",
            30,
        );
        (world, angles)
    };
    // B closed: A swings freely.
    let (_, free) = run(&truth.zero_state());
    // B open: A stops where it meets B.
    let (world, blocked) = run(&b_open);
    let a_end = blocked.last().copied().unwrap_or(0.0);
    let b_end = value(&truth, &world.true_state(), "corner_door_side_hinge");
    let (ia, ib) = (
        truth.part_id("corner_door_back").expect("part").index(),
        truth.part_id("corner_door_side").expect("part").index(),
    );
    let depth = penetration(&world, ia, ib);
    println!(
        "corner doors: with B closed A opens to {:.1} deg in {} pulls; with B open A stops at \
         {:.2} deg ({} pulls), first contact at {:.2} deg (sweep check); B pushed from 90 to \
         {:.2} deg; deepest A-B interpenetration {:.2} mm",
        free.last().copied().unwrap_or(0.0).to_degrees(),
        free.len(),
        a_end.to_degrees(),
        blocked.len(),
        contact.to_degrees(),
        b_end.to_degrees(),
        1e3 * depth
    );
    assert!(
        free.last().copied().unwrap_or(0.0) > contact + 0.3,
        "A must open freely without B"
    );
    assert_eq!(
        blocked.len(),
        30,
        "every pull step succeeds (the arm complies)"
    );
    // A presses on B (B, hinged too, yields a little) but cannot pass it.
    assert!(
        a_end >= contact - 0.05,
        "A stopped before touching B: {a_end} < {contact}"
    );
    assert!(a_end <= contact + 0.06, "A passed B: {a_end} > {contact}");
    assert!(
        b_end < FRAC_PI_2 - 1e-3,
        "B was not pushed: the contact is not real"
    );
    assert!(depth < 5e-3, "A and B interpenetrate by {depth} m");
}

/// Timed path through `points` at the robot's arm limits.
fn arm_path(robot: &RobotModel, points: Vec<Vec<f64>>) -> TimedPath {
    let v: Vec<f64> = robot.arm_joints().iter().map(|j| j.max_velocity).collect();
    let a: Vec<f64> = robot
        .arm_joints()
        .iter()
        .map(|j| j.max_acceleration)
        .collect();
    time_parameterise(&points, &v, &a, None).expect("timed arm path")
}

/// Timed base path through `points` ([x, y, yaw]) at the base's limits.
fn base_path(robot: &RobotModel, points: Vec<Vec<f64>>) -> TimedPath {
    let b = robot.base();
    time_parameterise(&points, &b.max_velocity, &b.max_acceleration, Some(2))
        .expect("timed base path")
}

/// Arm configurations from `base` placing the tool at each `(point, approach)` (IK, each
/// solved near the previous one), or `None` if one is unreachable.
fn arm_track(
    robot: &RobotModel,
    base: [f64; 3],
    targets: &[(Point3<f64>, Vector3<f64>)],
) -> Option<Vec<Vec<f64>>> {
    let ik = IkSolver::for_robot(
        robot,
        IkSettings {
            budget: std::time::Duration::from_secs(60),
            ..IkSettings::default()
        },
    )
    .expect("IK");
    let base_from_world = RobotModel::world_from_base(base).inverse();
    let mut seed = robot.neutral();
    let mut out = Vec::new();
    for (k, (p, approach)) in targets.iter().enumerate() {
        // Tool z along the approach, tool x (the fingers' closing axis) up: the fingers
        // close on the handle from above and below, clear of the neighbouring fronts.
        let z = approach.normalize();
        let x = (Vector3::z() - z * z.z).normalize();
        let rotation =
            Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[x, z.cross(&x), z]));
        let world_from_tool = Isometry3::from_parts(
            Translation3::from(p.coords),
            UnitQuaternion::from_rotation_matrix(&rotation),
        );
        let target = IkTarget::Pose(base_from_world * world_from_tool);
        let outcome = if k == 0 {
            ik.solve(&target, &seed)
        } else {
            ik.solve_near(&target, &seed)
        }
        .expect("IK input is valid");
        seed = outcome.q()?.clone();
        out.push(seed.as_slice().to_vec());
    }
    Some(out)
}

/// An arm path from `from` to `to` planned with OMPL (seeded, so deterministic) that keeps
/// 5 mm from the true scene at `state`, the part `ignore` (the one being grasped) exempt.
fn arm_plan(
    robot: &RobotModel,
    truth: &SceneModel,
    state: &State,
    base: [f64; 3],
    ignore: &str,
    from: &[f64],
    to: &[f64],
) -> Vec<Vec<f64>> {
    let collision = RobotCollision::new(robot).expect("robot collision");
    let mut data = SceneData::new(truth);
    forward_kinematics(truth, &mut data, state).expect("fk");
    let ignore = [truth.part_id(ignore).expect("part")];
    let valid = |q: &[f64]| {
        let config = RobotConfig {
            base,
            arm: DVector::from_column_slice(q),
        };
        robot.link_poses(&config).is_ok_and(|poses| {
            collision.self_collision(&poses).is_none()
                && collision
                    .scene_collision(&poses, truth, &data, Exempt::Parts(&ignore), 0.005)
                    .is_none()
        })
    };
    let (lower, upper) = robot.arm_bounds();
    let settings = PathSettings {
        budget: std::time::Duration::from_secs(10),
        seed: Some(7),
        ..PathSettings::default()
    };
    match plan_arm(
        from,
        to,
        lower.as_slice(),
        upper.as_slice(),
        &valid,
        &settings,
        &Termination::none(),
    )
    .expect("valid planning input")
    {
        PathOutcome::Solved(path) => path,
        other => panic!("no arm path: {other:?}"),
    }
}

/// A plan step standing at `base` (no base motion) whose manipulation of part `part` follows
/// `track`; approach and retreat planned between the stowed arm and the track's ends in the
/// true scene at `state` (before) and `after`.
fn step_at(
    robot: &RobotModel,
    truth: &SceneModel,
    (state, after): (&State, &State),
    part: &str,
    base: [f64; 3],
    track: Vec<Vec<f64>>,
) -> StepMotion {
    let stow = robot.neutral().as_slice().to_vec();
    let (first, last) = (track[0].clone(), track[track.len() - 1].clone());
    let approach = arm_path(
        robot,
        arm_plan(robot, truth, state, base, part, &stow, &first),
    );
    let manipulation = arm_path(robot, track);
    let retreat = arm_path(
        robot,
        arm_plan(robot, truth, after, base, part, &last, &stow),
    );
    let timing = StepTiming {
        base: 0.0,
        approach: approach.duration,
        manipulation: manipulation.duration,
        retreat: retreat.duration,
    };
    StepMotion {
        joint: "estimated_joint".into(),
        from: 0.0,
        to: 1.0,
        handle: "estimated_handle".into(),
        base,
        base_path: base_path(robot, vec![base.to_vec()]),
        pregrasp: approach.positions.len() - 1,
        approach,
        manipulation,
        retreat,
        postgrasp: 0,
        timing,
        manipulation_base: None,
        mode: StepMode::FixedBase,
        compared: None,
    }
}

/// Corner door A's handle (grasp point, approach) at angles `0..=to` in `n` steps, for a
/// hinge model: the true one (the planner's oracle), or with the hinge moved along the door.
fn door_a_track(truth: &SceneModel, to: f64, n: usize) -> Vec<(Point3<f64>, Vector3<f64>)> {
    (0..=n)
        .map(|k| {
            let s = state_with(
                truth,
                &[("corner_door_back_hinge", to * k as f64 / n as f64)],
            );
            let (p, normal) = handle_at(truth, &s, "corner_door_back_handle");
            (p, -normal)
        })
        .collect()
}

/// Drawer D1's handle (grasp point, approach) pulled out to `to` in `n` steps.
fn drawer_track(truth: &SceneModel, to: f64, n: usize) -> Vec<(Point3<f64>, Vector3<f64>)> {
    (0..=n)
        .map(|k| {
            let s = state_with(truth, &[("drawer_top_slide", to * k as f64 / n as f64)]);
            let (p, normal) = handle_at(truth, &s, "drawer_top_handle");
            (p, -normal)
        })
        .collect()
}

#[test]
fn executed_step_drags_the_part_along_its_true_joint() {
    let truth = kitchen();
    let robot = RobotModel::kinova_gen3_mobile();
    let base = [1.2, 1.6, 1.7];
    // Beyond about 0.85 rad the gripper holding A's handle meets B's closed handle.
    let to = 0.8;
    let track = arm_track(&robot, base, &door_a_track(&truth, to, 32)).expect("reachable track");
    let zero = truth.zero_state();
    let open = state_with(&truth, &[("corner_door_back_hinge", to)]);
    let step = step_at(
        &robot,
        &truth,
        (&zero, &open),
        "corner_door_back",
        base,
        track,
    );
    let mut world = world_at(
        &truth,
        pose(base[0], base[1], base[2]),
        SimSettings::default(),
    );
    let before = world.clock();
    let done = world.execute_step(&step);
    let a = value(&truth, &world.true_state(), "corner_door_back_hinge");
    println!(
        "execute: corner door A planned 0 -> {to} rad, reached {a:.4} rad; base {:.2} s, arm \
         {:.2} s (plan: {:.2} s); failure {:?}",
        done.base_time,
        done.arm_time,
        step.timing.arm(),
        done.failure
    );
    assert_eq!(done.failure, None);
    assert!((a - to).abs() < 0.02, "A ended at {a}, planned {to}");
    // Nothing else moved.
    let others = value(&truth, &world.true_state(), "corner_door_side_hinge").abs()
        + value(&truth, &world.true_state(), "drawer_top_slide").abs();
    assert!(others < 1e-6);
    assert!((done.arm_time - step.timing.arm()).abs() < 1e-9);
    assert!((world.clock().arm - before.arm - step.timing.arm()).abs() < 1e-9);
    assert_eq!(done.joint, "estimated_joint");
}

#[test]
fn executed_drawer_into_an_open_door_is_a_part_collision() {
    let truth = kitchen();
    let robot = RobotModel::kinova_gen3_mobile();
    let base = [1.0, 1.95, 0.0];
    let start = pose(base[0], base[1], base[2]);
    // The sink door open at 100°: its leaf leans over D1's right end, which meets it after
    // about 3.5 cm of travel (the URDF header: past ~91° the drawers cannot slide out).
    let s_open = state_with(&truth, &[("sink_door_hinge", 100f64.to_radians())]);
    let track = arm_track(&robot, base, &drawer_track(&truth, 0.25, 25)).expect("reachable");
    let after = state_with(
        &truth,
        &[
            ("sink_door_hinge", 100f64.to_radians()),
            ("drawer_top_slide", 0.25),
        ],
    );
    let step = step_at(
        &robot,
        &truth,
        (&s_open, &after),
        "drawer_top",
        base,
        track.clone(),
    );
    let mut world = world_at(&truth, start, SimSettings::default());
    world.reset(&s_open, start).expect("reset");
    let done = world.execute_step(&step);
    let failure = done.failure.expect("D1 must hit the sink door");
    let d1 = value(&truth, &world.true_state(), "drawer_top_slide");
    println!("execute D1 into the open sink door: {failure:?}; D1 stopped at {d1:.4} m");
    assert_eq!(failure.category, FailureCategory::PartCollision);
    assert!(failure.reason.contains("drawer_top") && failure.reason.contains("sink_door"));
    assert!(d1 < 0.06, "D1 passed the door: {d1}");
    // The same step with the door closed goes through.
    let zero = truth.zero_state();
    let drawn = state_with(&truth, &[("drawer_top_slide", 0.25)]);
    let step = step_at(&robot, &truth, (&zero, &drawn), "drawer_top", base, track);
    let mut world = world_at(&truth, start, SimSettings::default());
    let done = world.execute_step(&step);
    let d1 = value(&truth, &world.true_state(), "drawer_top_slide");
    assert_eq!(done.failure, None);
    assert!((d1 - 0.25).abs() < 0.005, "D1 at {d1}");
}

#[test]
fn executed_step_on_a_wrong_joint_model_loses_the_grasp() {
    let truth = kitchen();
    let robot = RobotModel::kinova_gen3_mobile();
    let base = [1.1, 1.45, 1.4];
    let start = pose(base[0], base[1], base[2]);
    // A taken for a drawer sliding out along its closed normal (-y): the handle leaves the
    // true arc (r = 0.36 m: at distance d along the tangent the arc is √(r² + d²) − r away,
    // 4.5 cm at d = 0.19 m), the spring stretches
    // and the grasp slips.
    let (p0, n0) = handle_at(&truth, &truth.zero_state(), "corner_door_back_handle");
    let line: Vec<_> = (0..=22)
        .map(|k| (p0 + n0 * (0.22 * k as f64 / 22.0), -n0))
        .collect();
    let track = arm_track(&robot, base, &line).expect("reachable line");
    let zero = truth.zero_state();
    let step = step_at(
        &robot,
        &truth,
        (&zero, &zero),
        "corner_door_back",
        base,
        track,
    );
    let mut world = world_at(&truth, start, SimSettings::default());
    let done = world.execute_step(&step);
    let failure = done.failure.expect("the grasp must slip");
    let a = value(&truth, &world.true_state(), "corner_door_back_hinge");
    println!("execute with a prismatic model of A: {failure:?}; A at {a:.3} rad");
    assert_eq!(failure.category, FailureCategory::GraspLost);
    // Before slipping the door followed part of the pull.
    assert!(a > 0.1, "A at {a}");
}

/// A plan step driving `path` (x, y, yaw waypoints) with the arm stowed throughout.
fn drive_step(robot: &RobotModel, path: Vec<Vec<f64>>) -> StepMotion {
    let stow = robot.neutral().as_slice().to_vec();
    let base_path = base_path(robot, path);
    let end = base_path.positions[base_path.positions.len() - 1].clone();
    let still = arm_path(robot, vec![stow]);
    StepMotion {
        joint: "j".into(),
        from: 0.0,
        to: 1.0,
        handle: "h".into(),
        base: [end[0], end[1], end[2]],
        timing: StepTiming {
            base: base_path.duration,
            ..StepTiming::default()
        },
        base_path,
        approach: still.clone(),
        pregrasp: 0,
        manipulation: still.clone(),
        retreat: still,
        postgrasp: 0,
        manipulation_base: None,
        mode: StepMode::FixedBase,
        compared: None,
    }
}

#[test]
fn base_path_through_an_open_door_is_blocked() {
    let truth = kitchen();
    let robot = RobotModel::kinova_gen3_mobile();
    // Along the passage (y = 2.0) from west to east of the sink door's hinge (x = 1.653).
    let path = vec![vec![1.0, 2.0, 0.0], vec![2.4, 2.0, 0.0]];
    let step = drive_step(&robot, path);
    let start = pose(1.0, 2.0, 0.0);

    // Closed door: the base gets through; with no handle under the stowed gripper the step
    // then fails at the grasp.
    let mut world = world_at(&truth, start, SimSettings::default());
    let done = world.execute_step(&step);
    let failure = done.failure.expect("nothing to grasp");
    assert_eq!(failure.category, FailureCategory::GraspLost, "{failure:?}");
    assert!((done.base_time - step.base_path.duration).abs() < 1e-9);
    assert!((world.base_pose().translation.vector - Vector2::new(2.4, 2.0)).norm() < 1e-9);

    // Open at 90°, the leaf (x 1.653..1.673, y 1.833..2.377) crosses the passage.
    let open = state_with(&truth, &[("sink_door_hinge", FRAC_PI_2)]);
    let mut world = world_at(&truth, start, SimSettings::default());
    world.reset(&open, start).expect("reset");
    let done = world.execute_step(&step);
    let failure = done.failure.expect("the open door blocks the passage");
    let x = world.base_pose().translation.vector.x;
    let radius = robot.base().footprint_radius;
    println!(
        "open sink door: {failure:?}; the base stopped at x = {x:.3} (leaf at x = 1.653, \
         footprint radius {radius:.3}) after {:.2} of {:.2} s",
        done.base_time, step.base_path.duration
    );
    assert_eq!(failure.category, FailureCategory::PathBlocked);
    assert!(failure.reason.contains("sink_door"), "{}", failure.reason);
    // It stops before any robot point reaches the leaf, within two 2 cm checks of contact:
    // the chassis (0.44 m long, centred 0 on the base) reaches 0.22 m ahead of the base.
    assert!(
        x <= 1.653 - 0.22 + 1e-9,
        "the base drove into the leaf: x = {x}"
    );
    assert!(x >= 1.653 - radius - 0.04, "stopped too early: x = {x}");
    assert!(done.base_time < step.base_path.duration);
    // The trace ends where the base stopped.
    let last = world.base_trace().last().expect("trace").translation.vector;
    assert!(last.x <= x + 1e-9 && last.x > 1.0);
}

#[test]
fn navigation_follows_the_true_grid_and_costs_time() {
    let truth = kitchen();
    let robot = RobotModel::kinova_gen3_mobile();
    let mut world = world_at(&truth, pose(1.0, -0.5, FRAC_PI_2), SimSettings::default());
    // Into the passage between the island and the back run (its free centre line on the
    // 5 cm grid inflated by the footprint radius is y ≈ 1.9-2.0): around the island.
    let goal = pose(2.2, 1.95, 0.0);
    world.navigate_to(&goal).expect("reachable");
    assert_eq!(world.base_pose(), goal);
    let t = world.clock().base;
    let v = robot.base().max_velocity;
    // Lower bound: the straight line (blocked by the island) plus the 90° turn.
    let straight = (Vector2::new(2.2, 1.95) - Vector2::new(1.0, -0.5)).norm();
    let lower = straight / v[0] + FRAC_PI_2 / v[2];
    println!("navigation (1.0, -0.5) -> (2.2, 1.95): {t:.2} s (straight-line bound {lower:.2} s)");
    assert!(t > lower, "{t} <= {lower}");
    assert!(t < 2.0 * lower);
    let trace = world.base_trace();
    assert!(trace.len() >= 3, "the route turns around the island");
    // No route corner lies on the island (x 1.5..3.0, y 0.65..1.55) or closer than the
    // footprint radius to it.
    let r = robot.base().footprint_radius;
    for p in trace {
        let q = p.translation.vector;
        let dx = (1.5 - q.x).max(q.x - 3.0).max(0.0);
        let dy = (0.65 - q.y).max(q.y - 1.55).max(0.0);
        assert!(
            dx.hypot(dy) >= r - 1e-9,
            "corner {q:?} too close to the island"
        );
    }
    // A goal inside the island, and a goal where an open door stands, fail.
    assert!(matches!(
        world.navigate_to(&pose(2.2, 1.1, 0.0)),
        Err(HardwareFailure::NavigationFailed { .. })
    ));
    // The open sink door closes the passage; the way around the island's east end (0.38 m to
    // the wall) is too narrow: no route west. Closed, the route stays in the passage.
    let open = state_with(&truth, &[("sink_door_hinge", FRAC_PI_2)]);
    world.reset(&open, pose(2.2, 1.95, 0.0)).expect("reset");
    assert!(matches!(
        world.navigate_to(&pose(1.66, 1.95, 0.0)),
        Err(HardwareFailure::NavigationFailed { .. })
    ));
    assert!(matches!(
        world.navigate_to(&pose(1.2, 1.95, 0.0)),
        Err(HardwareFailure::NavigationFailed { .. })
    ));
    world
        .reset(&truth.zero_state(), pose(2.2, 1.95, 0.0))
        .expect("reset");
    world
        .navigate_to(&pose(1.2, 1.95, 0.0))
        .expect("through the passage");
    let south = world
        .base_trace()
        .iter()
        .map(|p| p.translation.vector.y)
        .fold(f64::INFINITY, f64::min);
    assert!(
        south > 1.55 + r - 1e-9,
        "the route left the passage: min y {south}"
    );
}

#[test]
fn faults_fire_at_rate_one_and_settings_are_checked() {
    let truth = kitchen();
    let settings = SimSettings {
        faults: Faults::with_rate(1.0),
        ..SimSettings::default()
    };
    let mut world = world_at(&truth, pose(1.0, 1.95, 0.0), settings);
    let goal = LocalGoal {
        target: Point3::new(1.4, 2.36, 0.74),
        world_from_base: pose(1.1, 1.95, 0.0),
    };
    assert_eq!(
        world.navigate_local(&goal),
        Err(HardwareFailure::TrackingLost)
    );
    let (p0, n0) = handle_at(&truth, &truth.zero_state(), "drawer_top_handle");
    assert_eq!(
        world.grasp(&p0, &Unit::new_normalize(-n0)),
        Err(HardwareFailure::GraspLost)
    );
    assert_eq!(
        world.pull_step(&Unit::new_normalize(n0), 0.02),
        Err(HardwareFailure::GraspLost),
        "nothing is held"
    );
    // Rates are clamped; NaN is no fault.
    assert_eq!(Faults::with_rate(2.0), Faults::with_rate(1.0));
    assert_eq!(Faults::with_rate(f64::NAN), Faults::none());
    assert!((Faults::with_rate(0.5).nav_drift - 0.025).abs() < 1e-15);
    // Out-of-range settings are errors, not panics.
    let bad = SimSettings {
        faults: Faults {
            grasp_slip: 1.5,
            ..Faults::none()
        },
        ..SimSettings::default()
    };
    assert!(
        SimWorld::new(
            &truth,
            &RobotModel::kinova_gen3_mobile(),
            pose(0.0, 0.0, 0.0),
            bad
        )
        .is_err()
    );
    for grasp in [
        GraspCompliance {
            deflection: f64::NAN,
            tilt: 0.0,
        },
        GraspCompliance {
            deflection: 0.0,
            tilt: -0.1,
        },
    ] {
        let bad = SimSettings {
            grasp,
            ..SimSettings::default()
        };
        let world = SimWorld::new(
            &truth,
            &RobotModel::kinova_gen3_mobile(),
            pose(0.0, 0.0, 0.0),
            bad,
        );
        assert!(matches!(world, Err(e) if e.to_string().contains("grasp compliance")));
    }
    let nan = pose(f64::NAN, 0.0, 0.0);
    assert!(
        SimWorld::new(
            &truth,
            &RobotModel::kinova_gen3_mobile(),
            nan,
            SimSettings::default()
        )
        .is_err()
    );
}

/// A sequence of hardware calls with drift and random faults: (true state, base pose, ee pose,
/// time, outcomes).
fn scripted_run(seed: u64) -> (Vec<f64>, Isometry2<f64>, Isometry3<f64>, f64, Vec<String>) {
    let truth = kitchen();
    let settings = SimSettings {
        seed,
        faults: Faults {
            grasp_slip: 0.05,
            joint_limit: 0.05,
            tracker_loss: 0.2,
            nav_drift: 0.02,
        },
        ..SimSettings::default()
    };
    let mut world = world_at(&truth, pose(1.0, 1.9, 0.0), settings);
    let mut log = Vec::new();
    let (p0, n0) = handle_at(&truth, &truth.zero_state(), "drawer_top_handle");
    for _ in 0..3 {
        let goal = LocalGoal {
            target: p0,
            world_from_base: pose(1.0, 1.95, 0.0),
        };
        log.push(format!("{:?}", world.navigate_local(&goal)));
        log.push(format!(
            "{:?}",
            world
                .grasp(&p0, &Unit::new_normalize(-n0))
                .map(|p| p.translation)
        ));
        for _ in 0..6 {
            log.push(format!(
                "{:?}",
                world
                    .pull_step(&Unit::new_normalize(n0), 0.02)
                    .map(|p| p.translation)
            ));
        }
        log.push(format!("{:?}", world.retract()));
        // Camera noise and detections come from the same generator.
        let cloud = world
            .observe(Camera::Head)
            .expect("the head camera sees the kitchen");
        let sum: Vector3<f64> = cloud.points.iter().map(|p| p.coords).sum();
        log.push(format!(
            "{} points, sum {sum:?}, stamp {}",
            cloud.points.len(),
            cloud.stamp
        ));
        log.push(format!("{:?}", world.detect_handles()));
    }
    (
        world.true_state().as_slice().to_vec(),
        world.base_pose(),
        world.ee_pose(),
        world.time(),
        log,
    )
}

#[test]
fn same_seed_same_world() {
    let a = scripted_run(3);
    let b = scripted_run(3);
    // Bit for bit: simulated time only, one seeded generator, no wall clock in any decision.
    assert_eq!(a, b);
    let c = scripted_run(4);
    assert_ne!(a.1, c.1, "another seed drifts elsewhere");
    println!("scripted run: state {:?}, time {:.2} s", a.0, a.3);
}

/// Points of `cloud` within `tol` of some collider of `owner` in the world's snapshot.
fn points_on(world: &SimWorld, points: &[Point3<f64>], owner: Owner, tol: f64) -> usize {
    let shapes: Vec<_> = world
        .placed()
        .into_iter()
        .filter(|p| p.owner == owner)
        .collect();
    points
        .iter()
        .filter(|p| {
            let q = parry3d_f64::math::Vector::new(p.x, p.y, p.z);
            shapes
                .iter()
                .any(|s| s.shape.distance_to_point(&s.pose, q, true) <= tol)
        })
        .count()
}

#[test]
fn cameras_see_the_true_scene_and_the_robot() {
    let truth = kitchen();
    let sink = truth.part_id("sink_door").expect("part").index();
    let drawer = truth.part_id("drawer_top").expect("part").index();
    // In the passage facing the back run.
    let mut world = world_at(&truth, pose(1.9, 1.95, FRAC_PI_2), SimSettings::default());
    let t0 = world.time();
    let head = world.observe(Camera::Head).expect("head frame");
    assert!(head.stamp > t0 && (world.time() - t0 - 1.0 / 30.0).abs() < 1e-12);
    // σ = 5 mm depth noise: 3σ from the surfaces.
    let on_sink = points_on(&world, &head.points, Owner::Part(sink), 0.015);
    println!(
        "head frame from the passage: {} points, {on_sink} on the sink door",
        head.points.len()
    );
    assert!(on_sink > 200, "the sink door in front is seen");
    // The stowed arm is folded back over the base, out of view.
    assert_eq!(points_on(&world, &head.points, Owner::Robot, 0.015), 0);
    // The detector finds the sink door's handle (1 cm noise, 10 % misses: try a few frames).
    let (h, _) = handle_at(&truth, &truth.zero_state(), "sink_door_handle");
    let found = (0..5).any(|_| {
        world
            .detect_handles()
            .expect("detector")
            .iter()
            .any(|d| (d.position - h).norm() < 0.05)
    });
    assert!(found, "the sink handle is detected");

    // Reaching for the sink door's handle, the arm is in front of the head camera: it occludes.
    let mut world = world_at(&truth, pose(2.6, 1.9, 2.8), SimSettings::default());
    let (p0, n0) = handle_at(&truth, &truth.zero_state(), "sink_door_handle");
    world.grasp(&p0, &Unit::new_normalize(-n0)).expect("grasp");
    let head = world.observe(Camera::Head).expect("head frame");
    let on_robot = points_on(&world, &head.points, Owner::Robot, 0.015);
    println!("head frame while grasping the sink door: {on_robot} points on the robot's arm");
    assert!(on_robot > 100, "the arm occludes part of the view");

    // The wrist camera at the drawer handle sees the drawer front around the tool.
    let mut world = world_at(&truth, pose(1.0, 1.95, 0.0), SimSettings::default());
    let (p0, n0) = handle_at(&truth, &truth.zero_state(), "drawer_top_handle");
    world.grasp(&p0, &Unit::new_normalize(-n0)).expect("grasp");
    let wrist = world.observe(Camera::Wrist).expect("wrist frame");
    let near: Vec<_> = wrist
        .points
        .iter()
        .copied()
        .filter(|p| (p - p0).norm() < 0.15)
        .collect();
    let on_drawer = points_on(&world, &near, Owner::Part(drawer), 0.015);
    println!(
        "wrist frame at the drawer: {} points, {on_drawer} of {} near the handle on the drawer",
        wrist.points.len(),
        near.len()
    );
    assert!(on_drawer > near.len() / 2 && on_drawer > 20);
}

/// Wall-clock figures of the simulator (not a check; run with `--ignored --nocapture`).
#[test]
#[ignore = "timing report, run on demand"]
fn sim_timing() {
    use std::time::Instant;
    let truth = kitchen();
    let robot = RobotModel::kinova_gen3_mobile();
    let t = Instant::now();
    let mut world = world_at(&truth, pose(2.6, 1.9, 2.8), SimSettings::default());
    let build = t.elapsed();
    let (p0, n0) = handle_at(&truth, &truth.zero_state(), "sink_door_handle");
    let t = Instant::now();
    world.grasp(&p0, &Unit::new_normalize(-n0)).expect("grasp");
    let grasp = t.elapsed();
    let t = Instant::now();
    let pulls = pull_open(
        &mut world,
        &truth,
        "sink_door_handle",
        "sink_door_hinge",
        40,
    )
    .len();
    let pull = t.elapsed() / pulls.max(1) as u32;
    let t = Instant::now();
    let frames = 10;
    for _ in 0..frames {
        world.observe(Camera::Head).expect("frame");
    }
    let head = t.elapsed() / frames;
    let t = Instant::now();
    for _ in 0..frames {
        world.observe(Camera::Wrist).expect("frame");
    }
    let wrist = t.elapsed() / frames;
    let base = [1.2, 1.6, 1.7];
    let track = arm_track(&robot, base, &door_a_track(&truth, 0.8, 32)).expect("track");
    let zero = truth.zero_state();
    let open = state_with(&truth, &[("corner_door_back_hinge", 0.8)]);
    let step = step_at(
        &robot,
        &truth,
        (&zero, &open),
        "corner_door_back",
        base,
        track,
    );
    let mut world = world_at(
        &truth,
        pose(base[0], base[1], base[2]),
        SimSettings::default(),
    );
    let t = Instant::now();
    let done = world.execute_step(&step);
    let exec = t.elapsed();
    println!(
        "world build {build:?}; grasp (IK with restarts) {grasp:?}; pull_step {pull:?} per step \
         over {pulls} steps; head frame {head:?}; wrist frame {wrist:?}; execute_step {exec:?} \
         for {:.1} s simulated ({:?})",
        step.timing.total(),
        done.failure
    );
}
