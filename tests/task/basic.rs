//! Smallest cases of the search, with hand-derived expectations.

use kinscene::scene::{Handle, Joint, Limits, PartSpec, SceneModel, SceneModelBuilder, Shape};
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
