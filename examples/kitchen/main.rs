//! The kitchen: task-level planning on the project's kitchen scene.
//!
//! ```sh
//! bash setup.sh && cargo run --release --example kitchen [-- OUT_DIR]
//! ```
//!
//! Loads `examples/scenes/kitchen.urdf` (counters, an island, 4 drawers, 5 cabinet doors, a
//! dishwasher whose drawer rides on its door), then for every goal file in
//! `examples/scenes/goals/` plans the order of single-joint changes with the lattice search,
//! re-checks each plan with the independent validator, and compares with the paper's
//! *Random* and *Paper* baselines. Writes to `OUT_DIR` (default `out/kitchen`): one plan JSON
//! per goal, the scene exported back to URDF (the digital twin) and a markdown report.
//!
//! Stages 1–2 of the paper (mapping, articulation discovery) and motion refinement join this
//! example as their layers land; today it runs stage 3 at the task level on the authored model.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use kinscene::scene::urdf::{self, ExportOptions, ImportOptions};
use kinscene::task::{
    GoalSpec, NoRefinement, Outcome, PlanFile, Problem, Strategy, TaskSettings, Termination, plan,
    validate,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("out/kitchen"));
    std::fs::create_dir_all(&out)?;

    let scene = root.join("examples/scenes/kitchen.urdf");
    let model = urdf::read_file(&scene, &ImportOptions::default())?;
    println!(
        "kitchen: {} parts, {} handles, {} base shapes, nav grid {}×{} cells",
        model.parts().len(),
        model.handles().count(),
        model.base().shapes.len(),
        model.base_grid().width(),
        model.base_grid().height()
    );

    let mut goals: Vec<PathBuf> = std::fs::read_dir(root.join("examples/scenes/goals"))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    goals.sort();

    let mut report = String::from("# kinscene kitchen report\n\n");
    writeln!(
        report,
        "Scene `{}`: {} joints.\n\n| goal | search | steps | time | valid | Random | Paper |\n|---|---|---|---|---|---|---|",
        scene.display(),
        model.nq()
    )?;
    for goal in &goals {
        let name = goal
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string();
        let spec = GoalSpec::from_toml(&std::fs::read_to_string(goal)?)?;
        let problem = Problem::from_spec(&model, &spec)?;
        let settings = TaskSettings::default();
        let started = Instant::now();
        let result = plan(
            &model,
            &problem,
            &settings,
            &NoRefinement,
            &Termination::after(Duration::from_secs(30)),
        )?;
        let elapsed = started.elapsed();
        std::fs::write(
            out.join(format!("{name}.plan.json")),
            PlanFile::from_result(&result).to_json(),
        )?;
        let (verdict, steps, valid) = match &result.outcome {
            Outcome::Solved(p) => {
                let v = validate(&model, &problem, &p.steps, &settings)?;
                println!(
                    "\n{name}: solved in {elapsed:.2?}, {} steps, validator: {}",
                    p.steps.len(),
                    if v.valid { "valid" } else { "INVALID" }
                );
                for s in &p.steps {
                    println!("  {:<28} {:>7.3} -> {:>7.3}", s.joint, s.from, s.to);
                }
                ("solved", p.steps.len().to_string(), v.valid.to_string())
            }
            Outcome::Infeasible(why) => {
                println!("\n{name}: infeasible ({elapsed:.2?}): {}", why.message);
                ("infeasible", "–".into(), "–".into())
            }
            Outcome::Timeout(partial) => {
                println!("\n{name}: timeout; unmet {:?}", partial.unmet);
                ("timeout", "–".into(), "–".into())
            }
        };
        let baseline = |strategy| -> Result<&'static str, Box<dyn std::error::Error>> {
            let s = TaskSettings {
                strategy,
                ..TaskSettings::default()
            };
            let r = plan(
                &model,
                &problem,
                &s,
                &NoRefinement,
                &Termination::after(Duration::from_secs(10)),
            )?;
            Ok(match r.outcome {
                Outcome::Solved(p) if validate(&model, &problem, &p.steps, &settings)?.valid => {
                    "solved"
                }
                Outcome::Solved(_) => "solved, invalid",
                Outcome::Infeasible(_) => "failed",
                Outcome::Timeout(_) => "timeout",
            })
        };
        let random = baseline(Strategy::Random { seed: 1 })?;
        let paper = baseline(Strategy::Paper { seed: 1 })?;
        writeln!(
            report,
            "| {name} | {verdict} | {steps} | {:.1} ms | {valid} | {random} | {paper} |",
            elapsed.as_secs_f64() * 1e3
        )?;
    }

    // The twin refers to the scene's meshes by the same relative paths: copy them along.
    let meshes = root.join("examples/scenes/meshes");
    std::fs::create_dir_all(out.join("meshes"))?;
    for entry in std::fs::read_dir(&meshes)? {
        let path = entry?.path();
        if let Some(file) = path.file_name() {
            std::fs::copy(&path, out.join("meshes").join(file))?;
        }
    }
    let twin = out.join("kitchen_twin.urdf");
    urdf::write_file(
        &model,
        &twin,
        &ExportOptions {
            mesh_dir: Some(out.join("meshes")),
            ..ExportOptions::default()
        },
    )?;
    writeln!(report, "\nDigital twin: `{}`.", twin.display())?;
    std::fs::write(out.join("report.md"), &report)?;
    println!("\nwrote {}", out.display());
    Ok(())
}
