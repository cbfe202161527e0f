//! A robot whose mobile base is modelled as joints (prismatic x, prismatic y and a yaw joint
//! from an `odom` link, as several simulators export it) plans end to end: the shipped Gen3
//! URDF wrapped in such a chain, loaded through a robot description, opens the counter's
//! drawer, and the independent re-checker of `contact.rs`, reading the wrapped URDF with the
//! base joints held at 0 (so `odom` is where the base pose puts `base_link`), accepts the plan.
//! It also opens a cabinet door and then the drawer the closed door blocks.

use std::path::PathBuf;

use kinscene::kinematics::robot::RobotModel;
use kinscene::planner::{HierarchicalPlanner, PlannerSettings};

use super::contact::{RobotGeometry, recheck_robot, solve_with};

/// The shipped Gen3 URDF with `odom → base_x → base_y → base_yaw → base_link`, written next to
/// a description that points at it and at the shipped SRDF; the description's path.
fn gen3_on_base_joints() -> (PathBuf, PathBuf) {
    let robots = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("robots");
    let text = std::fs::read_to_string(robots.join("kinova_gen3_mobile.urdf")).unwrap();
    let chain = [
        ("base_x", "prismatic", "1 0 0", "odom", "carriage_x"),
        ("base_y", "prismatic", "0 1 0", "carriage_x", "carriage_y"),
        ("base_yaw", "continuous", "0 0 1", "carriage_y", "base_link"),
    ];
    let mut extra = String::from(
        "<link name=\"odom\"/><link name=\"carriage_x\"/><link name=\"carriage_y\"/>\n",
    );
    for (name, kind, axis, parent, child) in chain {
        extra += &format!(
            "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/>\
             <child link=\"{child}\"/><origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>\
             <axis xyz=\"{axis}\"/><limit lower=\"-100\" upper=\"100\" velocity=\"1\" \
             effort=\"1\"/></joint>\n"
        );
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("gen3_base_joints");
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("gen3_base_joints.urdf");
    std::fs::write(&urdf, text.replace("</robot>", &(extra + "</robot>"))).unwrap();
    let description = dir.join("gen3_base_joints.toml");
    let srdf = robots.join("kinova_gen3_mobile.srdf");
    std::fs::write(
        &description,
        format!(
            "urdf = {:?}\nsrdf = {:?}\n[tool]\nlink = \"tool_frame\"\n[base]\n\
             kind = \"holonomic\"\nmax_velocity = [0.5, 0.5, 1.0]\n\
             max_acceleration = [0.5, 0.5, 1.0]\n",
            urdf.display().to_string(),
            srdf.display().to_string()
        ),
    )
    .unwrap();
    (urdf, description)
}

/// The re-checker's geometry: the wrapped URDF with the base joints held at 0.
fn on_joints(urdf: PathBuf) -> RobotGeometry {
    RobotGeometry {
        urdf,
        frozen: ["base_x", "base_y", "base_yaw"]
            .map(|j| (j.to_string(), 0.0))
            .to_vec(),
        ..RobotGeometry::gen3()
    }
}

#[test]
fn a_base_modelled_as_joints_plans_the_drawer_and_the_plan_rechecks() {
    let (urdf, description) = gen3_on_base_joints();
    let robot = RobotModel::from_description_file(&description).expect("the description loads");
    // The base joints are the base, not arm joints: the arm is the Gen3's seven.
    assert_eq!(robot.dof(), 7);
    let planner = HierarchicalPlanner::new(robot, PlannerSettings::default()).unwrap();
    let model = super::counter_with_drawer(0.75);
    let problem = super::problem(
        &model,
        "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-0.9, 0.0, 0.0]\n",
    );
    let (planner, plan) = solve_with(planner, &model, &problem);
    let report = recheck_robot(&on_joints(urdf), &planner, &model, &problem.start, &plan)
        .unwrap_or_else(|v| panic!("{v}"));
    eprintln!("base joints: {report}");
    assert!(report.contact_samples > 0);
}

/// The cabinet of `differential.rs` (its drawer runs through the closed door; see there): the
/// Gen3 on base joints opens the door first, then the drawer, and the re-checker accepts it.
#[test]
fn a_base_modelled_as_joints_opens_the_door_then_the_drawer() {
    let (urdf, description) = gen3_on_base_joints();
    let robot = RobotModel::from_description_file(&description).expect("the description loads");
    let planner = HierarchicalPlanner::new(robot, PlannerSettings::default()).unwrap();
    let model = super::differential::cabinet_with_door_and_drawer();
    let problem = super::problem(
        &model,
        "[goal]\ndoor_hinge = { min = 1.5 }\ndrawer_slide = { min = 0.25 }\n\
         [robot]\nbase = [-1.3, 0.5, 0.0]\n",
    );
    let (planner, plan) = solve_with(planner, &model, &problem);
    let order: Vec<&str> = plan.steps.iter().map(|s| s.joint.as_str()).collect();
    let first_drawer = order.iter().position(|j| *j == "drawer_slide").unwrap();
    assert!(
        order[..first_drawer].contains(&"door_hinge"),
        "the door opens first: {order:?}"
    );
    let report = recheck_robot(&on_joints(urdf), &planner, &model, &problem.start, &plan)
        .unwrap_or_else(|v| panic!("{v}"));
    eprintln!("base joints, door then drawer {order:?}: {report}");
    assert!(report.contact_samples > 0);
}
