//! Smallest cases of the search, with hand-derived expectations.

use kinscene::scene::{
    BaseShape, Handle, Joint, Limits, PartSpec, SceneModel, SceneModelBuilder, Shape,
};
use kinscene::task::{GoalSpec, NoRefinement, Outcome, Problem, TaskSettings, Termination, plan};
use nalgebra::{Isometry3, Point3, Vector3};

/// A 0.5 m door hinged about z at the origin, closed along +x, handle near the free edge on
/// the -y face.
fn door() -> SceneModel {
    let mut b = SceneModelBuilder::new();
    b.add_part(
        PartSpec::on_base(
            "door",
            Joint::revolute(
                "hinge",
                Point3::origin(),
                Vector3::z(),
                Limits::new(0.0, 1.6),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.5, 0.02, 0.7)),
            Isometry3::translation(0.25, 0.0, 0.35),
        )
        .with_handle(Handle::new(
            "door_handle",
            Point3::new(0.45, -0.03, 0.35),
            -Vector3::y(),
        )),
    );
    b.build().unwrap()
}

#[test]
fn single_door_opens_in_one_step() {
    let model = door();
    let spec =
        GoalSpec::from_toml("[goal]\nhinge = { min = 1.2 }\n[robot]\nbase = [0.8, -0.8, 0.0]")
            .unwrap();
    let problem = Problem::from_spec(&model, &spec).unwrap();
    let r = plan(
        &model,
        &problem,
        &TaskSettings::default(),
        &NoRefinement,
        &Termination::none(),
    )
    .unwrap();
    let Outcome::Solved(p) = r.outcome else {
        panic!("expected a plan, got {:?}", r.outcome)
    };
    assert_eq!(p.steps.len(), 1, "{p:?}");
    assert_eq!(p.steps[0].joint, "hinge");
    assert!(p.steps[0].to >= 1.2);
    eprintln!("{p:#?} {:?}", r.stats);
}

/// A robot that starts farther from every body than the navigation grid's automatic padding
/// (1 m): the model's grid spans the base shapes only (none here: [-1, 1]² about the origin),
/// so (3.5, -2.5) is off it. The grid grows to the start instead of rejecting it, and the plan
/// drives there: by the triangle inequality its grid path is at least as long as the straight
/// line from the start to the base pose it chooses, and the independent validator (its own
/// grid search on the grown grid) accepts it.
#[test]
fn a_start_beyond_the_grid_padding_grows_the_grid() {
    let model = door();
    let (sx, sy) = (3.5, -2.5);
    assert!(
        model
            .base_grid()
            .cell_of(nalgebra::Point2::new(sx, sy))
            .is_none(),
        "the start is off the model's own grid"
    );
    let spec = GoalSpec::from_toml(&format!(
        "[goal]\nhinge = {{ min = 1.2 }}\n[robot]\nbase = [{sx}, {sy}, 0.0]"
    ))
    .unwrap();
    let problem = Problem::from_spec(&model, &spec).unwrap();
    let settings = TaskSettings::default();
    let r = plan(
        &model,
        &problem,
        &settings,
        &NoRefinement,
        &Termination::none(),
    )
    .unwrap();
    let Outcome::Solved(p) = r.outcome else {
        panic!("expected a plan, got {:?}", r.outcome)
    };
    assert_eq!(p.steps.len(), 1, "{p:?}");
    let [bx, by, _] = p.steps[0].base.expect("the step has a base pose");
    let straight = (bx - sx).hypot(by - sy);
    assert!(
        p.steps[0].travel >= straight - 1e-9,
        "travel {} < straight line {straight}",
        p.steps[0].travel
    );
    let v = kinscene::task::validate(&model, &problem, &p.steps, &settings).unwrap();
    assert!(v.valid, "{v:?}");

    // The brute-force predicate borrows its model and cannot grow it: on the model as given
    // it names the remedy, and on the covering model it finds the planned move feasible.
    let lattice = kinscene::task::Lattice::new(&model, &problem, &settings.lattice);
    let err = kinscene::task::Feasibility::new(&model, &problem, &settings, &lattice)
        .err()
        .expect("a start off the automatic grid is refused by the borrowing predicate");
    assert!(err.to_string().contains("covering"), "{err}");
    let grown = model.covering(&problem.robot.start_point()).unwrap();
    let lattice = kinscene::task::Lattice::new(&grown, &problem, &settings.lattice);
    let mut f = kinscene::task::Feasibility::new(&grown, &problem, &settings, &lattice).unwrap();
    let hinge = grown.joint_id("hinge").unwrap();
    let to = lattice.values(hinge).len() - 1;
    let start = vec![
        lattice
            .index_of(hinge, 0.0)
            .expect("the closed door is on the lattice"),
    ];
    assert!(
        matches!(
            f.check(&start, hinge, to).unwrap(),
            kinscene::task::MoveCheck::Feasible { .. }
        ),
        "opening the door fully is feasible from the grown grid's start"
    );
}

/// A panel sliding 2.4 m along +x (handle facing −y at height 0.35, from x = 0.2 to 2.6): no
/// base position is within `reach_max` = 0.9 m of both ends (2.4 > 2 × 0.9), so with one base
/// position per move the goal has no base pose. With two, the robot covers the first half
/// from about (0.8, −0.5) and the second from about (2.0, −0.5): each within 0.9 m of its
/// half's 1.2 m of travel (√(0.6² + 0.47²) ≈ 0.76 m) and on the handle's front side. The plan
/// validates with the same settings, and its base position covers the motion's start only.
/// A wall 0.3 m behind the track keeps the grid around the whole travel.
/// The panel of [`a_long_slide_needs_two_base_positions`] and its goal (slide to 2.4 m).
fn long_slide() -> (kinscene::scene::SceneModel, Problem) {
    let mut b = SceneModelBuilder::new();
    b.add_part(
        PartSpec::on_base(
            "panel",
            Joint::prismatic(
                "slide",
                Point3::origin(),
                Vector3::x(),
                Limits::new(0.0, 2.4),
            ),
        )
        .with_collider(
            Shape::box_size(Vector3::new(0.4, 0.02, 0.7)),
            Isometry3::translation(0.0, 0.0, 0.35),
        )
        .with_handle(Handle::new(
            "panel_handle",
            Point3::new(0.2, -0.03, 0.35),
            -Vector3::y(),
        )),
    );
    // A wall behind the track, from x = −1 to 3.6: the automatic grid spans it (plus 1 m).
    b.add_base_shape(BaseShape::new(
        "wall",
        Shape::box_size(Vector3::new(4.6, 0.1, 1.0)),
        Isometry3::translation(1.3, 0.3, 0.5),
    ));
    let model = b.build().unwrap();
    let spec = GoalSpec::from_toml(
        "[goal]\nslide = { min = 2.4 }\n[robot]\nbase = [0.8, -1.0, 0.0]\nradius = 0.2",
    )
    .unwrap();
    let problem = Problem::from_spec(&model, &spec).unwrap();
    (model, problem)
}

#[test]
fn a_long_slide_needs_two_base_positions() {
    let (model, problem) = long_slide();
    let settings = |segments| {
        let mut s = TaskSettings::default();
        s.manipulation.segments = segments;
        // No part-way value: the slide moves 0 → 2.4 in one move (with the default interior
        // value 1.2 the search would split it into two moves itself).
        s.lattice.interior_values = 0;
        s
    };
    let one = settings(1);
    let r = plan(&model, &problem, &one, &NoRefinement, &Termination::none()).unwrap();
    assert!(
        matches!(r.outcome, Outcome::Infeasible(_)),
        "one base position cannot cover 2.4 m: {:?}",
        r.outcome
    );
    let two = settings(2);
    let r = plan(&model, &problem, &two, &NoRefinement, &Termination::none()).unwrap();
    let Outcome::Solved(p) = r.outcome else {
        panic!("expected a plan in two segments, got {:?}", r.outcome)
    };
    assert_eq!(p.steps.len(), 1, "{p:?}");
    let [x, y, _] = p.steps[0].base.expect("a base pose");
    // Within reach of the handle's start (0.2, −0.03) and out of reach of its end (2.6, −0.03).
    assert!((x - 0.2).hypot(y + 0.03) <= 0.9 + 1e-9, "({x}, {y})");
    assert!((x - 2.6).hypot(y + 0.03) > 0.9, "({x}, {y})");
    let v = kinscene::task::validate(&model, &problem, &p.steps, &two).unwrap();
    assert!(v.valid, "{v:?}");
    // The validator's own segmented rule is the setting's: with one segment the same step
    // breaks the base-pose rule.
    let v = kinscene::task::validate(&model, &problem, &p.steps, &one).unwrap();
    assert!(!v.valid, "{v:?}");
}

/// The report of an infeasible goal says which limit of the manipulation region no base
/// cell meets, in numbers (`Cause::NoBasePose`'s shortfall), on the panel of
/// [`a_long_slide_needs_two_base_positions`]:
/// - one base position per move: the handle's 17 waypoints (16 steps over 2.4 m, 0.15 m
///   apart) are each within reach of some cell, but one cell within `reach_max` = 0.9 m of
///   waypoints 0..=e needs 0.15·e ≤ 1.8, so it holds at most 13 (e = 12), and a cell 0.3 m
///   in front of the track holds waypoints 0..=10 (√(0.75² + 0.3²) = 0.81 ≤ 0.9), so at
///   least 11;
/// - a grasp band below the handle (`height_max` = 0.3): the handle's height 0.35 m (its
///   grasp point) at waypoint 0, exactly.
#[test]
fn an_infeasible_report_gives_the_reach_limit_in_numbers() {
    use kinscene::task::{Cause, ReachLimit};
    let (model, problem) = long_slide();
    let shortfall = |s: &TaskSettings| {
        let r = plan(&model, &problem, s, &NoRefinement, &Termination::none()).unwrap();
        let Outcome::Infeasible(why) = r.outcome else {
            panic!("expected infeasible, got {:?}", r.outcome)
        };
        let Some(Cause::NoBasePose { shortfall: Some(s) }) =
            why.conflicts.first().map(|f| f.cause.clone())
        else {
            panic!("expected a shortfall in numbers: {why:?}")
        };
        (*s, why.message)
    };
    let mut s = TaskSettings::default();
    s.lattice.interior_values = 0;
    let (split, message) = shortfall(&s);
    assert_eq!(split.handle, "panel_handle");
    assert_eq!(split.waypoints, 17);
    let ReachLimit::Split { held, segments } = split.limit else {
        panic!("expected a split: {split:?}")
    };
    assert!((11..=13).contains(&held), "{split:?}");
    assert_eq!(segments, 1);
    assert!(
        message.contains(&format!("holds at most the first {held}")),
        "{message}"
    );
    s.manipulation.height_max = 0.3;
    let (band, message) = shortfall(&s);
    let ReachLimit::Height {
        waypoint,
        z,
        band: b,
    } = band.limit
    else {
        panic!("expected the height band: {band:?}")
    };
    assert_eq!(waypoint, 0);
    assert!((z - 0.35).abs() < 1e-12, "{z}");
    assert_eq!(b, [0.0, 0.3]);
    assert!(message.contains("height 0.350 m"), "{message}");
}
