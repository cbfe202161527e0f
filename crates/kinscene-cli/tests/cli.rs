//! The kinscene command-line tool: `kinscene inspect` on the kitchen scene, and its exit
//! code and one-line error on bad input.

use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

/// The repository's root, where the example scenes and the shipped robot are.
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn kitchen_path() -> PathBuf {
    repo().join("examples/scenes/kitchen.urdf")
}

fn kinscene(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_kinscene"))
        .args(args)
        .output()
        .expect("the kinscene binary runs")
}

/// Writes `contents` to a file of its own in the test scratch directory.
fn scratch_file(name: &str, contents: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, contents).unwrap();
    path
}

/// Asserts exit code 2, an empty stdout and exactly one `kinscene: error: ` line on stderr;
/// returns that line.
fn assert_bad_input(output: &Output) -> String {
    let stderr = String::from_utf8(output.stderr.clone()).unwrap();
    assert_eq!(output.status.code(), Some(2), "stderr: {stderr}");
    assert!(output.stdout.is_empty());
    let lines: Vec<_> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "stderr: {stderr:?}");
    assert!(stderr.ends_with('\n'));
    assert!(lines[0].starts_with("kinscene: error: "), "{stderr:?}");
    lines[0].to_string()
}

fn inspect_kitchen() -> Value {
    let path = kitchen_path();
    let output = kinscene(&["inspect", "--scene", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "stderr: {stderr}");
    assert!(stderr.is_empty(), "{stderr}");
    serde_json::from_slice(&output.stdout).expect("inspect prints JSON")
}

fn vec3(v: &Value) -> [f64; 3] {
    let a = v.as_array().expect("a 3-vector");
    assert_eq!(a.len(), 3);
    [0, 1, 2].map(|k| a[k].as_f64().unwrap())
}

fn assert_close(got: [f64; 3], want: [f64; 3]) {
    for k in 0..3 {
        assert!((got[k] - want[k]).abs() < 1e-9, "{got:?} != {want:?}");
    }
}

/// The non-fixed joints of a URDF document as (name, parent link), in document order, found
/// by a plain text scan of `<joint name="..." type="...">` tags and their
/// `<parent link="..."/>` (independent of the importer).
fn movable_joints(urdf: &str) -> Vec<(String, String)> {
    urdf.split("<joint ")
        .skip(1)
        .filter_map(|tag| {
            let attr = |text: &str, key: &str| {
                let start = text.find(&format!("{key}=\""))? + key.len() + 2;
                let len = text[start..].find('"')?;
                Some(text[start..start + len].to_string())
            };
            let body = &tag[..tag.find("</joint>")?];
            let parent = attr(&body[body.find("<parent ")?..], "link")?;
            (attr(tag, "type")? != "fixed")
                .then(|| attr(tag, "name").map(|name| (name, parent)))
                .flatten()
        })
        .collect()
}

#[test]
fn inspect_prints_the_kitchen_as_json() {
    let doc = inspect_kitchen();
    assert_eq!(doc["format"], "kinscene-inspect/1");
    assert_eq!(doc["name"], "kitchen_base");
    let joints = doc["joints"].as_array().unwrap();
    assert_eq!(joints.len(), 11);
    let mut names: Vec<String> = joints
        .iter()
        .map(|j| j["name"].as_str().unwrap().to_string())
        .collect();
    let joint_parents = movable_joints(&std::fs::read_to_string(kitchen_path()).unwrap());
    let mut want: Vec<String> = joint_parents.iter().map(|(n, _)| n.clone()).collect();
    assert_eq!(want.len(), 11);
    names.sort();
    want.sort();
    assert_eq!(names, want);
    assert_eq!(doc["zero_state"].as_object().unwrap().len(), 11);
    for j in joints {
        let (_, parent) = joint_parents.iter().find(|(n, _)| *n == j["name"]).unwrap();
        assert_eq!(j["parent"], parent.as_str());
        let kind = if parent == "kitchen_base" {
            "base"
        } else {
            "part"
        };
        assert_eq!(j["parent_kind"], kind, "{}", j["name"]);
        let unit = if j["type"] == "prismatic" { "m" } else { "rad" };
        assert_eq!(j["limits"]["unit"], unit);
    }

    // Door B, from the URDF: joint origin xyz (0.623, 2.25, 0.1), rpy (0, 0, π/2), axis
    // (0, 0, 1), limits [0, π/2]. Its pivot is the origin (no ancestors) and the world axis is
    // R_z(π/2) (0, 0, 1) = (0, 0, 1).
    let b = joints
        .iter()
        .find(|j| j["name"] == "corner_door_side_hinge")
        .unwrap();
    assert_eq!(b["type"], "revolute");
    assert_eq!(b["child"], "corner_door_side");
    assert_close(vec3(&b["pivot"]), [0.623, 2.25, 0.1]);
    assert_close(vec3(&b["origin"]["xyz"]), [0.623, 2.25, 0.1]);
    assert_close(vec3(&b["origin"]["rpy"]), [0.0, 0.0, FRAC_PI_2]);
    assert_close(vec3(&b["axis"]["joint"]), [0.0, 0.0, 1.0]);
    assert_close(vec3(&b["axis"]["world"]), [0.0, 0.0, 1.0]);
    // parent_from_joint row 0 is (cos π/2, -sin π/2, 0, x) = (0, -1, 0, 0.623).
    let row0: Vec<f64> = b["origin"]["parent_from_joint"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(row0.len(), 4);
    assert!((row0[0]).abs() < 1e-12 && (row0[1] + 1.0).abs() < 1e-12);
    assert!((row0[3] - 0.623).abs() < 1e-12);
    assert_eq!(b["limits"]["lower"], 0.0);
    assert!((b["limits"]["upper"].as_f64().unwrap() - FRAC_PI_2).abs() < 1e-12);
    // The dishwasher door turns about the world x axis.
    let dw = joints
        .iter()
        .find(|j| j["name"] == "dishwasher_door_hinge")
        .unwrap();
    assert_close(vec3(&dw["axis"]["world"]), [1.0, 0.0, 0.0]);

    // B's handle, by hand: the handle link's origin is (-0.41, -0.0175, 0.64) in the door
    // frame with rpy (0, 0, -π/2). The door frame is the joint frame at angle 0, i.e.
    // translation (0.623, 2.25, 0.1) and R_z(π/2), which maps (x, y, z) to (-y, x, z):
    // (-0.41, -0.0175, 0.64) -> (0.0175, -0.41, 0.64), plus the origin gives
    // (0.6405, 1.84, 0.74). The normal is the handle frame's +x: R_z(π/2) R_z(-π/2) x = +x
    // (the door faces +x, out of the left run).
    let handles = doc["handles"].as_array().unwrap();
    assert_eq!(handles.len(), 11);
    let h = handles
        .iter()
        .find(|h| h["name"] == "corner_door_side_handle")
        .unwrap();
    assert_eq!(h["part"], "corner_door_side");
    assert_eq!(h["joint"], "corner_door_side_hinge");
    assert_close(vec3(&h["part_frame"]["position"]), [-0.41, -0.0175, 0.64]);
    assert_close(vec3(&h["part_frame"]["normal"]), [0.0, -1.0, 0.0]);
    assert_close(vec3(&h["world"]["position"]), [0.6405, 1.84, 0.74]);
    assert_close(vec3(&h["world"]["normal"]), [1.0, 0.0, 0.0]);

    let shapes = doc["base_shapes"].as_array().unwrap();
    let bowl = shapes.iter().find(|s| s["name"] == "sink_bowl").unwrap();
    assert_eq!(bowl["kind"], "mesh");
    assert_eq!(bowl["mesh"], "meshes/sink_bowl.obj");
    let floor = shapes.iter().find(|s| s["name"] == "floor").unwrap();
    assert_eq!(floor["kind"], "box");
    assert!(floor.get("mesh").is_none());

    // Navigation grid: default 5 cm cells over the base shapes' extent (x in [-0.1, 3.5],
    // y in [-1.0, 3.1]) padded by 1 m: 5.6 m × 6.1 m = 112 × 122 cells from (-1.1, -2.0).
    let grid = &doc["nav_grid"];
    assert_eq!(grid["resolution"], 0.05);
    assert_eq!(
        (grid["width"].as_u64(), grid["height"].as_u64()),
        (Some(112), Some(122))
    );
    let origin = grid["origin"].as_array().unwrap();
    assert!((origin[0].as_f64().unwrap() + 1.1).abs() < 1e-9);
    assert!((origin[1].as_f64().unwrap() + 2.0).abs() < 1e-9);
    assert!(grid["occupied_cells"].as_u64().unwrap() > 0);
}

#[test]
fn inspect_accepts_package_paths() {
    let path = kitchen_path();
    let dir = path.parent().unwrap();
    let output = kinscene(&[
        "inspect",
        "--scene",
        path.to_str().unwrap(),
        "--package",
        &format!("kitchen={}", dir.display()),
    ]);
    assert_eq!(output.status.code(), Some(0));
    let bad = kinscene(&[
        "inspect",
        "--scene",
        path.to_str().unwrap(),
        "--package",
        "no-equals-sign",
    ]);
    assert_eq!(bad.status.code(), Some(2));
}

#[test]
fn malformed_xml_is_bad_input() {
    let path = scratch_file(
        "cli_malformed.urdf",
        "<robot name=\"broken\">\n  <link name=\"base\">\n</robot>\n",
    );
    let line = assert_bad_input(&kinscene(&["inspect", "--scene", path.to_str().unwrap()]));
    assert!(line.contains("cli_malformed.urdf"), "{line}");
}

#[test]
fn missing_file_is_bad_input() {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_no_such_scene.urdf");
    let line = assert_bad_input(&kinscene(&["inspect", "--scene", path.to_str().unwrap()]));
    assert!(line.contains("cli_no_such_scene.urdf"), "{line}");
}

#[test]
fn planar_joint_is_bad_input() {
    let path = scratch_file(
        "cli_planar.urdf",
        r#"<robot name="planar">
  <link name="floor"/>
  <link name="tray"/>
  <joint name="tray_slide" type="planar">
    <parent link="floor"/>
    <child link="tray"/>
    <axis xyz="0 0 1"/>
  </joint>
</robot>
"#,
    );
    let line = assert_bad_input(&kinscene(&["inspect", "--scene", path.to_str().unwrap()]));
    assert!(
        line.contains("tray_slide"),
        "the error names the joint: {line}"
    );
}

#[test]
fn usage_errors_exit_2() {
    assert_eq!(kinscene(&["inspect"]).status.code(), Some(2));
    assert_eq!(kinscene(&["no-such-command"]).status.code(), Some(2));
    assert_eq!(kinscene(&[]).status.code(), Some(2));
    let help = kinscene(&["inspect", "--help"]);
    assert_eq!(help.status.code(), Some(0));
    let text = String::from_utf8(help.stdout).unwrap();
    assert!(text.contains("JSON schema") && text.contains("parent_from_joint"));
}

// ----- plan and validate -----

fn goal_path(name: &str) -> PathBuf {
    repo().join("examples/scenes/goals").join(name)
}

fn arg(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Runs `kinscene plan` on the kitchen with `goal` and `extra` arguments.
fn plan_kitchen(goal: &Path, extra: &[&str]) -> Output {
    let scene = kitchen_path();
    let mut args = vec!["plan", "--scene", arg(&scene), "--goal", arg(goal)];
    args.extend_from_slice(extra);
    kinscene(&args)
}

/// Runs `kinscene validate` on the kitchen.
fn validate_kitchen(goal: &Path, plan: &Path) -> Output {
    let scene = kitchen_path();
    kinscene(&[
        "validate",
        "--scene",
        arg(&scene),
        "--goal",
        arg(goal),
        "--plan",
        arg(plan),
    ])
}

/// Asserts that stderr is exactly one line starting with `kinscene: <prefix>` (a verdict, not
/// an error); returns it.
fn verdict_line(output: &Output, prefix: &str) -> String {
    let stderr = String::from_utf8(output.stderr.clone()).unwrap();
    let lines: Vec<_> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "stderr: {stderr:?}");
    assert!(stderr.ends_with('\n'));
    assert!(
        lines[0].starts_with(&format!("kinscene: {prefix}")),
        "{stderr:?}"
    );
    assert!(!lines[0].contains("error:"), "{stderr:?}");
    lines[0].to_string()
}

/// The dishwasher plan, written to `name` in the scratch directory (one name per test: tests
/// run in parallel).
fn dishwasher_plan(name: &str) -> (PathBuf, Value) {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let output = plan_kitchen(&goal_path("dishwasher.toml"), &["--out", arg(&out)]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "stderr: {stderr}");
    assert!(stderr.is_empty(), "{stderr}");
    assert!(output.stdout.is_empty(), "--out leaves stdout empty");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    (out, doc)
}

fn step_names(doc: &Value) -> Vec<String> {
    doc["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["joint"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn plan_opens_the_dishwasher_door_before_the_rack_and_the_plan_validates() {
    let (path, doc) = dishwasher_plan("cli_dishwasher_plan.json");
    assert_eq!(doc["status"], "solved");
    assert!(doc["reason"].is_null());
    let names = step_names(&doc);
    let door = names.iter().position(|n| n == "dishwasher_door_hinge");
    let rack = names.iter().position(|n| n == "dishwasher_rack_slide");
    assert!(
        matches!((door, rack), (Some(d), Some(r)) if d < r),
        "the door step comes first: {names:?}"
    );
    // The goal file's targets: door >= 1.2 rad, rack >= 0.28 m; replaying from the zero
    // state (every joint at 0) must end inside them, each step starting where the last left
    // the joint.
    let mut state = std::collections::BTreeMap::<String, f64>::new();
    for s in doc["steps"].as_array().unwrap() {
        let joint = s["joint"].as_str().unwrap().to_string();
        let from = s["from"].as_f64().unwrap();
        assert!((from - state.get(&joint).copied().unwrap_or(0.0)).abs() < 1e-12);
        state.insert(joint, s["to"].as_f64().unwrap());
        assert_eq!(s["base"].as_array().map(Vec::len), Some(3));
    }
    assert!(state["dishwasher_door_hinge"] >= 1.2);
    assert!(state["dishwasher_rack_slide"] >= 0.28);

    let output = validate_kitchen(&goal_path("dishwasher.toml"), &path);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "stderr: {stderr}");
    assert!(stderr.is_empty(), "{stderr}");
    let report: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(report["format"], "kinscene-validate/1");
    assert_eq!(report["valid"], true);
    assert!(report["first_failure"].is_null());
    assert_eq!(report["unmet"].as_array().map(Vec::len), Some(0));
    assert_eq!(report["plan_status"], "solved");
    assert_eq!(report["steps"].as_u64(), Some(names.len() as u64));
    assert!(report["checked_samples"].as_u64().unwrap() > 0);
}

#[test]
fn plan_prints_the_document_on_stdout_without_out() {
    let output = plan_kitchen(&goal_path("dishwasher.toml"), &[]);
    assert_eq!(output.status.code(), Some(0));
    let doc: Value = serde_json::from_slice(&output.stdout).expect("plan prints JSON");
    assert_eq!(doc["status"], "solved");
    assert!(doc["stats"]["expanded"].as_u64().unwrap() > 0);
}

#[test]
fn validate_rejects_the_dishwasher_plan_with_its_steps_swapped() {
    let (_, mut doc) = dishwasher_plan("cli_dishwasher_plan_to_swap.json");
    let steps = doc["steps"].as_array_mut().unwrap();
    assert_eq!(steps.len(), 2, "{steps:?}");
    steps.swap(0, 1);
    let path = scratch_file("cli_dishwasher_swapped.json", &doc.to_string());
    let output = validate_kitchen(&goal_path("dishwasher.toml"), &path);
    assert_eq!(output.status.code(), Some(3));
    let line = verdict_line(&output, "invalid plan: step 0: ");
    let report: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(report["valid"], false);
    assert_eq!(report["first_failure"]["step"], 0);
    // With the door closed the rack slides up: the top of its handle bar (z = 0.595 + value,
    // from the URDF: door hinge z 0.1, rack origin 0.47 up the door, bar top 0.025 above the
    // rack's end face) meets the underside of the tub top (z = 0.845 − 0.025 = 0.82) at
    // 0.225 m, short of the 0.28 m the step asks for.
    let reason = report["first_failure"]["reason"].as_str().unwrap();
    assert!(reason.contains("dishwasher_tub_top"), "{reason}");
    assert!(line.contains("dishwasher_tub_top"), "{line}");
    // Replay stops before the first step: both goal joints are still at 0.
    let mut unmet: Vec<&str> = report["unmet"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    unmet.sort();
    assert_eq!(unmet, ["dishwasher_door_hinge", "dishwasher_rack_slide"]);
}

#[test]
fn plan_reports_the_corner_doors_as_infeasible_naming_both() {
    let output = plan_kitchen(&goal_path("corner.toml"), &[]);
    assert_eq!(output.status.code(), Some(3));
    let line = verdict_line(&output, "infeasible: ");
    assert!(
        line.contains("corner_door_back_hinge") && line.contains("corner_door_side_hinge"),
        "{line}"
    );
    let doc: Value = serde_json::from_slice(&output.stdout).expect("the document is written");
    assert_eq!(doc["status"], "infeasible");
    assert_eq!(doc["steps"].as_array().map(Vec::len), Some(0));
    assert!(doc["reason"].as_str().is_some_and(|r| !r.is_empty()));
}

/// The dishwasher door fully open with the rack out (goals/dishwasher_rack_out.toml): the
/// disc robot meets each target alone but not both (the island leaves the lowered door's front
/// no free cell), and the Gen3 cannot hold the lowered door's handle from any free cell; both
/// verdicts come from the task level, name the joints, and the Gen3's gives the arm span.
#[test]
fn plan_reports_the_open_dishwasher_with_its_rack_out_as_infeasible_with_its_reason() {
    let goal = goal_path("dishwasher_rack_out.toml");
    let output = plan_kitchen(&goal, &[]);
    assert_eq!(output.status.code(), Some(3));
    let line = verdict_line(&output, "infeasible: ");
    assert!(
        line.contains("dishwasher_door_hinge") && line.contains("dishwasher_rack_slide"),
        "{line}"
    );
    let output = plan_kitchen(&goal, &["--robot", "gen3", "--budget", "10s"]);
    assert_eq!(output.status.code(), Some(3));
    let line = verdict_line(&output, "infeasible: ");
    assert!(line.contains("dishwasher_door_hinge"), "{line}");
    assert!(line.contains("spans at most"), "{line}");
}

#[test]
fn validate_checks_the_steps_of_an_infeasible_plan_anyway() {
    // An infeasible document has no steps: replaying nothing leaves the start state, which
    // misses both dishwasher targets.
    let doc = r#"{"status": "infeasible", "steps": [], "reason": "none"}"#;
    let path = scratch_file("cli_empty_plan.json", doc);
    let output = validate_kitchen(&goal_path("dishwasher.toml"), &path);
    assert_eq!(output.status.code(), Some(3));
    let line = verdict_line(&output, "invalid plan: ");
    assert!(line.contains("unmet"), "{line}");
    let report: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(report["plan_status"], "infeasible");
    assert!(report["first_failure"].is_null());
    assert_eq!(report["unmet"].as_array().map(Vec::len), Some(2));
    assert_eq!(report["checked_samples"], 0);
}

#[test]
fn plan_with_a_zero_budget_times_out() {
    let output = plan_kitchen(&goal_path("dishwasher.toml"), &["--budget", "0s"]);
    assert_eq!(output.status.code(), Some(4));
    let line = verdict_line(&output, "timeout after 0s: ");
    assert!(
        line.contains("dishwasher"),
        "names the unmet joints: {line}"
    );
    let doc: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(doc["status"], "timeout");
}

#[test]
fn plan_runs_the_baselines_with_consistent_exit_codes() {
    for strategy in ["random", "paper"] {
        let output = plan_kitchen(
            &goal_path("dishwasher.toml"),
            &["--strategy", strategy, "--seed", "7"],
        );
        let doc: Value = serde_json::from_slice(&output.stdout).unwrap();
        let want = match doc["status"].as_str().unwrap() {
            "solved" => 0,
            "infeasible" => 3,
            "timeout" => 4,
            other => panic!("status {other}"),
        };
        assert_eq!(output.status.code(), Some(want), "{strategy}");
    }
    // --seed has no meaning for the search without --robot.
    let output = plan_kitchen(&goal_path("dishwasher.toml"), &["--seed", "7"]);
    assert!(assert_bad_input(&output).contains("--seed"));
}

#[test]
fn bad_goals_are_bad_input() {
    let malformed = scratch_file(
        "cli_malformed_goal.toml",
        "[goal\ndishwasher_door_hinge = 1\n",
    );
    let line = assert_bad_input(&plan_kitchen(&malformed, &[]));
    assert!(line.contains("cli_malformed_goal.toml"), "{line}");

    let unknown = scratch_file(
        "cli_unknown_joint.toml",
        "[goal]\nfridge_door_hinge = 1.0\n",
    );
    let line = assert_bad_input(&plan_kitchen(&unknown, &[]));
    assert!(line.contains("fridge_door_hinge"), "{line}");

    // The sink door's limits are [0, 1.92] rad.
    let outside = scratch_file(
        "cli_outside_goal.toml",
        "[goal]\nsink_door_hinge = { min = 2.5 }\n",
    );
    let line = assert_bad_input(&plan_kitchen(&outside, &[]));
    assert!(line.contains("sink_door_hinge"), "{line}");

    let missing = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_no_such_goal.toml");
    let line = assert_bad_input(&plan_kitchen(&missing, &[]));
    assert!(line.contains("cli_no_such_goal.toml"), "{line}");

    // The same goal as JSON (chosen by the extension) parses.
    let json = scratch_file(
        "cli_goal.json",
        r#"{"goal": {"island_drawer_left_slide": {"min": 0.2}}, "robot": {"base": [1.0, 0.0, 1.5708]}}"#,
    );
    assert_eq!(plan_kitchen(&json, &[]).status.code(), Some(0));
    let missing_scene = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_no_such_scene.urdf");
    let goal = goal_path("dishwasher.toml");
    let line = assert_bad_input(&kinscene(&[
        "plan",
        "--scene",
        arg(&missing_scene),
        "--goal",
        arg(&goal),
    ]));
    assert!(line.contains("cli_no_such_scene.urdf"), "{line}");
}

#[test]
fn bad_budgets_are_bad_input() {
    for budget in ["2", "abc", "-1s", "1.5.2s", "10 sec"] {
        let output = plan_kitchen(&goal_path("dishwasher.toml"), &["--budget", budget]);
        let line = assert_bad_input(&output);
        assert!(line.contains("--budget"), "{budget}: {line}");
    }
}

#[test]
fn bad_plans_are_bad_input() {
    let goal = goal_path("dishwasher.toml");
    let malformed = scratch_file(
        "cli_malformed_plan.json",
        r#"{"status": "solved", "steps": ["#,
    );
    let line = assert_bad_input(&validate_kitchen(&goal, &malformed));
    assert!(line.contains("cli_malformed_plan.json"), "{line}");

    let step = |joint: &str, to: f64| {
        format!(
            r#"{{"status": "solved", "steps": [{{"joint": "{joint}", "from": 0.0, "to": {to}}}]}}"#
        )
    };
    let unknown = scratch_file("cli_unknown_plan.json", &step("fridge_door_hinge", 1.0));
    let line = assert_bad_input(&validate_kitchen(&goal, &unknown));
    assert!(line.contains("fridge_door_hinge"), "{line}");

    // The dishwasher door's limits are [0, π/2] rad.
    let outside = scratch_file("cli_outside_plan.json", &step("dishwasher_door_hinge", 2.0));
    let line = assert_bad_input(&validate_kitchen(&goal, &outside));
    assert!(line.contains("dishwasher_door_hinge"), "{line}");

    let missing = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_no_such_plan.json");
    let line = assert_bad_input(&validate_kitchen(&goal, &missing));
    assert!(line.contains("cli_no_such_plan.json"), "{line}");
}

#[test]
fn plan_and_validate_help_print_the_schemas() {
    let help = kinscene(&["plan", "--help"]);
    assert_eq!(help.status.code(), Some(0));
    let text = String::from_utf8(help.stdout).unwrap();
    assert!(
        text.contains("[goal]") && text.contains("\"conflicts\""),
        "{text}"
    );
    let help = kinscene(&["validate", "--help"]);
    assert_eq!(help.status.code(), Some(0));
    let text = String::from_utf8(help.stdout).unwrap();
    assert!(text.contains("first_failure") && text.contains("checked_samples"));
    let help = kinscene(&["--help"]);
    let text = String::from_utf8(help.stdout).unwrap();
    assert!(text.contains("plan") && text.contains("validate") && text.contains("4 "));
}

/// A counter whose front face is the plane x = 0 and a drawer front sliding out along -x, its
/// handle at 0.75 m (the README's planner example).
fn counter_path() -> PathBuf {
    repo().join("examples/scenes/counter.urdf")
}

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
#[test]
fn plan_with_a_robot_writes_base_and_arm_paths_with_timing() {
    let scene = counter_path();
    let goal = scratch_file(
        "counter_goal.toml",
        "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-0.9, 0.0, 0.0]\n",
    );
    let out = scratch_file("counter_motion.json", "");
    let output = kinscene(&[
        "plan",
        "--scene",
        arg(&scene),
        "--goal",
        arg(&goal),
        "--robot",
        "gen3",
        "--budget",
        "60s",
        "--out",
        arg(&out),
    ]);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(doc["status"], "solved");
    assert_eq!(doc["robot"], "kinova_gen3_mobile");
    let motion = doc["motion"].as_array().unwrap();
    assert_eq!(motion.len(), doc["steps"].as_array().unwrap().len());
    let m = &motion[0];
    assert_eq!(m["joint"], "drawer_slide");
    // The base path starts at the goal file's start pose; the arm paths are 7-D (the Gen3).
    assert_eq!(m["base_path"]["positions"][0][0].as_f64(), Some(-0.9));
    assert_eq!(m["approach"]["positions"][0].as_array().unwrap().len(), 7);
    let times = m["manipulation"]["times"].as_array().unwrap();
    assert_eq!(
        times.len(),
        m["manipulation"]["positions"].as_array().unwrap().len()
    );
    assert!(m["timing"]["manipulation"].as_f64().unwrap() > 0.0);
    assert!(doc["duration"].as_f64().unwrap() > 0.0);
}

/// `--base differential`: the Gen3 starts 0.6 m to the side of the drawer, facing the
/// counter; every piece of every base path in the document is a turn in place or a drive
/// along the heading (checked here from the positions: the displacement across the heading
/// below 1e-9 m, and no turn while driving). A base kind clap does not know, or `--base`
/// without `--robot`, is a usage error.
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
#[test]
fn plan_with_a_differential_base_never_moves_sideways() {
    let scene = counter_path();
    let goal = scratch_file(
        "counter_goal_differential.toml",
        "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-1.1, 0.6, 0.0]\n",
    );
    let out = scratch_file("counter_motion_differential.json", "");
    let mut args = vec!["plan", "--scene", arg(&scene), "--goal", arg(&goal)];
    args.extend([
        "--robot",
        "gen3",
        "--base",
        "differential",
        "--budget",
        "60s",
    ]);
    args.extend(["--out", arg(&out)]);
    let output = kinscene(&args);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let pieces = turns_and_straight_drives(&doc);
    assert!(
        pieces >= 2,
        "the base had to turn and drive: {pieces} pieces"
    );

    for extra in [
        &["--robot", "gen3", "--base", "sideways"][..],
        &["--base", "differential"][..],
    ] {
        let output = plan_kitchen(&goal_path("dishwasher.toml"), extra);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains("--base"), "{extra:?}: {stderr}");
    }
}

/// The pieces of the document's base paths, each checked to be a turn in place or a drive
/// along the heading (from the positions: the displacement across the heading below 1e-9 m,
/// and no turn while driving).
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
fn turns_and_straight_drives(doc: &Value) -> usize {
    let mut pieces = 0;
    for m in doc["motion"].as_array().unwrap() {
        let positions: Vec<[f64; 3]> = m["base_path"]["positions"]
            .as_array()
            .unwrap()
            .iter()
            .map(vec3)
            .collect();
        for w in positions.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let lateral = -a[2].sin() * dx + a[2].cos() * dy;
            assert!(lateral.abs() < 1e-9, "{a:?} -> {b:?}");
            if dx.hypot(dy) > 1e-9 {
                assert!(
                    (b[2] - a[2]).abs() < 1e-9,
                    "turns while driving: {a:?} -> {b:?}"
                );
            }
            pieces += 1;
        }
    }
    pieces
}

#[test]
fn max_segments_is_a_positive_count_for_a_robot() {
    // 0 segments cannot cover a step; without --robot there is no motion to segment.
    let goal = goal_path("dishwasher.toml");
    for extra in [
        &["--robot", "gen3", "--max-segments", "0"][..],
        &["--robot", "gen3", "--max-segments", "two"][..],
        &["--max-segments", "2"][..],
    ] {
        // Rejected by the argument parser (clap's own message, exit code 2), before any file
        // is read.
        let output = plan_kitchen(&goal, extra);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(output.stdout.is_empty());
        assert!(stderr.contains("--max-segments"), "{extra:?}: {stderr}");
    }
}

#[test]
fn whole_body_moves_the_base_during_the_wide_door_and_needs_a_robot() {
    // examples/scenes/goals/wide_door.toml: the 0.6 m cabinet door that no single Gen3 base
    // pose covers. By default (whole-body manipulation) the document's one entry moves the base
    // during the manipulation (a base pose per manipulation waypoint, the same times) and
    // records the segments' time it beat; with --fixed-base, the entries keep their base still.
    let scene = repo().join("examples/scenes/appliances.urdf");
    let goal = goal_path("wide_door.toml");
    let run = |extra: &[&str]| -> Value {
        let mut args = vec!["plan", "--scene", arg(&scene), "--goal", arg(&goal)];
        args.extend_from_slice(&["--robot", "gen3"]);
        args.extend_from_slice(extra);
        let output = kinscene(&args);
        assert_eq!(output.status.code(), Some(0), "{output:?}");
        serde_json::from_slice(&output.stdout).expect("plan prints JSON")
    };
    let fixed = run(&["--fixed-base"]);
    for m in fixed["motion"].as_array().unwrap() {
        assert!(m.get("manipulation_base").is_none(), "{m}");
        assert_ne!(m["mode"], "whole_body");
    }
    let doc = run(&[]);
    let motion = doc["motion"].as_array().unwrap();
    if let [m] = motion.as_slice() {
        assert_eq!(m["mode"], "whole_body");
        let bases = &m["manipulation_base"];
        assert_eq!(bases["times"], m["manipulation"]["times"]);
        let positions = bases["positions"].as_array().unwrap();
        assert!(positions.iter().any(|p| p != &positions[0]), "{bases}");
        let time = |k: &str| m["compared"][k].as_f64().expect("both times");
        assert!(time("whole_body") <= time("segments"), "{}", m["compared"]);
    } else {
        // The segments executed faster: every entry says so.
        assert!(
            motion
                .iter()
                .all(|m| m["mode"] == "segment" && m["compared"].is_object())
        );
    }
    for flags in [&["--whole-body"][..], &["--fixed-base"]] {
        let output = plan_kitchen(&goal, flags);
        assert_eq!(output.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&output.stderr).contains("--robot"));
    }
    // The two modes contradict each other: rejected by the argument parser.
    let output = plan_kitchen(&goal, &["--robot", "gen3", "--whole-body", "--fixed-base"]);
    assert_eq!(output.status.code(), Some(2), "{output:?}");
}

#[test]
fn turned_bar_grasps_open_the_corner_doors_back_first_and_the_plan_validates() {
    // examples/scenes/goals/corner_order.toml: the back corner door to 1.2 rad and the side
    // door to 0.6 rad. Past about 0.8 rad each corner handle faces the neighbouring run, so
    // the Gen3 needs a grasp turned about the bar (`--bar-turn`, default 1.2) and the base
    // moving along (the default); the side door's sweep meets the back door's, so the back
    // door goes first (the goal file's header has the numbers). The command is the goal
    // file's own, with the defaults a new user gets.
    // The plan is checked step by step by `kinscene validate` (the task level's own validator,
    // which replays the sweeps in exact geometry); the grasp contact rule of these plans is
    // re-checked in the library's tests (tests/planner/corner.rs).
    let goal = goal_path("corner_order.toml");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("corner_order.json");
    let output = plan_kitchen(
        &goal,
        &["--robot", "gen3", "--seed", "1", "--out", arg(&out)],
    );
    assert_eq!(output.status.code(), Some(0), "{output:?}");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let steps = step_names(&doc);
    assert_eq!(
        steps.first().map(String::as_str),
        Some("corner_door_back_hinge"),
        "{steps:?}"
    );
    assert!(
        steps.iter().any(|s| s == "corner_door_side_hinge"),
        "{steps:?}"
    );
    let validated = validate_kitchen(&goal, &out);
    assert_eq!(validated.status.code(), Some(0), "{validated:?}");
    for bad in ["2", "-0.1", "NaN", "wide"] {
        // Outside [0, pi/2]: rejected by the argument parser before any file is read.
        let flag = format!("--bar-turn={bad}");
        let output = plan_kitchen(&goal, &["--robot", "gen3", &flag]);
        assert_eq!(output.status.code(), Some(2), "{bad}: {output:?}");
        assert!(String::from_utf8_lossy(&output.stderr).contains("--bar-turn"));
    }
}

#[test]
fn plan_with_a_bad_robot_file_is_bad_input() {
    let scene = counter_path();
    let goal = scratch_file(
        "counter_goal2.toml",
        "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-0.9, 0.0, 0.0]\n",
    );
    let robot = scratch_file(
        "not_a_robot.urdf",
        "<robot name=\"x\"><link name=\"a\"/></robot>",
    );
    let output = kinscene(&[
        "plan",
        "--scene",
        arg(&scene),
        "--goal",
        arg(&goal),
        "--robot",
        arg(&robot),
    ]);
    assert_bad_input(&output);
}

// ----- a start state in collision -----

/// A counter box x ∈ [0, 0.6], y ∈ [0, 1], z ∈ [0, 0.9] on the floor, a drawer that slides
/// along +x out of it and is modelled 0.1 m too deep (its box x ∈ [0.5, 0.9] at value 0
/// overlaps the counter by 0.1 m), and a door hinged at x = -1 that touches nothing. Hand
/// geometry: only the drawer/counter pair overlaps at the zero state.
fn drawer_in_counter_scene() -> PathBuf {
    scratch_file(
        "cli_drawer_in_counter.urdf",
        r#"<robot name="room">
  <link name="room">
    <collision name="counter">
      <origin xyz="0.3 0.5 0.45"/>
      <geometry><box size="0.6 1.0 0.9"/></geometry>
    </collision>
  </link>
  <link name="drawer">
    <collision><origin xyz="0.7 0.5 0.6"/><geometry><box size="0.4 0.4 0.15"/></geometry></collision>
  </link>
  <link name="drawer_handle"/>
  <joint name="drawer_slide" type="prismatic">
    <parent link="room"/><child link="drawer"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.4" effort="1" velocity="1"/>
  </joint>
  <joint name="drawer_handle_joint" type="fixed">
    <parent link="drawer"/><child link="drawer_handle"/><origin xyz="0.95 0.5 0.6"/>
  </joint>
  <link name="door">
    <collision><origin xyz="-1 0.25 0.4"/><geometry><box size="0.02 0.5 0.8"/></geometry></collision>
  </link>
  <link name="door_handle"/>
  <joint name="door_hinge" type="revolute">
    <parent link="room"/><child link="door"/><origin xyz="0 0 0"/>
    <axis xyz="0 0 1"/><limit lower="0" upper="1.5" effort="1" velocity="1"/>
  </joint>
  <joint name="door_handle_joint" type="fixed">
    <parent link="door"/><child link="door_handle"/><origin xyz="-1.03 0.45 0.4"/>
  </joint>
</robot>
"#,
    )
}

#[test]
fn inspect_flags_a_start_state_in_collision() {
    let scene = drawer_in_counter_scene();
    let output = kinscene(&["inspect", "--scene", arg(&scene)]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "stderr: {stderr}");
    assert!(
        stderr.contains("warning") && stderr.contains("drawer") && stderr.contains("counter"),
        "{stderr}"
    );
    let doc: Value = serde_json::from_slice(&output.stdout).unwrap();
    let pairs = doc["zero_state_collisions"].as_array().unwrap();
    assert_eq!(pairs.len(), 1, "{pairs:?}");
    assert_eq!(pairs[0]["a"]["part"], "drawer");
    assert_eq!(pairs[0]["b"]["base"], "counter");
    assert_eq!(pairs[0]["distance"], 0.0);
    // The kitchen's zero state is free (inspect_kitchen also asserts an empty stderr).
    assert!(
        inspect_kitchen()["zero_state_collisions"]
            .as_array()
            .unwrap()
            .is_empty()
    );
}

#[test]
fn plan_refuses_a_start_state_in_collision_at_once() {
    let scene = drawer_in_counter_scene();
    let goal = scratch_file(
        "cli_drawer_in_counter.toml",
        "[goal]\ndoor_hinge = { min = 1.2 }\n[robot]\nbase = [-1.5, 1.5, 0.0]\n",
    );
    let output = kinscene(&[
        "plan",
        "--scene",
        arg(&scene),
        "--goal",
        arg(&goal),
        "--budget",
        "60s",
    ]);
    let line = assert_bad_input(&output);
    assert!(
        line.contains("start state is in collision")
            && line.contains("\"drawer\"")
            && line.contains("\"counter\"")
            && line.contains("touching or overlapping")
            && line.contains("leave a few millimetres"),
        "{line}"
    );
}

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
#[test]
fn breakfast_with_the_gen3_is_infeasible_with_the_reach_in_numbers() {
    // The tall wall cabinet's handle (z 1.463 m, over the counter) is beyond the Gen3's arm
    // reach from every free base cell (tests/planner/reach.rs checks the bound against
    // Pinocchio's FK): exit 3 from the task level, naming the joint and both distances, with
    // no motion planned. The same goal without a robot is solved (the disc model has no arm).
    let output = plan_kitchen(
        &goal_path("breakfast.toml"),
        &["--robot", "gen3", "--budget", "60s"],
    );
    assert_eq!(output.status.code(), Some(3));
    let line = verdict_line(&output, "infeasible");
    assert!(
        line.contains("wall_door_tall_hinge") && line.contains("spans at most 0.735 m"),
        "{line}"
    );
}

/// `kinscene plan` on the counter scene with the drawer goal (scratch files named by `tag`),
/// `--robot robot` and then `args`.
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
fn plan_counter_with(tag: &str, robot: &str, args: &[&str]) -> Output {
    let scene = counter_path();
    let goal = scratch_file(
        &format!("counter_goal_{tag}.toml"),
        "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-0.9, 0.0, 0.0]\n",
    );
    let mut all = vec![
        "plan",
        "--scene",
        arg(&scene),
        "--goal",
        arg(&goal),
        "--robot",
        robot,
    ];
    all.extend_from_slice(args);
    kinscene(&all)
}

/// The shipped Gen3's URDF file.
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
fn gen3_urdf() -> PathBuf {
    repo().join("robots/kinova_gen3_mobile.urdf")
}

#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
#[test]
fn the_tool_link_of_a_robot_urdf_is_named_on_the_command_line() {
    let urdf = gen3_urdf();
    let run = |robot: &str, link: &str| {
        plan_counter_with("tool", robot, &["--tool-link", link, "--budget", "1s"])
    };
    // A link the URDF does not have: bad input naming it.
    let line = assert_bad_input(&run(arg(&urdf), "no_such_link"));
    assert!(line.contains("no_such_link"), "{line}");
    // The shipped robot has its tool fixed.
    let line = assert_bad_input(&run("gen3", "end_effector_link"));
    assert!(line.contains("--tool-link"), "{line}");
    // Without a robot the flag means nothing (clap's usage error).
    let scene = counter_path();
    let output = kinscene(&[
        "plan",
        "--scene",
        arg(&scene),
        "--goal",
        "g.toml",
        "--tool-link",
        "x",
    ]);
    assert_eq!(output.status.code(), Some(2));
    // The flange instead of the TCP loads (the verdict depends on the planner, not the flag).
    let output = run(arg(&urdf), "end_effector_link");
    assert_ne!(
        output.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// `--srdf`: the shipped Gen3 given as its URDF and SRDF files plans the counter drawer as
/// `--robot gen3` does; an SRDF with an element lacking an attribute is bad input naming it,
/// and the flag means nothing with the shipped robot.
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
#[test]
fn plan_with_a_robot_srdf() {
    let urdf = gen3_urdf();
    let run = |robot: &str, srdf: &str| {
        plan_counter_with(
            "srdf",
            robot,
            &["--srdf", srdf, "--budget", "60s", "--seed", "1"],
        )
    };
    let bad = scratch_file(
        "bad.srdf",
        "<robot name=\"r\"><disable_collisions link1=\"a\"/></robot>",
    );
    let line = assert_bad_input(&run(arg(&urdf), arg(&bad)));
    assert!(
        line.contains("disable_collisions") && line.contains("link2"),
        "{line}"
    );
    let srdf = repo().join("robots/kinova_gen3_mobile.srdf");
    let line = assert_bad_input(&run("gen3", arg(&srdf)));
    assert!(line.contains("--srdf"), "{line}");
    let output = run(arg(&urdf), arg(&srdf));
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let doc: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(doc["status"], "solved");
}

/// `--arm-root`, `--frozen` and `--contact-link` name what they get wrong (exit 2): a joint
/// that is an arm joint of the Gen3, a link that is not on the arm's path, a contact link that
/// does not move with the tool, a value that is not a number.
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
#[test]
fn plan_with_frozen_joints_and_an_arm_root_checks_them() {
    let urdf = gen3_urdf();
    let run = |flag: &str, value: &str| {
        plan_counter_with("frozen", arg(&urdf), &[flag, value, "--budget", "1s"])
    };
    let line = assert_bad_input(&run("--frozen", "Actuator1=0"));
    assert!(
        line.contains("Actuator1") && line.contains("arm joint"),
        "{line}"
    );
    let line = assert_bad_input(&run("--arm-root", "no_such_link"));
    assert!(line.contains("no_such_link"), "{line}");
    // A contact link that does not move with the tool.
    let line = assert_bad_input(&run("--contact-link", "Shoulder_Link"));
    assert!(line.contains("Shoulder_Link"), "{line}");
    // clap's usage error for a value that is not a number.
    assert_eq!(run("--frozen", "Actuator1=fast").status.code(), Some(2));
}

/// `--robot robots/gen3.toml`: the shipped Gen3's description file plans the counter drawer as
/// `--robot gen3` does (solved, the same robot name in the document).
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
#[test]
fn plan_with_a_robot_description() {
    let toml = repo().join("robots/gen3.toml");
    let output = plan_counter_with("toml", arg(&toml), &["--budget", "60s", "--seed", "1"]);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let doc: Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(doc["status"], "solved");
    assert_eq!(doc["robot"], "kinova_gen3_mobile");
}

/// A bad robot description is bad input naming the element at fault: an unknown key (and its
/// table), an unknown base kind, a stow joint that is not an arm joint, a URDF flag given with
/// a description, a description that is not TOML, and TIAGo's description without
/// `EXAMPLE_ROBOT_DATA`; with the variable set, TIAGo loads (the verdict within a 1 s budget
/// is the planner's, not bad input).
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
#[test]
fn plan_with_a_bad_robot_description_names_the_element() {
    let urdf = gen3_urdf();
    let head = format!(
        "urdf = {:?}\n[tool]\nlink = \"tool_frame\"\n",
        urdf.display().to_string()
    );
    let run = |name: &str, extra: &str, args: &[&str]| {
        let file = scratch_file(name, &(head.clone() + extra));
        let mut all = vec!["--budget", "1s"];
        all.extend_from_slice(args);
        plan_counter_with("description", arg(&file), &all)
    };
    let line = assert_bad_input(&run("unknown_key.toml", "[base]\nspeed = 1.0\n", &[]));
    assert!(line.contains("speed") && line.contains("[base]"), "{line}");
    let line = assert_bad_input(&run("kind.toml", "[base]\nkind = \"legged\"\n", &[]));
    assert!(
        line.contains("base.kind") && line.contains("legged"),
        "{line}"
    );
    let line = assert_bad_input(&run("stow.toml", "[stow]\nhead = 0.0\n", &[]));
    assert!(line.contains("stow.head"), "{line}");
    let line = assert_bad_input(&run("flag.toml", "", &["--tool-link", "x"]));
    assert!(
        line.contains("--tool-link") && line.contains("description"),
        "{line}"
    );
    let line = assert_bad_input(&run("syntax.toml", "[tool\n", &[]));
    assert!(line.contains("robot description"), "{line}");
}

/// `--robot robots/tiago.toml`: TIAGo from example-robot-data, found through the environment
/// (without it, bad input naming the variable), plans the counter drawer end to end with the
/// differential drive its description gives it.
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
#[test]
fn plan_with_tiago_s_description_end_to_end() {
    let tiago = repo().join("robots/tiago.toml");
    let scene = counter_path();
    let goal = scratch_file(
        "counter_goal_tiago.toml",
        "[goal]\ndrawer_slide = { min = 0.25 }\n[robot]\nbase = [-0.9, 0.0, 0.0]\n",
    );
    let out = scratch_file("counter_motion_tiago.json", "");
    let tiago_plan = |data: Option<&Path>| {
        let mut command = Command::new(env!("CARGO_BIN_EXE_kinscene"));
        command.args([
            "plan",
            "--scene",
            arg(&scene),
            "--goal",
            arg(&goal),
            "--robot",
            arg(&tiago),
            "--budget",
            "120s",
            "--out",
            arg(&out),
        ]);
        match data {
            Some(path) => command.env("EXAMPLE_ROBOT_DATA", path),
            None => command.env_remove("EXAMPLE_ROBOT_DATA"),
        };
        command.output().unwrap()
    };
    let line = assert_bad_input(&tiago_plan(None));
    assert!(
        line.contains("EXAMPLE_ROBOT_DATA") && line.contains("packages.example-robot-data"),
        "{line}"
    );
    // End to end: TIAGo's description makes its base a differential drive.
    let output = tiago_plan(Some(&example_robot_data()));
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(doc["robot"], "tiago");
    assert_eq!(doc["steps"][0]["joint"], "drawer_slide");
    assert!(turns_and_straight_drives(&doc) >= 1);
}

/// `share/example-robot-data` in the venv's cmeel prefix (installed by `setup.sh`).
#[cfg(all(feature = "ompl", feature = "pinocchio", feature = "casadi"))]
fn example_robot_data() -> PathBuf {
    let lib = repo().join(".deps/venv/lib");
    std::fs::read_dir(&lib)
        .ok()
        .and_then(|entries| {
            entries
                .filter_map(Result::ok)
                .map(|e| {
                    e.path()
                        .join("site-packages/cmeel.prefix/share/example-robot-data")
                })
                .find(|p| p.is_dir())
        })
        .unwrap_or_else(|| panic!("example-robot-data is not in {lib:?}: run `bash setup.sh`"))
}
