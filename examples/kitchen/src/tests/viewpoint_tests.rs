//! The mapping viewpoints computed from the base map, on the kitchen and on the galley (a
//! scene the computation was not tuned on): every viewpoint is free for the robot's footprint
//! and reached by the simulator's navigation, and every handle of the scene that faces the
//! room (its outward normal within 45° of horizontal) is seen from at least one of them by a
//! detector that never misses. (The kitchen's dishwasher rack handle faces up inside the
//! closed tub: no camera sees it until the door is open.)

use kinscene::discovery::{Hardware, Perception};
use kinscene::kinematics::robot::RobotModel;
use kinscene::scene::nav::occupancy;
use kinscene::scene::urdf::{ImportOptions, read_file};
use kinscene::scene::{SceneData, SceneModel, forward_kinematics, world_from_handle};
use kinscene::task::GoalSpec;
use nalgebra::Point2;

use crate::pipeline::viewpoints::{ViewpointSettings, viewpoints};
use crate::pipeline::{START_BASE, pose};
use crate::sim::{SimSettings, SimWorld};

fn scene(file: &str) -> SceneModel {
    let path = crate::repository().join("examples/scenes").join(file);
    read_file(&path, &ImportOptions::default()).expect("the shipped scene loads")
}

/// Each handle's name and how many viewpoints saw it (a detection within 2 cm: the detector
/// is noiseless here), after checking every viewpoint against the true scene's occupancy grid
/// inflated by the footprint radius and driving to it.
fn coverage(truth: &SceneModel, start: [f64; 3]) -> (Vec<[f64; 3]>, Vec<(String, usize)>) {
    let robot = RobotModel::kinova_gen3_mobile();
    let radius = robot.base().footprint_radius;
    let views = viewpoints(truth.base(), radius, start, &ViewpointSettings::default())
        .expect("viewpoints are computed");
    assert!(!views.is_empty() && views.len() <= ViewpointSettings::default().max_views);
    let mut data = SceneData::new(truth);
    forward_kinematics(truth, &mut data, &truth.zero_state()).expect("zero state");
    let grid = occupancy(truth, &data)
        .and_then(|g| g.inflate(radius))
        .expect("occupancy grid");
    for v in &views {
        let (i, j) = grid
            .cell_of(Point2::new(v[0], v[1]))
            .expect("a viewpoint on the grid");
        assert!(!grid.is_occupied(i, j), "viewpoint {v:?} is not free");
    }
    let mut settings = SimSettings::default();
    settings.detector.miss_rate = 0.0;
    settings.detector.false_positives = 0.0;
    settings.detector.position_noise = 0.0;
    let start_pose = pose(start);
    let mut world = SimWorld::new(truth, &robot, start_pose, settings).expect("world");
    let handles: Vec<(String, nalgebra::Point3<f64>)> = truth
        .handles()
        .filter_map(|(id, h)| {
            let p = world_from_handle(truth, &data, id).expect("handle pose");
            let facing_the_room = p.normal.z.abs() <= std::f64::consts::FRAC_1_SQRT_2;
            facing_the_room.then(|| (h.name.clone(), p.position))
        })
        .collect();
    let mut seen = vec![0; handles.len()];
    for v in &views {
        world
            .navigate_to(&pose(*v))
            .unwrap_or_else(|e| panic!("viewpoint {v:?} not reached: {e}"));
        let detections = world.detect_handles().expect("detector");
        for (k, (_, p)) in handles.iter().enumerate() {
            if detections.iter().any(|d| (d.position - p).norm() < 0.02) {
                seen[k] += 1;
            }
        }
    }
    let counts = handles.into_iter().map(|(n, _)| n).zip(seen).collect();
    (views, counts)
}

fn assert_all_seen(views: &[[f64; 3]], counts: &[(String, usize)]) {
    let unseen: Vec<&str> = counts
        .iter()
        .filter(|(_, n)| *n == 0)
        .map(|(h, _)| h.as_str())
        .collect();
    assert!(
        unseen.is_empty(),
        "handles seen from no viewpoint: {unseen:?}\nviewpoints: {views:?}\ncounts: {counts:?}"
    );
}

#[test]
fn computed_viewpoints_see_every_galley_handle() {
    let truth = scene("galley.urdf");
    let goal = crate::repository().join("examples/scenes/goals/galley.toml");
    let text = std::fs::read_to_string(goal).expect("the galley's goal file");
    let spec = GoalSpec::from_toml(&text).expect("a goal document");
    let start = spec
        .robot
        .base
        .expect("the galley's goal gives the start pose");
    let (views, counts) = coverage(&truth, start);
    assert_all_seen(&views, &counts);
}

#[test]
fn computed_viewpoints_see_every_kitchen_handle() {
    let truth = scene("kitchen.urdf");
    let (views, counts) = coverage(&truth, START_BASE);
    assert_all_seen(&views, &counts);
}
