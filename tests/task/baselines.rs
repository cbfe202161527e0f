//! The *Random* and *Paper* baselines, against the search and the validator.

use std::collections::BTreeSet;

use kinscene::scene::collision::{CollisionSettings, collisions};
use kinscene::scene::nav::{GridBounds, NavGridSettings};
use kinscene::scene::{
    BaseShape, Handle, Joint, JointKind, Limits, PartSpec, SceneData, SceneModel,
    SceneModelBuilder, Shape, forward_kinematics,
};
use kinscene::task::{
    BodyName, Cause, GoalSpec, NoRefinement, Outcome, PlanResult, Problem, Strategy, TaskSettings,
    Termination, plan, validate,
};
use nalgebra::{Isometry3, Point2, Point3, Vector3};

/// A 0.5 m × 0.02 m × 0.7 m door slab along +x of its joint frame (z from 0 to 0.7), hinged
/// at the joint frame's origin about `axis`, limits [0, 1.6] rad; handle `<name>_handle` near
/// the free edge, 1 cm off the face on the side `side` (±1 along the frame's y), facing out.
pub(super) fn door(name: &str, at: Isometry3<f64>, axis: Vector3<f64>, side: f64) -> PartSpec {
    PartSpec::on_base(
        name,
        Joint::new(
            format!("{name}_hinge"),
            JointKind::Revolute,
            at,
            axis,
            Limits::new(0.0, 1.6),
        ),
    )
    .with_collider(
        Shape::box_size(Vector3::new(0.5, 0.02, 0.7)),
        Isometry3::translation(0.25, 0.0, 0.35),
    )
    .with_handle(Handle::new(
        format!("{name}_handle"),
        Point3::new(0.45, 0.02 * side, 0.35),
        Vector3::y() * side,
    ))
}

/// A navigation grid over the square [-half, half]² (default resolution 5 cm).
pub(super) fn square_grid(half: f64) -> NavGridSettings {
    NavGridSettings {
        bounds: Some(GridBounds {
            min: Point2::new(-half, -half),
            max: Point2::new(half, half),
        }),
        ..NavGridSettings::default()
    }
}

/// The one-door scene of `basic.rs` (door `door`, joint `door_hinge` at the origin about +z,
/// handle on the -y face), on a 3 m × 3 m grid, plus `extra` base shapes.
pub(super) fn one_door(extra: Vec<BaseShape>) -> SceneModel {
    let mut b = SceneModelBuilder::new();
    b.nav_settings(square_grid(1.5));
    b.add_part(door("door", Isometry3::identity(), Vector3::z(), -1.0));
    for s in extra {
        b.add_base_shape(s);
    }
    b.build().unwrap()
}

/// Goal "open the door to at least 1.2 rad", robot at (0.8, -0.8) facing +x.
pub(super) fn open_door_problem(model: &SceneModel) -> Problem {
    let spec =
        GoalSpec::from_toml("[goal]\ndoor_hinge = { min = 1.2 }\n[robot]\nbase = [0.8, -0.8, 0.0]")
            .unwrap();
    Problem::from_spec(model, &spec).unwrap()
}

fn run(model: &SceneModel, problem: &Problem, strategy: Strategy) -> PlanResult {
    let settings = TaskSettings {
        strategy,
        ..TaskSettings::default()
    };
    plan(
        model,
        problem,
        &settings,
        &NoRefinement,
        &Termination::none(),
    )
    .unwrap()
}

/// The one-door scene plus a thin sliding plate, a part: 4 cm × 2 mm × 0.7 m, normal along
/// y, at x ∈ [0.485, 0.525], y ∈ [0.077, 0.079], z ∈ [v, 0.7 + v] for its slide value
/// `v ∈ [0, 0.1]` (joint `plate_slide`, along +z), handle on its -y face. Goal: the door to
/// at least 1.2 rad and the plate to at least 0.05 m, robot at (0.8, -0.8).
///
/// Why the door's sweep hits the plate (at either height): the door's front face (y = +0.01
/// in the door frame) has its outer corner at `(0.5 cos φ − 0.01 sin φ, 0.5 sin φ +
/// 0.01 cos φ)`; at φ = 7.83° (sin φ = (0.078 − 0.0099)/0.5) that is (0.494, 0.078), inside
/// the plate, whose z range overlaps the door's [0, 0.7] for every slide value.
/// Why the paper's boxes miss it: at the door's 6 configurations 0°, 18°, …, 90° its box
/// reaches y <= 0.01 at 0° (the plate starts at y = 0.077) and x <= 0.5 cos 18° +
/// 0.01 sin 18° = 0.4786 at 18° and beyond (the plate starts at x = 0.485); the door's box at
/// its target 1.2 rad reaches x <= 0.5 cos 1.2 + 0.01 sin 1.2 = 0.19; and the plate's own
/// boxes (moving along z) keep its x and y ranges. So no box pair overlaps in either order.
fn door_and_plate() -> (SceneModel, Problem) {
    let mut b = SceneModelBuilder::new();
    b.nav_settings(square_grid(1.5));
    b.add_part(door("door", Isometry3::identity(), Vector3::z(), -1.0));
    b.add_part(
        PartSpec::on_base(
            "plate",
            Joint::prismatic(
                "plate_slide",
                Point3::new(0.505, 0.078, 0.0),
                Vector3::z(),
                Limits::new(0.0, 0.1),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.04, 0.002, 0.7)),
            Isometry3::translation(0.0, 0.0, 0.35),
        )
        .with_handle(Handle::new(
            "plate_handle",
            Point3::new(0.0, -0.011, 0.35),
            -Vector3::y(),
        )),
    );
    let model = b.build().unwrap();
    let spec = GoalSpec::from_toml(
        "[goal]\ndoor_hinge = { min = 1.2 }\nplate_slide = { min = 0.05 }\n\
         [robot]\nbase = [0.8, -0.8, 0.0]",
    )
    .unwrap();
    let problem = Problem::from_spec(&model, &spec).unwrap();
    (model, problem)
}

#[test]
fn paper_misses_a_thin_part_between_its_samples_the_search_detects() {
    let (model, problem) = door_and_plate();
    // Start and goal states (and the mixed ones) are collision-free: only the door's sweep
    // meets the plate.
    let mut data = SceneData::new(&model);
    for (door, plate) in [(0.0, 0.0), (1.2, 0.0), (0.0, 0.05), (1.2, 0.05)] {
        let mut s = problem.start.clone();
        s.set_by_name(&model, "door_hinge", door).unwrap();
        s.set_by_name(&model, "plate_slide", plate).unwrap();
        forward_kinematics(&model, &mut data, &s).unwrap();
        assert!(
            collisions(&model, &data, &CollisionSettings::default())
                .unwrap()
                .is_empty()
        );
    }

    let paper = run(&model, &problem, Strategy::Paper { seed: 1 });
    let Outcome::Solved(p) = &paper.outcome else {
        panic!(
            "the paper's planner should miss the plate: {:?}",
            paper.outcome
        )
    };
    assert_eq!(p.steps.len(), 2);
    assert_eq!(
        paper.stats.samples, 1,
        "no box overlaps: the first order passes"
    );
    let door_step = p
        .steps
        .iter()
        .position(|s| s.joint == "door_hinge")
        .unwrap();
    let v = validate(&model, &problem, &p.steps, &TaskSettings::default()).unwrap();
    assert!(!v.valid);
    let (step, why) = v.first_failure.expect("the door's sweep hits the plate");
    assert_eq!(step, door_step, "{why}");
    assert!(
        why.contains("part \"door\" collides with part \"plate\""),
        "{why}"
    );

    let search = run(&model, &problem, Strategy::Search);
    let Outcome::Infeasible(why) = &search.outcome else {
        panic!("the plate blocks every opening: {:?}", search.outcome)
    };
    assert!(why.unreached.contains(&"door_hinge".to_string()), "{why:?}");
    assert!(
        why.conflicts.iter().any(|f| matches!(
            &f.cause,
            Cause::Collision { other: BodyName::Part(n), .. } if n == "plate"
        )),
        "{why:?}"
    );
}

/// The thin plate of [`door_and_plate`] as a base shape (fixed at slide value 0).
fn thin_plate() -> BaseShape {
    BaseShape::new(
        "plate",
        Shape::box_size(Vector3::new(0.04, 0.002, 0.7)),
        Isometry3::translation(0.505, 0.078, 0.35),
    )
}

/// A 0.3 m block in the door's swing, centred 0.35 m from the hinge at 45°: x, y ∈
/// [0.097, 0.397], z ∈ [0, 0.7]. The door's front face meets its corner (0.397, 0.097) at
/// about 12° (the corner's distance from the door's radial line reaches 0.01 m), and the
/// block also occupies the door's target 1.2 rad. The door's box at its 18° configuration
/// overlaps it: x ∈ [−0.003, 0.479] (up to 0.5 cos 18° + 0.01 sin 18°), y ∈ [−0.010, 0.164]
/// (up to 0.5 sin 18° + 0.01 cos 18°), z ∈ [0, 0.7].
fn block() -> BaseShape {
    let c = 0.35 * std::f64::consts::FRAC_1_SQRT_2;
    BaseShape::new(
        "block",
        Shape::box_size(Vector3::new(0.3, 0.3, 0.7)),
        Isometry3::translation(c, c, 0.35),
    )
}

/// The paper's box rule concerns the manipulated parts only: base shapes never reject an
/// order, whether the door's boxes miss them (the thin plate) or overlap them (the block).
/// The validator and the search see both.
#[test]
fn paper_ignores_base_shapes() {
    for (obstacle, name) in [(thin_plate(), "plate"), (block(), "block")] {
        let model = one_door(vec![obstacle]);
        let problem = open_door_problem(&model);
        let paper = run(&model, &problem, Strategy::Paper { seed: 1 });
        let Outcome::Solved(p) = &paper.outcome else {
            panic!(
                "{name}: Paper does not box base shapes: {:?}",
                paper.outcome
            )
        };
        assert_eq!(p.steps.len(), 1, "{name}");
        let v = validate(&model, &problem, &p.steps, &TaskSettings::default()).unwrap();
        let (step, why) = v.first_failure.expect("the door's sweep hits the obstacle");
        assert_eq!(step, 0);
        assert!(
            why.contains(&format!("base shape \"{name}\"")),
            "{name}: {why}"
        );
        let search = run(&model, &problem, Strategy::Search);
        let Outcome::Infeasible(why) = &search.outcome else {
            panic!("{name} blocks every opening: {:?}", search.outcome)
        };
        assert!(
            why.conflicts.iter().any(|f| matches!(
                &f.cause,
                Cause::Collision { other: BodyName::Base(n), .. } if n == name
            )),
            "{name}: {why:?}"
        );
    }
}

/// Three doors 1.5 m apart along x (hinges at x = -1.5, 0, 1.5), handles on the -y face, robot
/// in front of the middle one; every order is feasible.
fn three_doors() -> (SceneModel, Problem) {
    let mut b = SceneModelBuilder::new();
    b.nav_settings(NavGridSettings {
        bounds: Some(GridBounds {
            min: Point2::new(-3.0, -2.0),
            max: Point2::new(3.0, 2.0),
        }),
        ..NavGridSettings::default()
    });
    for (name, x) in [("left", -1.5), ("middle", 0.0), ("right", 1.5)] {
        b.add_part(door(
            name,
            Isometry3::translation(x, 0.0, 0.0),
            Vector3::z(),
            -1.0,
        ));
    }
    let model = b.build().unwrap();
    let spec = GoalSpec::from_toml(
        "[goal]\nleft_hinge = { min = 1.2 }\nmiddle_hinge = { min = 1.2 }\n\
         right_hinge = { min = 1.2 }\n[robot]\nbase = [0.3, -1.0, 0.0]",
    )
    .unwrap();
    let problem = Problem::from_spec(&model, &spec).unwrap();
    (model, problem)
}

fn order(result: &PlanResult) -> Vec<String> {
    match &result.outcome {
        Outcome::Solved(p) => p.steps.iter().map(|s| s.joint.clone()).collect(),
        other => panic!("expected a plan, got {other:?}"),
    }
}

#[test]
fn random_is_deterministic_for_a_seed() {
    let (model, problem) = three_doors();
    let settings = TaskSettings::default();
    let mut orders = BTreeSet::new();
    for seed in 0..12 {
        let first = run(&model, &problem, Strategy::Random { seed });
        let again = run(&model, &problem, Strategy::Random { seed });
        assert_eq!(first.outcome, again.outcome, "seed {seed}");
        assert_eq!(first.stats.samples, 1);
        let o = order(&first);
        assert_eq!(o.len(), 3);
        let Outcome::Solved(p) = &first.outcome else {
            unreachable!()
        };
        let v = validate(&model, &problem, &p.steps, &settings).unwrap();
        assert!(v.valid, "seed {seed}: {v:?}");
        orders.insert(o);
    }
    // The seed matters: twelve seeds do not all give the same of the 6 orders.
    assert!(orders.len() >= 2, "{orders:?}");
}

/// A cabinet drawer (`drawer`, slide `drawer_slide` along -y from y = 0, 0.3 m wide, at
/// z ∈ [0.4, 0.6]) behind a door (`door`, hinge `door_hinge` at (-0.25, -0.05), axis -z so
/// that opening swings it towards -y, its back face 4 cm in front of the drawer).
///
/// Sliding the drawer out 0.3 m with the door closed drives its front (y = 0 → -0.3)
/// through the door (y ∈ [-0.06, -0.04]). With the door at 1.5 rad its slab lies at
/// x <= -0.25 + 0.5 cos 1.5 + 0.01 sin 1.5 = -0.205, clear of the drawer (x >= -0.15).
fn door_and_drawer() -> (SceneModel, Problem) {
    let mut b = SceneModelBuilder::new();
    b.nav_settings(square_grid(2.0));
    b.add_part(door(
        "door",
        Isometry3::translation(-0.25, -0.05, 0.25),
        -Vector3::z(),
        -1.0,
    ));
    b.add_part(
        PartSpec::on_base(
            "drawer",
            Joint::prismatic(
                "drawer_slide",
                Point3::new(0.0, 0.0, 0.5),
                -Vector3::y(),
                Limits::new(0.0, 0.4),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.3, 0.4, 0.2)),
            Isometry3::translation(0.0, 0.2, 0.0),
        )
        .with_handle(Handle::new(
            "drawer_handle",
            Point3::new(0.0, -0.01, 0.0),
            -Vector3::y(),
        )),
    );
    let model = b.build().unwrap();
    let spec = GoalSpec::from_toml(
        "[goal]\ndoor_hinge = { min = 1.5 }\ndrawer_slide = { min = 0.3 }\n\
         [robot]\nbase = [0.9, -1.2, 0.0]",
    )
    .unwrap();
    let problem = Problem::from_spec(&model, &spec).unwrap();
    (model, problem)
}

#[test]
fn random_fails_on_the_wrong_order_and_its_plans_validate() {
    let (model, problem) = door_and_drawer();
    let settings = TaskSettings::default();
    let (mut solved, mut failed) = (0, 0);
    for seed in 0..16 {
        let r = run(&model, &problem, Strategy::Random { seed });
        match &r.outcome {
            Outcome::Solved(p) => {
                solved += 1;
                assert_eq!(order(&r), ["door_hinge", "drawer_slide"]);
                let v = validate(&model, &problem, &p.steps, &settings).unwrap();
                assert!(v.valid, "seed {seed}: {v:?}");
            }
            Outcome::Infeasible(why) => {
                failed += 1;
                assert_eq!(why.conflicts.len(), 1);
                let f = &why.conflicts[0];
                assert_eq!(f.joint, "drawer_slide", "{why:?}");
                assert!(
                    matches!(&f.cause, Cause::Collision { other: BodyName::Part(n), .. } if n == "door"),
                    "{why:?}"
                );
                assert_eq!(why.unreached, ["drawer_slide", "door_hinge"]);
            }
            other => panic!("unexpected {other:?}"),
        }
    }
    // Each of the 2 orders has probability 1/2 per seed; 16 seeds show both.
    assert!(solved > 0 && failed > 0, "solved {solved}, failed {failed}");
}

#[test]
fn paper_orders_the_door_before_the_drawer() {
    let (model, problem) = door_and_drawer();
    for seed in 0..4 {
        let r = run(&model, &problem, Strategy::Paper { seed });
        assert_eq!(order(&r), ["door_hinge", "drawer_slide"], "seed {seed}");
        assert!((1..=2).contains(&r.stats.samples));
        let Outcome::Solved(p) = &r.outcome else {
            unreachable!()
        };
        assert!(
            p.steps
                .iter()
                .all(|s| s.base.is_some() && s.handle.is_some())
        );
        let v = validate(&model, &problem, &p.steps, &TaskSettings::default()).unwrap();
        assert!(v.valid, "{v:?}");
    }
}

/// Two doors facing each other across a 0.8 m corridor: `a` hinged at the origin opening
/// towards +y (axis +z), `b` hinged at (0, 0.8) opening towards -y (axis -z); goal: both
/// at least 1.4 rad. At exactly 1.4 rad both slabs contain the point
/// (0.406 cos 1.4, 0.406 sin 1.4) (arc length s solves s sin 1.4 = 0.8 − s sin 1.4), so the
/// *Paper* planner, which moves each door to the nearest target value, finds every order
/// overlapping (each door's 90° box meets the other's open box). Opening `a` to its limit
/// 1.6 rad (past 90°, leaning away from `b`) solves it.
fn facing_doors() -> (SceneModel, Problem) {
    let mut b = SceneModelBuilder::new();
    b.nav_settings(square_grid(2.0));
    b.add_part(door("a", Isometry3::identity(), Vector3::z(), 1.0));
    b.add_part(door(
        "b",
        Isometry3::translation(0.0, 0.8, 0.0),
        -Vector3::z(),
        -1.0,
    ));
    let model = b.build().unwrap();
    let spec = GoalSpec::from_toml(
        "[goal]\na_hinge = { min = 1.4 }\nb_hinge = { min = 1.4 }\n[robot]\nbase = [1.0, 0.4, 0.0]",
    )
    .unwrap();
    let problem = Problem::from_spec(&model, &spec).unwrap();
    (model, problem)
}

#[test]
fn paper_is_infeasible_once_every_order_is_rejected() {
    let (model, problem) = facing_doors();
    let r = run(&model, &problem, Strategy::Paper { seed: 9 });
    let Outcome::Infeasible(why) = &r.outcome else {
        panic!("both orders overlap: {:?}", r.outcome)
    };
    assert_eq!(r.stats.samples, 2, "2! orders, each tried once");
    assert!(!why.conflicts.is_empty());
    assert!(
        why.conflicts
            .iter()
            .all(|f| matches!(f.cause, Cause::Collision { .. }))
    );
    // The search is not limited to the nearest target values.
    let search = run(&model, &problem, Strategy::Search);
    let Outcome::Solved(p) = &search.outcome else {
        panic!("opening a past 90° solves it: {:?}", search.outcome)
    };
    let v = validate(&model, &problem, &p.steps, &TaskSettings::default()).unwrap();
    assert!(v.valid, "{v:?}");
}

#[test]
fn paper_times_out_at_its_sample_limit() {
    let (model, problem) = facing_doors();
    let settings = TaskSettings {
        strategy: Strategy::Paper { seed: 9 },
        max_samples: 1,
        ..TaskSettings::default()
    };
    let r = plan(
        &model,
        &problem,
        &settings,
        &NoRefinement,
        &Termination::none(),
    )
    .unwrap();
    let Outcome::Timeout(partial) = &r.outcome else {
        panic!("one sample cannot exhaust 2 orders: {:?}", r.outcome)
    };
    assert_eq!(r.stats.samples, 1);
    assert!(
        partial.plan.steps.is_empty(),
        "every prefix is rejected by boxes"
    );
    assert_eq!(partial.unmet, ["a_hinge", "b_hinge"]);
}

#[test]
fn baselines_skip_goal_joints_met_at_the_start() {
    let model = one_door(Vec::new());
    let spec =
        GoalSpec::from_toml("[goal]\ndoor_hinge = { max = 0.5 }\n[robot]\nbase = [0.8, -0.8, 0.0]")
            .unwrap();
    let problem = Problem::from_spec(&model, &spec).unwrap();
    for strategy in [Strategy::Random { seed: 0 }, Strategy::Paper { seed: 0 }] {
        let r = run(&model, &problem, strategy);
        assert_eq!(
            r.outcome,
            Outcome::Solved(Default::default()),
            "{strategy:?}"
        );
    }
}

/// The kitchen's dishwasher goal (examples/scenes/goals/dishwasher.toml): the door and the
/// rack riding on it are one kinematic chain, so their boxes never reject an order, and the
/// tub and the worktop are base shapes, which the paper's rule does not box. Every order is
/// therefore decided by the robot's path rule alone. Rack first is rejected by it: with the
/// door closed the rack's handle faces straight up inside the tub, steeper than
/// `max_normal_elevation` (1 rad) from horizontal, so no base pose can grasp it. Door first
/// passes, so *Paper* returns door first for every seed, and that plan validates.
#[test]
fn paper_solves_the_dishwasher_door_first_for_every_seed() {
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    let model = kinscene::scene::urdf::read_file(
        scenes.join("kitchen.urdf"),
        &kinscene::scene::urdf::ImportOptions::default(),
    )
    .unwrap();
    let goal = std::fs::read_to_string(scenes.join("goals/dishwasher.toml")).unwrap();
    let problem = Problem::from_spec(&model, &GoalSpec::from_toml(&goal).unwrap()).unwrap();
    for seed in 0..6 {
        let r = run(&model, &problem, Strategy::Paper { seed });
        assert!(
            (1..=2).contains(&r.stats.samples),
            "seed {seed}: {:?}",
            r.stats
        );
        assert_eq!(
            order(&r),
            ["dishwasher_door_hinge", "dishwasher_rack_slide"],
            "seed {seed}"
        );
        let Outcome::Solved(p) = &r.outcome else {
            unreachable!()
        };
        let v = validate(&model, &problem, &p.steps, &TaskSettings::default()).unwrap();
        assert!(v.valid, "seed {seed}: {v:?}");
    }
}
