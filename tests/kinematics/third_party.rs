//! Robots as they ship: TIAGo and the Panda from the PyPI package `example-robot-data`
//! (installed by `setup.sh` into `.deps/venv`, pinned in `scripts/requirements.txt`), loaded
//! with their meshes and, for the Panda, its SRDF.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use kinscene::kinematics::robot::{
    PairSampling, RobotCollision, RobotConfig, RobotImportOptions, RobotModel, Srdf, StowSearch,
};

/// `share/example-robot-data` in the venv's cmeel prefix.
pub(super) fn example_robot_data() -> PathBuf {
    let lib = Path::new(env!("CARGO_MANIFEST_DIR")).join(".deps/venv/lib");
    let found = std::fs::read_dir(&lib).ok().and_then(|entries| {
        entries
            .filter_map(Result::ok)
            .map(|e| {
                e.path()
                    .join("site-packages/cmeel.prefix/share/example-robot-data")
            })
            .find(|p| p.is_dir())
    });
    found.unwrap_or_else(|| panic!("example-robot-data is not in {lib:?}: run `bash setup.sh`"))
}

fn options(tool: &str) -> RobotImportOptions {
    let mut o = RobotImportOptions {
        tool_link: tool.to_string(),
        ..RobotImportOptions::default()
    };
    o.package_paths
        .insert("example-robot-data".into(), example_robot_data());
    o
}

/// The movable joints of a URDF file, read with urdf-rs here.
fn movable_joints(urdf: &Path) -> BTreeSet<String> {
    let robot = urdf_rs::read_file(urdf).unwrap();
    robot
        .joints
        .iter()
        .filter(|j| {
            matches!(
                j.joint_type,
                urdf_rs::JointType::Revolute
                    | urdf_rs::JointType::Continuous
                    | urdf_rs::JointType::Prismatic
            )
        })
        .map(|j| j.name.clone())
        .collect()
}

/// TIAGo (mobile base with wheels, torso lift, head, 7-DoF arm, five-finger hand; 77 mesh
/// files): with the arm rooted at the torso, the arm is `arm_1_joint` … `arm_7_joint` and
/// every other movable joint of the URDF (read here with urdf-rs) is frozen; the computed stow
/// keeps the arm near the base (footprint under 0.6 m; the arm stretched out reaches over 1 m)
/// and free of self-collision under sampled exemptions, and the wheels may stand on a floor.
#[test]
fn tiago_loads_with_torso_head_wheels_and_hand_frozen() {
    let urdf = example_robot_data().join("robots/tiago_description/robots/tiago.urdf");
    let mut o = options("hand_grasping_frame");
    o.arm_root = Some("torso_lift_link".into());
    o.tool_approach = Some([1.0, 0.0, 0.0]);
    let robot = RobotModel::from_urdf_file_with(&urdf, &o).unwrap();
    let arm: Vec<String> = robot.arm_joints().iter().map(|j| j.name.clone()).collect();
    let expected: Vec<String> = (1..=7).map(|k| format!("arm_{k}_joint")).collect();
    assert_eq!(arm, expected);
    let frozen: BTreeSet<String> = robot
        .frozen_joints()
        .iter()
        .map(|f| f.name.clone())
        .collect();
    let mut others = movable_joints(&urdf);
    for a in &arm {
        others.remove(a);
    }
    assert_eq!(frozen, others);
    assert!(frozen.contains("torso_lift_joint") && frozen.contains("head_1_joint"));
    assert!(
        robot.links()[0].colliders.len() > 5,
        "the base carries its meshes"
    );
    let stowed = robot
        .with_computed_stow(&StowSearch {
            samples: 300,
            ..StowSearch::default()
        })
        .unwrap()
        .with_sampled_pairs(&PairSampling {
            samples: 300,
            ..PairSampling::default()
        })
        .unwrap();
    assert!(
        stowed.base().footprint_radius < 0.6,
        "{}",
        stowed.base().footprint_radius
    );
    let poses = stowed
        .link_poses(&RobotConfig {
            base: [0.0; 3],
            arm: stowed.neutral(),
        })
        .unwrap();
    assert_eq!(
        RobotCollision::new(&stowed).unwrap().self_collision(&poses),
        None
    );
}

/// The Panda with its SRDF: every link the SRDF names carries collision elements in the model
/// (its hand and fingers merged into link 7), and the exemptions are the robot-link pairs all
/// of whose URDF-link pairs the SRDF disables, recounted here from the SRDF's lines; link 6
/// and link 7 (with the hand and fingers) are among them, link 0 and link 7 are not.
#[test]
fn the_panda_takes_its_srdf() {
    let root = example_robot_data().join("robots/panda_description");
    let robot =
        RobotModel::from_urdf_file_with(&root.join("urdf/panda.urdf"), &options("panda_hand"))
            .unwrap();
    let text = std::fs::read_to_string(root.join("srdf/panda.srdf")).unwrap();
    let srdf = Srdf::parse(&text).unwrap();
    assert!(
        robot.srdf_unknown_links(&srdf).is_empty(),
        "{:?}",
        robot.srdf_unknown_links(&srdf)
    );
    let robot = robot.with_srdf(&srdf).unwrap();
    // The disabled pairs by a line scan.
    let scanned: BTreeSet<(String, String)> = text
        .lines()
        .filter(|l| l.trim_start().starts_with("<disable_collisions"))
        .map(|l| {
            let attr = |key: &str| {
                let k = format!("{key}=\"");
                let start = l.find(&k).unwrap() + k.len();
                l[start..start + l[start..].find('"').unwrap()].to_string()
            };
            let (a, b) = (attr("link1"), attr("link2"));
            if a < b { (a, b) } else { (b, a) }
        })
        .collect();
    let off = |a: &String, b: &String| {
        let key = if a < b {
            (a.clone(), b.clone())
        } else {
            (b.clone(), a.clone())
        };
        scanned.contains(&key)
    };
    let links = robot.links();
    let mut expected = Vec::new();
    for i in 0..links.len() {
        for j in i + 1..links.len() {
            let (x, y) = (&links[i].merged, &links[j].merged);
            if !x.is_empty() && !y.is_empty() && x.iter().all(|a| y.iter().all(|b| off(a, b))) {
                expected.push((i, j));
            }
        }
    }
    let got: Vec<(usize, usize)> = robot
        .allowed_pairs()
        .unwrap()
        .iter()
        .map(|p| (p.link1, p.link2))
        .collect();
    assert_eq!(got, expected);
    assert!(links[7].merged.contains(&"panda_hand".to_string()));
    assert!(got.contains(&(6, 7)) && !got.contains(&(0, 7)), "{got:?}");
}
