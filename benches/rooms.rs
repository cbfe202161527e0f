//! The task planner on realistic generated rooms (tests/task/rooms.rs): the lattice search
//! against the paper's sampler, same instances, same process, same budget. No criterion: one
//! run per planner and instance, wall clock.
//!
//! # Instances
//! Families galley, L-shaped and U-shaped kitchens, office corridor. The grid of cells is
//! parts ∈ {50, 100, 200, 300} × targets ∈ {5, 10, 20, 40}, without cells with more than one
//! target per 5 parts (13 cells per family); `rooms::RoomParams::new(family, parts, targets,
//! seed)` with seeds 0, 1, …, plus the infeasible-by-construction variant of seed 0 (same
//! scene, `k − 2` spread targets and a conflicting pair).
//!
//! The default run takes the cells [`DEFAULT_CELLS`] with [`SEEDS`] seeds (about 15 minutes):
//! the search is anytime, and after its first plan its second pass usually runs until the
//! budget ends (it has not proven the incumbent minimal), so every search run with 10 or more
//! targets costs the whole budget. `KINSCENE_BENCH_FULL=1` runs the whole grid with
//! [`FULL_SEEDS`] seeds (well over an hour).
//!
//! # Planners
//! - **search**: [`Strategy::Search`], default [`TaskSettings`]; recorded: `stats.first_plan`
//!   (the time to its first plan) and the final outcome (an anytime run stopped by the budget
//!   returns its incumbent as `Solved`; the table gives the largest proven suboptimality
//!   factor);
//! - **paper**: [`Strategy::Paper`] with `seed` = the instance's seed and no sample limit
//!   (`max_samples` = `usize::MAX`, so only the budget stops it; `KINSCENE_BENCH_PAPER_SAMPLES`
//!   sets a limit); recorded: its wall time to the plan.
//!
//! Both under `Termination::after(budget)`, budget [`BUDGET`] (`KINSCENE_BENCH_BUDGET=<s>`);
//! the sampler on an infeasible variant gets at most [`INFEASIBLE_PAPER_BUDGET`] (without a
//! sample limit it can only end at the budget or, for few targets, after every order).
//! Every returned plan is replayed with [`validate`] (untimed); a plan that fails it counts
//! as a failure and is printed loudly. Untimed too, [`rooms::witness`] looks for a plan
//! greedily with the search's own feasibility predicate: a witness proves the (feasible
//! variant of the) instance feasible in the search's lattice, so a search `Infeasible` there
//! is a bug (printed loudly, as is an infeasible variant the search does not refute).
//!
//! # Output
//! One markdown table per family: per cell, the search's first-plan time median / max over
//! the seeds (runs without a plan count as ∞ and show as `>budget`), its final outcomes
//! (`S/I/T` counts) and largest proven factor, the sampler's time to a valid plan median /
//! max and its solved count, the ratio of the medians search / sampler (below 1: the search
//! is faster), the greedy witnesses found, and the infeasible variant's outcome and wall time
//! for both planners (`I` = proven infeasible, `T` = budget, `S!` = a plan, which cannot be
//! valid: validation rejects it and it is printed loudly).
//!
//! # Environment
//! `KINSCENE_BENCH_QUICK=1`: cells [`QUICK_CELLS`], [`QUICK_SEEDS`] seeds, budget
//! [`QUICK_BUDGET`] (about 2 minutes); `KINSCENE_BENCH_FULL=1`: the whole grid;
//! `KINSCENE_BENCH_FAMILIES=galley,l,u,corridor`; `KINSCENE_BENCH_CELLS=100x20,300x40`
//! (parts x targets, any cell); `KINSCENE_BENCH_SEEDS=<n>`; `KINSCENE_BENCH_BUDGET=<seconds>`;
//! `KINSCENE_BENCH_PLANNERS=search,paper`; `KINSCENE_BENCH_REDUCTION=0` runs the search
//! without its partial-order reduction ([`TaskSettings::reduction`]), `KINSCENE_BENCH_DIVE=0`
//! without its greedy dive (so that its first plan comes from the passes); `KINSCENE_BENCH_INFEASIBLE=0` skips the infeasible
//! variants; `KINSCENE_BENCH_WITNESS=0` skips the witnesses; `KINSCENE_BENCH_VERBOSE=1` prints
//! one line per run on stderr (progress lines are always there).
//!
//! `cargo bench --no-default-features --bench rooms` (the task layer is pure Rust).

#[path = "../tests/task/generators.rs"]
mod generators;
#[path = "../tests/task/rooms.rs"]
mod rooms;

use std::time::{Duration, Instant};

use kinscene::task::{
    Interaction, NoRefinement, Outcome, Strategy, TaskSettings, Termination, plan, validate,
};
use rooms::{Family, Room, RoomParams};

/// Scene sizes.
const PARTS: [usize; 4] = [50, 100, 200, 300];
/// Goal sizes.
const TARGETS: [usize; 4] = [5, 10, 20, 40];
/// At most one target per this many parts.
const PARTS_PER_TARGET: usize = 5;
/// Cells of the default run.
const DEFAULT_CELLS: [(usize, usize); 4] = [(50, 5), (100, 20), (200, 20), (300, 40)];
/// Seeds per cell of the default run.
const SEEDS: u64 = 2;
/// Seeds per cell with `KINSCENE_BENCH_FULL=1`.
const FULL_SEEDS: u64 = 3;
/// Budget per planner and instance.
const BUDGET: Duration = Duration::from_secs(30);
/// Largest budget of the sampler on an infeasible variant.
const INFEASIBLE_PAPER_BUDGET: Duration = Duration::from_secs(5);
/// Cells of the quick subset.
const QUICK_CELLS: [(usize, usize); 2] = [(50, 5), (100, 20)];
/// Seeds per cell of the quick subset.
const QUICK_SEEDS: u64 = 2;
/// Budget of the quick subset.
const QUICK_BUDGET: Duration = Duration::from_secs(10);

// ---------------------------------------------------------------------------------------------
// Settings from the environment

fn env(name: &str) -> Option<String> {
    std::env::var(name).ok().filter(|v| !v.trim().is_empty())
}

fn env_flag(name: &str) -> bool {
    env(name).is_some_and(|v| v != "0")
}

fn quick() -> bool {
    env_flag("KINSCENE_BENCH_QUICK")
}

fn full() -> bool {
    env_flag("KINSCENE_BENCH_FULL")
}

fn verbose() -> bool {
    env_flag("KINSCENE_BENCH_VERBOSE")
}

fn budget() -> Duration {
    env("KINSCENE_BENCH_BUDGET")
        .and_then(|v| v.parse::<f64>().ok())
        .and_then(|s| Duration::try_from_secs_f64(s).ok())
        .unwrap_or(if quick() { QUICK_BUDGET } else { BUDGET })
}

fn seeds() -> u64 {
    env("KINSCENE_BENCH_SEEDS")
        .and_then(|v| v.parse().ok())
        .unwrap_or(if quick() {
            QUICK_SEEDS
        } else if full() {
            FULL_SEEDS
        } else {
            SEEDS
        })
}

fn families() -> Vec<Family> {
    match env("KINSCENE_BENCH_FAMILIES") {
        Some(list) => list
            .split(',')
            .map(|f| {
                Family::from_label(f.trim())
                    .unwrap_or_else(|| panic!("unknown family {f:?} (galley, l, u, corridor)"))
            })
            .collect(),
        None => Family::ALL.to_vec(),
    }
}

fn cells() -> Vec<(usize, usize)> {
    if let Some(list) = env("KINSCENE_BENCH_CELLS") {
        return list
            .split(',')
            .map(|c| {
                let (p, t) = c
                    .trim()
                    .split_once('x')
                    .unwrap_or_else(|| panic!("cell {c:?} is not <parts>x<targets>"));
                (
                    p.parse().expect("parts is a number"),
                    t.parse().expect("targets is a number"),
                )
            })
            .collect();
    }
    if quick() {
        return QUICK_CELLS.to_vec();
    }
    if !full() {
        return DEFAULT_CELLS.to_vec();
    }
    PARTS
        .iter()
        .flat_map(|&p| {
            TARGETS
                .iter()
                .filter(move |&&t| t * PARTS_PER_TARGET <= p)
                .map(move |&t| (p, t))
        })
        .collect()
}

fn planner_selected(label: &str) -> bool {
    match env("KINSCENE_BENCH_PLANNERS") {
        Some(list) => list.split(',').any(|p| p.trim() == label),
        None => true,
    }
}

fn paper_samples() -> usize {
    env("KINSCENE_BENCH_PAPER_SAMPLES")
        .and_then(|v| v.parse().ok())
        .unwrap_or(usize::MAX)
}

// ---------------------------------------------------------------------------------------------
// Runs

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Planner {
    Search,
    Paper,
}

impl Planner {
    fn label(self) -> &'static str {
        match self {
            Planner::Search => "search",
            Planner::Paper => "paper",
        }
    }

    fn settings(self, seed: u64) -> TaskSettings {
        let mut s = TaskSettings::default();
        if self == Planner::Paper {
            s.strategy = Strategy::Paper { seed };
            s.max_samples = paper_samples();
        } else {
            s.reduction = env("KINSCENE_BENCH_REDUCTION").is_none_or(|v| v != "0");
            s.dive = env("KINSCENE_BENCH_DIVE").is_none_or(|v| v != "0");
        }
        s
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Verdict {
    Solved,
    Infeasible,
    Timeout,
    /// A plan that fails validation.
    Invalid,
    /// `Err` from the planner.
    Error,
}

impl Verdict {
    fn letter(self) -> &'static str {
        match self {
            Verdict::Solved => "S",
            Verdict::Infeasible => "I",
            Verdict::Timeout => "T",
            Verdict::Invalid => "X",
            Verdict::Error => "E",
        }
    }
}

/// One planner on one instance.
struct Run {
    verdict: Verdict,
    /// Time to the (first) plan: the search's `first_plan`, the sampler's wall time; `None`
    /// without a valid plan.
    to_plan: Option<Duration>,
    /// Wall time of the call.
    wall: Duration,
    steps: usize,
    /// The search's proven suboptimality factor of a returned plan.
    factor: Option<f64>,
    note: String,
}

fn run(planner: Planner, room: &Room, budget: Duration) -> Run {
    let settings = planner.settings(room.params.seed);
    let started = Instant::now();
    let result = plan(
        &room.model,
        &room.problem,
        &settings,
        &NoRefinement,
        &Termination::after(budget),
    );
    let wall = started.elapsed();
    let r = match result {
        Ok(r) => r,
        Err(e) => {
            return Run {
                verdict: Verdict::Error,
                to_plan: None,
                wall,
                steps: 0,
                factor: None,
                note: format!("error: {e}"),
            };
        }
    };
    match r.outcome {
        Outcome::Solved(p) => {
            let to_plan = match planner {
                Planner::Search => r.stats.first_plan.unwrap_or(wall),
                Planner::Paper => wall,
            };
            let (verdict, note) = match validate(&room.model, &room.problem, &p.steps, &settings) {
                Ok(v) if v.valid => (
                    Verdict::Solved,
                    match planner {
                        Planner::Search => format!(
                            "cost {:.2}, proven factor {}, passes {}, dive {}, expanded {}, \
                             evaluated {}, pruned {}, components {}",
                            p.cost,
                            r.stats
                                .suboptimality
                                .map_or("-".into(), |f| format!("{f:.2}")),
                            r.stats.passes,
                            r.stats.greedy_first_plan,
                            r.stats.expanded,
                            r.stats.evaluated,
                            r.stats.pruned,
                            components(room)
                        ),
                        Planner::Paper => format!("{} orders", r.stats.samples),
                    },
                ),
                Ok(v) => (
                    Verdict::Invalid,
                    format!("first failure {:?}, unmet {:?}", v.first_failure, v.unmet),
                ),
                Err(e) => (Verdict::Invalid, format!("validate error: {e}")),
            };
            Run {
                verdict,
                to_plan: (verdict == Verdict::Solved).then_some(to_plan),
                wall,
                steps: p.steps.len(),
                factor: r.stats.suboptimality,
                note,
            }
        }
        Outcome::Infeasible(why) => Run {
            verdict: Verdict::Infeasible,
            to_plan: None,
            wall,
            steps: 0,
            factor: None,
            note: format!(
                "{} (expanded {}, evaluated {}, pruned {})",
                why.message, r.stats.expanded, r.stats.evaluated, r.stats.pruned
            ),
        },
        Outcome::Timeout(partial) | Outcome::Cancelled(partial) => Run {
            verdict: Verdict::Timeout,
            to_plan: None,
            wall,
            steps: partial.plan.steps.len(),
            factor: None,
            note: format!(
                "{} of {} targets unmet; expanded {}, evaluated {}, pruned {}, orders {}",
                partial.unmet.len(),
                room.params.targets,
                r.stats.expanded,
                r.stats.evaluated,
                r.stats.pruned,
                r.stats.samples
            ),
        },
    }
}

/// The number of components of the instance's interaction relation (untimed; `?` on error).
fn components(room: &Room) -> String {
    Interaction::new(&room.model, &room.problem, &TaskSettings::default())
        .map_or("?".into(), |i| i.components().to_string())
}

// ---------------------------------------------------------------------------------------------
// A cell

#[derive(Default)]
struct Cell {
    parts: usize,
    targets: usize,
    search: Vec<Run>,
    paper: Vec<Run>,
    /// Witnesses found / looked for.
    witnesses: (usize, usize),
    /// The infeasible variant (seed 0): search and paper.
    infeasible_search: Option<Run>,
    infeasible_paper: Option<Run>,
    /// Instances generated, the time to generate them.
    generate: Duration,
}

fn loud(what: &str) {
    println!("!!!!! {what}");
    eprintln!("!!!!! {what}");
}

fn measure(family: Family, parts: usize, targets: usize) -> Cell {
    let mut cell = Cell {
        parts,
        targets,
        ..Cell::default()
    };
    let label = |seed: u64, infeasible: bool| {
        format!(
            "{} {parts}x{targets} seed {seed}{}",
            family.label(),
            if infeasible { " infeasible" } else { "" }
        )
    };
    let report = |what: &str, planner: Planner, r: &Run| {
        if verbose() {
            eprintln!(
                "  {what:<32} {:<6} {:<2} to plan {:>10} wall {:>8.2?} steps {:>3} | {}",
                planner.label(),
                r.verdict.letter(),
                r.to_plan.map_or("-".into(), |d| format!("{d:.2?}")),
                r.wall,
                r.steps,
                r.note
            );
        }
        if r.verdict == Verdict::Invalid {
            loud(&format!(
                "{what}: {} returned a plan that fails validation: {}",
                planner.label(),
                r.note
            ));
        }
        if r.verdict == Verdict::Error {
            loud(&format!("{what}: {} failed: {}", planner.label(), r.note));
        }
    };
    for seed in 0..seeds() {
        let what = label(seed, false);
        let started = Instant::now();
        let room = rooms::room(&RoomParams::new(family, parts, targets, seed));
        cell.generate += started.elapsed();
        let witnessed = env("KINSCENE_BENCH_WITNESS").is_none_or(|v| v != "0");
        let witness = witnessed.then(|| rooms::witness(&room, &TaskSettings::default()));
        if let Some(w) = &witness {
            cell.witnesses.1 += 1;
            if w.is_some() {
                cell.witnesses.0 += 1;
            }
        }
        if planner_selected("search") {
            let r = run(Planner::Search, &room, budget());
            report(&what, Planner::Search, &r);
            if r.verdict == Verdict::Infeasible {
                let how = match &witness {
                    Some(Some(_)) => "although the greedy witness found a plan (a search bug)",
                    Some(None) => "no greedy witness either; check by hand",
                    None => "witness not run",
                };
                loud(&format!(
                    "{what}: the search calls a feasible-by-design instance infeasible, {how}: {}",
                    r.note
                ));
            }
            cell.search.push(r);
        }
        if planner_selected("paper") {
            let r = run(Planner::Paper, &room, budget());
            report(&what, Planner::Paper, &r);
            cell.paper.push(r);
        }
    }
    if env("KINSCENE_BENCH_INFEASIBLE").is_none_or(|v| v != "0") && targets >= 2 {
        let what = label(0, true);
        let room = rooms::room(&RoomParams::new(family, parts, targets, 0).infeasible());
        if planner_selected("search") {
            let r = run(Planner::Search, &room, budget());
            report(&what, Planner::Search, &r);
            if r.verdict != Verdict::Infeasible {
                loud(&format!(
                    "{what}: the search does not prove the infeasible variant infeasible ({})",
                    r.verdict.letter()
                ));
            }
            cell.infeasible_search = Some(r);
        }
        if planner_selected("paper") {
            let r = run(Planner::Paper, &room, budget().min(INFEASIBLE_PAPER_BUDGET));
            report(&what, Planner::Paper, &r);
            cell.infeasible_paper = Some(r);
        }
    }
    cell
}

// ---------------------------------------------------------------------------------------------
// Output

/// Median (lower middle) and max of the times to a plan, runs without one counting as ∞
/// (`None`).
fn median_max(runs: &[Run]) -> (Option<Duration>, Option<Duration>) {
    let mut v: Vec<Option<Duration>> = runs.iter().map(|r| r.to_plan).collect();
    v.sort_by_key(|t| (t.is_none(), *t));
    let median = v.get(v.len().saturating_sub(1) / 2).copied().flatten();
    let max = v.last().copied().flatten();
    (median, max)
}

fn secs(d: Option<Duration>) -> String {
    match d {
        None => format!(">{:.0} s", budget().as_secs_f64()),
        Some(d) if d < Duration::from_millis(10) => format!("{:.1} ms", d.as_secs_f64() * 1e3),
        Some(d) if d < Duration::from_secs(1) => format!("{:.0} ms", d.as_secs_f64() * 1e3),
        Some(d) => format!("{:.1} s", d.as_secs_f64()),
    }
}

/// `solved/runs`, and any other outcome than a timeout spelled out.
fn solved(runs: &[Run]) -> String {
    let n = |v: Verdict| runs.iter().filter(|r| r.verdict == v).count();
    let mut s = format!("{}/{}", n(Verdict::Solved), runs.len());
    for (v, what) in [
        (Verdict::Infeasible, "INFEASIBLE"),
        (Verdict::Invalid, "INVALID"),
        (Verdict::Error, "ERROR"),
    ] {
        if n(v) > 0 {
            s += &format!(" ({} {what})", n(v));
        }
    }
    s
}

/// The ratio of the medians search / paper.
fn ratio(search: Option<Duration>, paper: Option<Duration>) -> String {
    match (search, paper) {
        (Some(s), Some(p)) => format!("{:.2}", s.as_secs_f64() / p.as_secs_f64().max(1e-9)),
        (None, Some(p)) => format!(">{:.0}", budget().as_secs_f64() / p.as_secs_f64().max(1e-9)),
        (Some(s), None) => format!("<{:.3}", s.as_secs_f64() / budget().as_secs_f64()),
        (None, None) => "-".into(),
    }
}

/// The search's final outcomes `S/I/T` and its largest proven factor.
fn final_outcome(runs: &[Run]) -> String {
    let n = |v: Verdict| runs.iter().filter(|r| r.verdict == v).count();
    let mut s = format!(
        "{}/{}/{}",
        n(Verdict::Solved),
        n(Verdict::Infeasible),
        n(Verdict::Timeout)
    );
    if let Some(f) = runs.iter().filter_map(|r| r.factor).max_by(f64::total_cmp) {
        s += &format!(", factor ≤ {f:.2}");
    }
    for (v, what) in [(Verdict::Invalid, "INVALID"), (Verdict::Error, "ERROR")] {
        if n(v) > 0 {
            s += &format!(" ({} {what})", n(v));
        }
    }
    s
}

fn variant(r: &Option<Run>) -> String {
    match r {
        None => "-".into(),
        Some(r) => {
            let letter = match r.verdict {
                Verdict::Solved | Verdict::Invalid => "S!",
                v => v.letter(),
            };
            format!("{letter} {}", secs(Some(r.wall)))
        }
    }
}

fn print_table(family: Family, cells: &[Cell]) {
    println!();
    println!(
        "### {} ({} seeds per cell, budget {:.0} s per planner and instance; sampler on the infeasible variant ≤ {:.0} s)",
        family.label(),
        seeds(),
        budget().as_secs_f64(),
        budget().min(INFEASIBLE_PAPER_BUDGET).as_secs_f64()
    );
    println!();
    println!(
        "| cell | search first plan median / max | search final S/I/T | paper median / max | paper solved | search / paper | witnesses | infeasible variant: search, paper |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for c in cells {
        let (sm, sx) = median_max(&c.search);
        let (pm, px) = median_max(&c.paper);
        println!(
            "| {}x{} | {} / {} | {} | {} / {} | {} | {} | {}/{} | {}, {} |",
            c.parts,
            c.targets,
            secs(sm),
            secs(sx),
            final_outcome(&c.search),
            secs(pm),
            secs(px),
            solved(&c.paper),
            ratio(sm, pm),
            c.witnesses.0,
            c.witnesses.1,
            variant(&c.infeasible_search),
            variant(&c.infeasible_paper),
        );
    }
}

fn main() {
    // `--list` (cargo's test harness protocol) only lists; nothing to measure then.
    if std::env::args().any(|a| a == "--list") {
        return;
    }
    let started = Instant::now();
    let cells = cells();
    eprintln!(
        "rooms: families {:?}, cells {cells:?}, {} seeds, budget {:?}, {} hardware threads",
        families().iter().map(|f| f.label()).collect::<Vec<_>>(),
        seeds(),
        budget(),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    for family in families() {
        let mut rows = Vec::new();
        for &(parts, targets) in &cells {
            let t = Instant::now();
            let cell = measure(family, parts, targets);
            eprintln!(
                "rooms: {} {parts}x{targets} done in {:.1?} (generation {:.2?})",
                family.label(),
                t.elapsed(),
                cell.generate
            );
            rows.push(cell);
        }
        print_table(family, &rows);
    }
    println!();
    println!("rooms: {:.1?} in all", started.elapsed());
}
