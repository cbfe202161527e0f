//! Robot description files (TOML): the shipped descriptions load (the Gen3's to the same model
//! as `RobotModel::kinova_gen3_mobile`, TIAGo's from example-robot-data), bad descriptions are
//! typed errors naming their field, and a base modelled as x/y/yaw joints is recognised.

use std::path::{Path, PathBuf};

use kinscene::kinematics::robot::{
    BaseKind, RobotCollision, RobotConfig, RobotDescription, RobotError, RobotModel,
};
use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::third_party::example_robot_data;

fn robots() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("robots")
}

/// Only `EXAMPLE_ROBOT_DATA`, set to the venv's copy.
fn vars(name: &str) -> Option<String> {
    (name == "EXAMPLE_ROBOT_DATA").then(|| example_robot_data().display().to_string())
}

/// `robots/gen3.toml` gives the model `RobotModel::kinova_gen3_mobile()` builds from the
/// compiled-in URDF and SRDF: the same links (with their colliders), joints, frozen joints,
/// frames, stow, allowed pairs and base.
#[test]
fn the_gen3_description_is_the_shipped_robot() {
    let loaded = RobotModel::from_description_file(&robots().join("gen3.toml")).unwrap();
    let shipped = RobotModel::kinova_gen3_mobile();
    assert_eq!(loaded.name(), shipped.name());
    assert_eq!(loaded.links(), shipped.links());
    assert_eq!(loaded.arm_joints(), shipped.arm_joints());
    assert_eq!(loaded.frozen_joints(), shipped.frozen_joints());
    assert_eq!(loaded.base_from_arm_root(), shipped.base_from_arm_root());
    assert_eq!(loaded.last_from_tool(), shipped.last_from_tool());
    assert_eq!(loaded.neutral(), shipped.neutral());
    assert_eq!(loaded.allowed_pairs(), shipped.allowed_pairs());
    assert!(loaded.allowed_pairs().is_some_and(|p| !p.is_empty()));
    assert_eq!(loaded.base(), shipped.base());
    // The SRDF's stow, not 0 clamped: Actuator1 = π there.
    assert_eq!(loaded.neutral()[0], std::f64::consts::PI);
}

/// `robots/tiago.toml` loads from example-robot-data through `${EXAMPLE_ROBOT_DATA}` and
/// `package://`: the 7-DoF arm above the frozen torso, the limits the file derives from the
/// URDF's wheels, a computed stow free of self-collision under sampled exemptions.
#[test]
fn the_tiago_description_loads_from_example_robot_data() {
    let path = robots().join("tiago.toml");
    let description = RobotDescription::from_file(&path).unwrap();
    let robot = RobotModel::from_description(&description, &robots(), &vars).unwrap();
    let arm: Vec<&str> = robot.arm_joints().iter().map(|j| j.name.as_str()).collect();
    assert_eq!(
        arm,
        (1..=7)
            .map(|k| format!("arm_{k}_joint"))
            .collect::<Vec<_>>()
    );
    let torso = robot
        .frozen_joints()
        .iter()
        .find(|f| f.name == "torso_lift_joint")
        .unwrap();
    assert_eq!(torso.value, 0.0);
    assert_eq!(robot.base().kind, BaseKind::DifferentialDrive);
    assert_eq!(robot.base().max_velocity, [1.0, 0.0, 4.9]);
    // The computed stow keeps the arm near the base (stretched out it reaches over 1 m; see
    // third_party.rs).
    assert!(
        robot.base().footprint_radius < 0.6,
        "{}",
        robot.base().footprint_radius
    );
    let pairs = robot.allowed_pairs().expect("sampled exemptions");
    assert!(!pairs.is_empty());
    let poses = robot
        .link_poses(&RobotConfig {
            base: [0.0; 3],
            arm: robot.neutral(),
        })
        .unwrap();
    assert_eq!(
        RobotCollision::new(&robot).unwrap().self_collision(&poses),
        None
    );
    // Without the variable: a typed error naming the package and the variable.
    let e = RobotModel::from_description(&description, &robots(), &|_| None).unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(&e, RobotError::Description { field, .. } if field == "packages.example-robot-data")
            && text.contains("EXAMPLE_ROBOT_DATA"),
        "{text}"
    );
}

/// A description of the shipped Gen3 URDF (absolute path) with `extra` appended.
fn gen3_description(srdf: bool, extra: &str) -> String {
    let mut text = format!(
        "urdf = {:?}\n",
        robots()
            .join("kinova_gen3_mobile.urdf")
            .display()
            .to_string()
    );
    if srdf {
        text += &format!(
            "srdf = {:?}\n",
            robots()
                .join("kinova_gen3_mobile.srdf")
                .display()
                .to_string()
        );
    }
    text + "[tool]\nlink = \"tool_frame\"\n" + extra
}

/// The error of loading `text`, as (field, message).
fn load_error(text: &str) -> (String, String) {
    let result = RobotDescription::parse(text)
        .and_then(|d| RobotModel::from_description(&d, &robots(), &|_| None));
    match result {
        Err(RobotError::Description { field, message }) => (field, message),
        Err(other) => panic!("not a description error: {other}"),
        Ok(_) => panic!("accepted:\n{text}"),
    }
}

/// Each bad description is a `RobotError::Description` naming the field or key at fault.
#[test]
fn bad_descriptions_name_their_field() {
    let (field, message) = load_error(&gen3_description(true, "colour = \"red\"\n"));
    assert!(
        message.contains("colour") && field.contains("[tool]"),
        "{field}: {message}"
    );
    let (field, message) = load_error(&gen3_description(true, "[base]\nkinds = \"x\"\n"));
    assert!(
        message.contains("kinds") && field.contains("[base]"),
        "{field}: {message}"
    );
    let (field, message) = load_error(&gen3_description(true, "[base]\nkind = \"tracked\"\n"));
    assert!(
        field == "base.kind" && message.contains("tracked"),
        "{field}: {message}"
    );
    let (field, _) = load_error(&gen3_description(
        true,
        "[base]\nmax_velocity = [0.5, 0.0, 1.0]\n",
    ));
    assert_eq!(field, "base.max_velocity[1]");
    // A differential drive moves forward and turns: its lateral limits must be 0.
    let (field, message) = load_error(&gen3_description(
        true,
        "[base]\nkind = \"differential_drive\"\nmax_velocity = [0.5, 0.5, 1.0]\n",
    ));
    assert!(
        field == "base.max_velocity[1]" && message.contains("lateral"),
        "{field}: {message}"
    );
    let (field, _) = load_error(&gen3_description(true, "[base]\nfootprint_radius = -1.0\n"));
    assert_eq!(field, "base.footprint_radius");
    // A footprint polygon: not with a radius too, and a polygon (a bow tie is not).
    let (field, message) = load_error(&gen3_description(
        true,
        "[base]\nfootprint_radius = 0.5\nfootprint = [[0, 0], [1, 0], [0, 1]]\n",
    ));
    assert!(
        field == "base.footprint" && message.contains("not both"),
        "{field}: {message}"
    );
    let (field, message) = load_error(&gen3_description(
        true,
        "[base]\nfootprint = [[0, 0], [1, 1], [1, 0], [0, 1]]\n",
    ));
    assert!(
        field == "base.footprint" && message.contains("cross"),
        "{field}: {message}"
    );
    let (_, message) = load_error("urdf = \"x.urdf\"\n");
    assert!(message.contains("tool"), "{message}");
    let (field, message) = load_error("[tool]\nlink = \"t\"\n");
    assert!(message.contains("urdf"), "{field}: {message}");
    let (field, _) = load_error("urdf = \"${NO_SUCH_VARIABLE}/r.urdf\"\n[tool]\nlink = \"t\"\n");
    assert_eq!(field, "urdf");
    let (field, _) = load_error("urdf = \"package://nope/r.urdf\"\n[tool]\nlink = \"t\"\n");
    assert_eq!(field, "urdf");
    // Stows: a joint that is not an arm joint, a missing one, one outside its limits.
    let full = |a2: f64| {
        format!(
            "[stow]\nActuator1 = 0.0\nActuator2 = {a2}\nActuator3 = 0.0\nActuator4 = 0.0\n\
             Actuator5 = 0.0\nActuator6 = 0.0\nActuator7 = 0.0\n"
        )
    };
    let (field, _) = load_error(&gen3_description(true, &(full(0.0) + "wheel = 0.0\n")));
    assert_eq!(field, "stow.wheel");
    let (field, message) = load_error(&gen3_description(true, "[stow]\nActuator1 = 0.0\n"));
    assert!(
        field == "stow.Actuator2" && message.contains("missing"),
        "{field}"
    );
    let (field, message) = load_error(&gen3_description(true, &full(10.0)));
    assert!(
        field == "stow.Actuator2" && message.contains("limits"),
        "{field}: {message}"
    );
    // The URDF loader's own errors keep their variants.
    let e = RobotDescription::parse(&gen3_description(false, "[arm]\nroot = \"nowhere\"\n"))
        .and_then(|d| RobotModel::from_description(&d, &robots(), &|_| None))
        .unwrap_err();
    assert!(matches!(e, RobotError::InvalidArmRoot { .. }), "{e}");
}

/// A described stow wins over the computed one (no SRDF), and one in self-collision is
/// refused: the first of seeded random configurations that the robot's own checker finds in
/// self-collision (under the SRDF's exemptions) is named as the stow.
#[test]
fn a_described_stow_is_used_and_checked() {
    let names: Vec<String> = (1..=7).map(|k| format!("Actuator{k}")).collect();
    let stow_table = |q: &DVector<f64>| {
        let mut t = String::from("[stow]\n");
        for (name, v) in names.iter().zip(q.iter()) {
            t += &format!("{name} = {v:?}\n");
        }
        t
    };
    let shipped = RobotModel::kinova_gen3_mobile();
    // The SRDF's stow with Actuator7 turned: no SRDF, so this stow is the neutral one.
    let mut q = shipped.neutral();
    q[6] = 0.3;
    let robot = RobotDescription::parse(&gen3_description(false, &stow_table(&q)))
        .and_then(|d| RobotModel::from_description(&d, &robots(), &|_| None))
        .unwrap();
    assert_eq!(robot.neutral(), q);
    let checker = RobotCollision::new(&shipped).unwrap();
    let (lower, upper) = shipped.arm_bounds();
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let colliding = (0..10_000)
        .map(|_| {
            DVector::from_fn(7, |i, _| {
                let (lo, hi) = (lower[i].max(-3.0), upper[i].min(3.0));
                rng.random_range(lo..=hi)
            })
        })
        .find(|q| {
            let poses = shipped
                .link_poses(&RobotConfig {
                    base: [0.0; 3],
                    arm: q.clone(),
                })
                .unwrap();
            checker.self_collision(&poses).is_some()
        })
        .expect("some arm configuration of the Gen3 folds into itself");
    let (field, message) = load_error(&gen3_description(true, &stow_table(&colliding)));
    assert!(
        field == "stow" && message.contains("collide"),
        "{field}: {message}"
    );
}

/// A description round-trips through its TOML text.
#[test]
fn a_description_round_trips() {
    let text = std::fs::read_to_string(robots().join("tiago.toml")).unwrap();
    let description = RobotDescription::parse(&text).unwrap();
    assert_eq!(description.tool.approach, Some([1.0, 0.0, 0.0]));
    assert_eq!(
        RobotDescription::parse(&description.to_toml()).unwrap(),
        description
    );
}

/// A differential-drive `[base]` loads as `BaseKind::DifferentialDrive` with its lateral
/// limits 0 and the rest as written.
#[test]
fn a_differential_drive_base_loads() {
    let dir = std::env::temp_dir().join(format!("kinscene-dd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("robot.toml");
    std::fs::write(
        &path,
        gen3_description(
            true,
            "[base]\nkind = \"differential_drive\"\nmax_velocity = [0.8, 0.0, 2.0]\n\
             max_acceleration = [0.4, 0.0, 1.5]\n",
        ),
    )
    .unwrap();
    let robot = RobotModel::from_description_file(&path).expect("the description loads");
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(robot.base().kind, BaseKind::DifferentialDrive);
    assert_eq!(robot.base().max_velocity, [0.8, 0.0, 2.0]);
    assert_eq!(robot.base().max_acceleration, [0.4, 0.0, 1.5]);
}

/// A footprint polygon sets the base's footprint radius to its farthest vertex: a 0.7 × 0.5 m
/// rectangle 0.05 m ahead of the origin has its far corners at (0.4, ±0.25), so the radius is
/// hypot(0.4, 0.25) = √0.2225 ≈ 0.4717 m (by hand), whatever the computed one was.
#[test]
fn a_footprint_polygon_gives_its_enclosing_radius() {
    let text = gen3_description(
        true,
        "[base]\nfootprint = [[-0.3, -0.25], [0.4, -0.25], [0.4, 0.25], [-0.3, 0.25]]\n",
    );
    let description = RobotDescription::parse(&text).unwrap();
    let robot = RobotModel::from_description(&description, &robots(), &|_| None).unwrap();
    let r = robot.base().footprint_radius;
    assert!((r - 0.2225f64.sqrt()).abs() < 1e-12, "{r}");
    let computed = RobotModel::from_description_file(&robots().join("gen3.toml"))
        .unwrap()
        .base()
        .footprint_radius;
    assert!((computed - r).abs() > 1e-3, "{computed} vs {r}");
}
