//! The report as markdown ([`Report::to_markdown`]): every section, no wall-clock figure
//! unless the configuration asks for it.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::Experiment;
use super::config::Method;
use super::manipulation::{Category, PRISMATIC_TOLERANCE, REVOLUTE_TOLERANCE};
use super::summary::{AttemptRow, Report, fig5_tally, table1_summary, table2_summary};

/// `n / d` in percent, or `–`.
fn pct(n: usize, d: usize) -> String {
    if d == 0 {
        "–".into()
    } else {
        format!("{:.0} %", 100.0 * n as f64 / d as f64)
    }
}

/// A number with `d` decimals, or `–`.
fn num(v: Option<f64>, d: usize) -> String {
    v.map_or_else(|| "–".into(), |x| format!("{x:.d$}"))
}

/// A reason without the numbers and names that differ between runs (estimated part names,
/// values), so equal causes group together.
fn short_reason(s: &str) -> String {
    let mut out = String::new();
    for word in s.split_whitespace() {
        let w = word.trim_matches(|c: char| c == '"' || c == ',' || c == ';' || c == ':');
        let numeric = w.chars().any(|c| c.is_ascii_digit())
            && w.chars()
                .all(|c| c.is_ascii_digit() || ".-()→>".contains(c));
        let estimated =
            w.starts_with("part") && w[4..].chars().next().is_some_and(|c| c.is_ascii_digit());
        out.push_str(if numeric {
            "#"
        } else if estimated {
            "part#"
        } else {
            word
        });
        out.push(' ');
        if out.len() > 160 {
            out.push('…');
            break;
        }
    }
    out.trim_end().to_string()
}

/// Shortens a reason to one table cell.
fn cell(s: &str) -> String {
    let s = s.replace('|', "/").replace('\n', " ");
    if s.chars().count() > 220 {
        format!("{}…", s.chars().take(220).collect::<String>())
    } else {
        s
    }
}

impl Report {
    /// The report as markdown. No wall-clock figure appears unless `config.wall_clock` is set,
    /// so the same configuration gives the same text.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        self.intro(&mut s);
        self.targets(&mut s);
        self.stage1(&mut s);
        self.stage2(&mut s);
        self.fig5_section(&mut s);
        self.table1_section(&mut s);
        self.table2_section(&mut s);
        self.fig6_section(&mut s);
        self.task_section(&mut s);
        self.closing(&mut s);
        s
    }

    fn intro(&self, s: &mut String) {
        let c = &self.config;
        let _ = writeln!(s, "# kinscene kitchen report\n");
        let _ = writeln!(
            s,
            "The three stages of the paper on the simulated kitchen `{}` ({} parts, {} handles, \
             {} base shapes): **mapping** ({} viewpoints, handle detection, fusion, \
             registration) → **articulation discovery** (Algorithm 1 in a rapier3d physics \
             world, {} estimator) → **scene-level manipulation** (the hierarchical planner with \
             the Kinova Gen3 on its omnidirectional base, executed in the simulator).\n",
            self.scene.file,
            self.scene.parts,
            self.scene.handles,
            self.scene.base_shapes,
            match c.viewpoints {
                super::ViewpointChoice::Kitchen => "fixed",
                super::ViewpointChoice::Computed => "computed",
            },
            c.estimator.name()
        );
        let _ = writeln!(
            s,
            "Configuration: {} run(s), seeds {}..={}; depth noise σ = {:.1} mm, detector noise \
             σ = {:.1} mm, grasp compliance σ = {:.1} mm, {:.1}°, fault rate {}; planner budget \
             {} s per call, {}, grasps turned about bar handles by up to {:.2} rad; \
             experiments: {}{}.\n",
            c.runs,
            c.seed,
            c.seed.wrapping_add(c.runs as u64 - 1),
            c.depth_noise * 1e3,
            c.detector_noise * 1e3,
            c.grasp_deflection * 1e3,
            c.grasp_tilt.to_degrees(),
            c.fault_rate,
            c.planner_budget,
            if c.whole_body {
                "whole-body manipulation where no single base pose covers a step"
            } else {
                "fixed-base manipulation (the paper's)"
            },
            c.bar_turn,
            c.experiments
                .iter()
                .map(|e| e.name())
                .collect::<Vec<_>>()
                .join(", "),
            if c.quick { " (quick sizes)" } else { "" }
        );
        let _ = writeln!(
            s,
            "The static base map is the base link of the true URDF (the paper builds it with \
             SLAM; this is a perfect SLAM map). Every time below is **simulated** time; the \
             report holds no wall-clock figure unless asked for, so the same seed gives the \
             same report.\n"
        );
    }

    fn targets(&self, s: &mut String) {
        let _ = writeln!(s, "## Targets and what was reached\n");
        let _ = writeln!(
            s,
            "| figure | paper | target | reached here |\n|---|---|---|---|"
        );
        let rate = |m| num(self.success_rate(m).map(|r| 100.0 * r), 0);
        if !self.fig5.is_empty() {
            let _ = writeln!(
                s,
                "| Fig. 5 scene success, Ours (estimated model) | 73 % | ≥ 95 % | {} % |",
                rate(Method::Ours)
            );
            let _ = writeln!(
                s,
                "| Fig. 5 scene success, Oracle (true model) | – | 100 % | {} % |",
                rate(Method::Oracle)
            );
            let _ = writeln!(
                s,
                "| Fig. 5 scene success, Random | 23 % | near 23 % | {} % |",
                rate(Method::Random)
            );
        }
        for t in table2_summary(&self.table2, &self.type_checks) {
            let _ = writeln!(
                s,
                "| Table II {}: axis angle prismatic / revolute, axis position revolute | {} | ≤ 2° / 2° / 2 cm at σ = 5 mm | {}° / {}° / {} m |",
                t.estimator,
                if t.estimator == "proprioceptive" {
                    "2.77° / 5.43° / 0.19 m (Proprioception)"
                } else {
                    "8.11° / 4.07° / 0.08 m (DiTH)"
                },
                num(t.pris_angle, 2),
                num(t.rev_angle, 2),
                num(t.rev_position, 3)
            );
        }
        if !self.table1.is_empty() {
            let _ = writeln!(
                s,
                "| Table I base repositioning, Exploration-only / Ours | 2.88× | ≥ 3× | {}× |",
                num(self.base_ratio(), 2)
            );
        }
        let _ = writeln!(s);
        self.limits(s);
    }

    /// What limits the figures, from the data: the discovery stage's yield and how many Fig. 5
    /// attempts of Ours had every goal part in its model.
    fn limits(&self, s: &mut String) {
        let Some(first) = self.runs.first() else {
            return;
        };
        let parts = self.scene.joints.len();
        let registered: usize = self
            .runs
            .iter()
            .filter_map(|r| r.discovery.first())
            .map(|d| {
                d.matches
                    .iter()
                    .filter(|m| m.est_kind == m.true_kind)
                    .count()
            })
            .sum();
        let _ = writeln!(
            s,
            "What limits these numbers: the discovery stage ({} estimator) registered, with \
             the right joint type, {registered} of {} true parts over {} run(s) ({:.1} per run; \
             see Stage 2 for each part and why it failed).",
            first
                .discovery
                .first()
                .map_or("–", |d| d.estimator.as_str()),
            parts * self.runs.len(),
            self.runs.len(),
            registered as f64 / self.runs.len() as f64
        );
        let ours: Vec<&AttemptRow> = self
            .fig5
            .iter()
            .filter(|r| r.method == Method::Ours)
            .collect();
        if !ours.is_empty() {
            let missing = ours
                .iter()
                .filter(|r| {
                    r.verdict
                        .reason
                        .starts_with("the estimated model has no part")
                        || r.verdict.reason.contains("was estimated as")
                })
                .count();
            let _ = writeln!(
                s,
                "In {missing} of the {} Fig. 5 attempts of Ours a goal part was missing from the \
                 estimated model (or had the wrong joint type), so nothing could be planned; \
                 the Oracle, planning on the true model with the same planner and simulator, \
                 shows what the planner and the execution achieve on their own.",
                ours.len()
            );
        }
        let _ = writeln!(s);
    }

    fn stage1(&self, s: &mut String) {
        if self.runs.is_empty() {
            return;
        }
        let _ = writeln!(
            s,
            "## Stage 1: mapping\n\nThe robot starts at (1.0, −0.5) facing +y and drives \
             through {} viewpoints (global navigation); detections from all views are fused \
             (3D non-maximum suppression, clustering with confidence) and registered against \
             the base map.\n",
            self.runs[0].mapping.views.len()
        );
        let _ = writeln!(
            s,
            "| run | views reached | detections | fused | registered | rejected | true handles mapped | false positives kept | base time (s) |\n|---|---|---|---|---|---|---|---|---|"
        );
        for r in &self.runs {
            let m = &r.mapping;
            let _ = writeln!(
                s,
                "| {} | {}/{} | {} | {} | {} | {} | {}/{} | {} | {:.1} |",
                r.run,
                m.views.iter().filter(|v| v.reached).count(),
                m.views.len(),
                m.detections,
                m.fused,
                m.registered,
                m.rejected,
                m.true_mapped.len(),
                self.scene.handles,
                m.false_positives,
                m.base_time
            );
        }
        let _ = writeln!(s);
    }

    fn stage2(&self, s: &mut String) {
        if self.runs.is_empty() {
            return;
        }
        let _ = writeln!(
            s,
            "## Stage 2: articulation discovery\n\nHandles are explored farthest from the \
             start first (parts are left open; exploring from the far end keeps the way \
             free), stacked handles lowest first (an open drawer above would hide the top of \
             the front below from the cameras). A registered part is matched to the true \
             part whose handle (zero state) is within 6 cm of its own.\n"
        );
        let _ = writeln!(
            s,
            "| run | estimator | handles explored | parts registered | matched to true parts | base time (s) | arm time (s) |\n|---|---|---|---|---|---|---|"
        );
        for r in &self.runs {
            for d in &r.discovery {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {} | {:.1} | {:.1} |",
                    r.run,
                    d.estimator,
                    d.handles.len(),
                    d.registered,
                    d.matches.len(),
                    d.base_time,
                    d.arm_time
                );
            }
        }
        let _ = writeln!(s);
        self.per_part(s);
        for r in &self.runs {
            let Some(d) = r.discovery.first() else {
                continue;
            };
            let _ = writeln!(
                s,
                "<details><summary>Run {} ({}): every handle</summary>\n\n| # | mapped at (m) | true part | outcome | attempts | pulled (m) | estimate |\n|---|---|---|---|---|---|---|",
                r.run, d.estimator
            );
            for h in &d.handles {
                let _ = writeln!(
                    s,
                    "| {} | ({:.2}, {:.2}, {:.2}) | {} | {} | {} | {:.2} | {} |",
                    h.index,
                    h.mapped[0],
                    h.mapped[1],
                    h.mapped[2],
                    h.true_joint.as_deref().unwrap_or("(none: false positive)"),
                    cell(&h.outcome),
                    h.attempts,
                    h.pull,
                    h.estimate.as_deref().unwrap_or("–")
                );
            }
            let _ = writeln!(s, "\n</details>\n");
        }
    }

    /// Per true part over the runs (configured estimator): how often it was registered with
    /// the right type, and how its failures ended.
    fn per_part(&self, s: &mut String) {
        let _ = writeln!(
            s,
            "Per true part over the {} run(s) ({} estimator): registered with the right type, \
             and the failures by stage with the most frequent reason.\n\n| true joint | \
             registered | not mapped | failed: mapping | navigation | exploration | estimation \
             | most frequent failure |\n|---|---|---|---|---|---|---|---|",
            self.runs.len(),
            self.config.estimator.name()
        );
        for joint in &self.scene.joints {
            let (mut ok, mut unmapped) = (0, 0);
            let mut stages: BTreeMap<&str, usize> = BTreeMap::new();
            let mut reasons: BTreeMap<String, usize> = BTreeMap::new();
            for r in &self.runs {
                let Some(d) = r.discovery.first() else {
                    continue;
                };
                if d.matches
                    .iter()
                    .any(|m| &m.true_joint == joint && m.est_kind == m.true_kind)
                {
                    ok += 1;
                    continue;
                }
                let Some(h) = d
                    .handles
                    .iter()
                    .find(|h| h.true_joint.as_ref() == Some(joint))
                else {
                    unmapped += 1;
                    continue;
                };
                for stage in ["Mapping", "Navigation", "Exploration", "Estimation"] {
                    if h.outcome.starts_with(&format!("failed at {stage}")) {
                        *stages.entry(stage).or_insert(0) += 1;
                    }
                }
                let reason = if h.outcome.starts_with("registered") {
                    format!("{} (wrong type)", h.outcome)
                } else {
                    h.outcome.clone()
                };
                *reasons.entry(reason).or_insert(0) += 1;
            }
            let top = reasons
                .iter()
                .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0)))
                .map_or_else(String::new, |(r, n)| format!("{n}×: {}", cell(r)));
            let n = |k: &str| stages.get(k).copied().unwrap_or(0);
            let _ = writeln!(
                s,
                "| {joint} | {ok}/{} | {unmapped} | {} | {} | {} | {} | {top} |",
                self.runs.len(),
                n("Mapping"),
                n("Navigation"),
                n("Exploration"),
                n("Estimation")
            );
        }
        let _ = writeln!(s);
    }

    fn fig5_section(&self, s: &mut String) {
        if self.sequences.is_empty() && self.fig5.is_empty() {
            return;
        }
        let _ = writeln!(
            s,
            "## Fig. 5: scene-level manipulation\n\nGoal sequences of three objects where the \
             order matters, on the true joint names, translated to the estimated model through \
             the part matching. **Ours**: the hierarchical planner on the estimated model. \
             **Random**: one random order of the goal joints (the paper's baseline) on the \
             estimated model; an order the task layer rejects fails with the failure it \
             predicts, an accepted one is refined (`HierarchicalPlanner::refine`) and \
             executed. **Oracle**: the planner on the true model. The estimated boxes were \
             cut back by the discovery stage wherever they collided in what the robot saw \
             (the closed scene, each opening it executed; depth noise makes boxes a little \
             too large, and adjacent fronts are 3–6 mm apart), and again at each sequence's \
             start state, one face at a time. Parts the discovery stage did not register \
             (or whose handles were never mapped) are in the map as fixed obstacles at the \
             start state (the map is the true static geometry, a perfect SLAM map of what the \
             robot sees; only their joints are unknown). Success: the \
             simulator's true state meets every target (within {:.2} rad / {:.0} mm).\n",
            REVOLUTE_TOLERANCE,
            PRISMATIC_TOLERANCE * 1e3
        );
        let _ = writeln!(
            s,
            "| sequence | goal | start | why the order matters | lattice search on the true model | Random orders rejected (task level, true model) |\n|---|---|---|---|---|---|"
        );
        for q in &self.sequences {
            let rejected: usize = q.random_rejected.values().sum();
            let detail = q
                .random_rejected
                .iter()
                .map(|(k, v)| format!("{v} {k}"))
                .collect::<Vec<_>>()
                .join(", ");
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {}: {} | {}/{}{} |",
                q.name,
                q.goal,
                if q.start.is_empty() {
                    "closed"
                } else {
                    &q.start
                },
                q.about,
                q.search,
                q.order.join("; "),
                rejected,
                q.random_tried,
                if detail.is_empty() {
                    String::new()
                } else {
                    format!(" ({detail})")
                }
            );
        }
        let _ = writeln!(s);
        if self.fig5.is_empty() {
            return;
        }
        let _ = writeln!(
            s,
            "| method | attempts | success | part collision | path blocking | other |\n|---|---|---|---|---|---|"
        );
        for (m, n, counts) in fig5_tally(&self.fig5) {
            let c = |k| counts.get(&k).copied().unwrap_or(0);
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |",
                m.name(),
                n,
                pct(c(Category::Success), n),
                pct(c(Category::PartCollision), n),
                pct(c(Category::PathBlocking), n),
                pct(c(Category::Other), n)
            );
        }
        let _ = writeln!(
            s,
            "\nPaper (real robot): Ours 73 %, Random 23 %.\n\n![Fig. 5](fig5.svg)\n"
        );
        let methods: Vec<Method> = Method::ALL
            .into_iter()
            .filter(|m| self.fig5.iter().any(|r| r.method == *m))
            .collect();
        let _ = writeln!(
            s,
            "| sequence | {} |\n|---|{}",
            methods
                .iter()
                .map(|m| format!("{} successes", m.name()))
                .collect::<Vec<_>>()
                .join(" | "),
            "---|".repeat(methods.len())
        );
        let mut names: Vec<&str> = Vec::new();
        for r in &self.fig5 {
            if !names.contains(&r.sequence.as_str()) {
                names.push(&r.sequence);
            }
        }
        for q in names {
            let cells: Vec<String> = methods
                .iter()
                .map(|m| {
                    let mine: Vec<&AttemptRow> = self
                        .fig5
                        .iter()
                        .filter(|r| r.sequence == q && r.method == *m)
                        .collect();
                    format!(
                        "{}/{}",
                        mine.iter()
                            .filter(|r| r.verdict.category == Category::Success)
                            .count(),
                        mine.len()
                    )
                })
                .collect();
            let _ = writeln!(s, "| {q} | {} |", cells.join(" | "));
        }
        let _ = writeln!(s, "\nWhy the attempts failed (reasons with counts):\n");
        for m in &methods {
            let mut reasons: BTreeMap<String, usize> = BTreeMap::new();
            for r in self.fig5.iter().filter(|r| r.method == *m) {
                if r.verdict.category != Category::Success {
                    let why = format!("{}: {}", r.verdict.category.name(), r.verdict.reason);
                    *reasons.entry(short_reason(&why)).or_insert(0) += 1;
                }
            }
            let mut v: Vec<(String, usize)> = reasons.into_iter().collect();
            v.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
            for (why, n) in v.iter().take(6) {
                let _ = writeln!(s, "- {} — {n}× {}", m.name(), cell(why));
            }
        }
        let _ = writeln!(
            s,
            "\n<details><summary>Every attempt</summary>\n\n| run | sequence | method | result | order executed | sim base (s) | sim arm (s) | why |\n|---|---|---|---|---|---|---|---|"
        );
        for r in &self.fig5 {
            let v = &r.verdict;
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {:.1} | {:.1} | {} |",
                r.run,
                r.sequence,
                r.method.name(),
                v.category.name(),
                v.steps.join("; "),
                v.base_time,
                v.arm_time,
                cell(&v.reason)
            );
        }
        let _ = writeln!(s, "\n</details>\n");
    }

    fn table1_section(&self, s: &mut String) {
        if !self.config.runs_experiment(Experiment::Table1) {
            return;
        }
        let _ = writeln!(
            s,
            "## Table I: single-object manipulation\n\n**Exploration-only**: the discovery \
             stage's heuristic controller on one handle (Algorithm 1 from the start pose; the \
             action starts after its global navigation: local navigation, repositioning, the \
             step back, and every arm motion). **Ours** / **Oracle**: the planner on the \
             estimated / true model from the pose the exploration's global navigation reached, \
             to the target opening, executed. Execution time as the paper defines it: from the \
             start of the action until the true joint has moved 30° (revolute) or 5 cm \
             (prismatic), watched at every physics step, over the measurements that got there; \
             the second table times the whole action. Opening = true opening reached / \
             target.\n"
        );
        let _ = writeln!(
            s,
            "| method | base (s) | arm, revolute (s) | arm, prismatic (s) | opening, revolute | opening, prismatic | reached 30° / 5 cm | measurements |\n|---|---|---|---|---|---|---|---|"
        );
        let summary = table1_summary(&self.table1);
        for r in &summary {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} |",
                r.method,
                num(r.base, 2),
                num(r.arm_rev, 2),
                num(r.arm_pris, 2),
                num(r.open_rev, 2),
                num(r.open_pris, 2),
                r.reached,
                r.n
            );
        }
        let _ = writeln!(
            s,
            "\nThe whole action (until the part is released and the arm retracted):\n\n| method | base (s) | arm, revolute (s) | arm, prismatic (s) |\n|---|---|---|---|"
        );
        for r in &summary {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} |",
                r.method,
                num(r.total_base, 2),
                num(r.total_arm_rev, 2),
                num(r.total_arm_pris, 2),
            );
        }
        let _ = writeln!(
            s,
            "\nPaper: Exploration-only 9.85 / 10.37 / 9.57 s, opening 0.43 / 0.92; Ours 3.41 / \
             3.41 / 4.40 s, 0.78 / 1.00; Oracle 3.39 / 2.99 / 4.68 s, 1.00 / 1.00. Base \
             repositioning Exploration-only / Ours here (until the threshold): {}× (paper 2.88×; \
             whole action: {}×).\n\n![Table I](table1.svg)\n",
            num(self.base_ratio(), 2),
            num(self.total_base_ratio(), 2)
        );
        let _ = writeln!(
            s,
            "<details><summary>Every measurement</summary>\n\n| run | joint | method | target | reached | base to 30° / 5 cm (s) | arm to 30° / 5 cm (s) | base (s) | arm (s) | global navigation before (s) | note |\n|---|---|---|---|---|---|---|---|---|---|---|"
        );
        for r in &self.table1 {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.2} | {} | {} | {} | {} | {} | {} | {} |",
                r.run,
                r.joint,
                r.method,
                r.target,
                num(r.reached, 3),
                num(r.to_threshold.map(|t| t.0), 2),
                num(r.to_threshold.map(|t| t.1), 2),
                num(r.base_time, 2),
                num(r.arm_time, 2),
                num(r.global_time, 2),
                cell(&r.note)
            );
        }
        let _ = writeln!(s, "\n</details>\n");
    }

    fn table2_section(&self, s: &mut String) {
        if !self.config.runs_experiment(Experiment::Table2) {
            return;
        }
        let _ = writeln!(
            s,
            "## Table II: articulation estimation\n\nOver every registered part matched to a \
             true part of the same type (the estimator's type too: a tiny turn registered as \
             the slide the exploration saw is a wrong estimate), at the zero state: axis \
             angle error (degrees, the axis' sign ignored) and, for revolute joints, the \
             distance between the axis lines (m), DiTH's metrics, of the estimator's own axis (as logged; registration then \
             levels an axis within {:.0}° of horizontal or vertical, the gravity prior, and the \
             registered joint's angle error is in the last table). Type accuracy over every \
             estimate of a true part's handle (`unknown` counts as wrong). Depth noise σ = \
             {:.1} mm.\n",
            self.config.discovery.axis_snap.to_degrees(),
            self.config.depth_noise * 1e3
        );
        let _ = writeln!(
            s,
            "| estimator | prismatic: angle (°) | revolute: angle (°) | revolute: position (m) | joint type accuracy | parts (prismatic, revolute) |\n|---|---|---|---|---|---|"
        );
        let summary = table2_summary(&self.table2, &self.type_checks);
        if summary.is_empty() {
            let _ = writeln!(s, "| (no estimate in any run) | – | – | – | – | – |");
        }
        for t in summary {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} ({}/{}) | {}, {} |",
                t.estimator,
                num(t.pris_angle, 2),
                num(t.rev_angle, 2),
                num(t.rev_position, 3),
                pct(t.types.0, t.types.1),
                t.types.0,
                t.types.1,
                t.counts.0,
                t.counts.1
            );
        }
        let _ = writeln!(
            s,
            "\nPaper (real robot): Proprioception 2.77° / 5.43° / 0.19 m; DiTH (two point \
             clouds) 8.11° / 4.07° / 0.08 m.\n\n![Table II](table2.svg)\n"
        );
        let _ = writeln!(
            s,
            "<details><summary>Every part</summary>\n\n| run | estimator | true joint | estimated joint | type (true → estimated) | angle (°) | position (m) | handle offset (m) | registered angle (°) |\n|---|---|---|---|---|---|---|---|---|"
        );
        for r in &self.table2 {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} → {} | {:.2} | {} | {:.3} | {:.2} |",
                r.run,
                r.estimator,
                r.m.true_joint,
                r.m.est_joint,
                r.m.true_kind.as_str(),
                if r.m.estimator_kind == r.m.est_kind {
                    r.m.est_kind.to_string()
                } else {
                    format!(
                        "{} (registered {})",
                        r.m.estimator_kind.as_str(),
                        r.m.est_kind.as_str()
                    )
                },
                r.m.angle_error,
                num(r.m.position_error, 3),
                r.m.handle_distance,
                r.m.registered_angle_error
            );
        }
        let _ = writeln!(s, "\n</details>\n");
    }

    fn fig6_section(&self, s: &mut String) {
        if !self.config.runs_experiment(Experiment::Fig6) {
            return;
        }
        let _ = writeln!(
            s,
            "## Fig. 6: discovery error analysis\n\nPer run, the share of the true handles \
             that pass each stage: **mapping** (mapped, and re-detected at the approach pose; a \
             true handle never mapped fails here), **navigation** (approach and \
             pre-interaction poses reached), **exploration** (the part moved enough), \
             **estimation** (a part registered, matched to the true part, of the right type).\n"
        );
        let _ = writeln!(
            s,
            "| run | true handles | mapping | navigation | exploration | estimation | false positives mapped (became parts) |\n|---|---|---|---|---|---|---|"
        );
        let mut tot = [0usize; 5];
        for r in &self.fig6 {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} ({}) |",
                r.run,
                r.handles,
                pct(r.mapping, r.handles),
                pct(r.navigation, r.handles),
                pct(r.exploration, r.handles),
                pct(r.estimation, r.handles),
                r.false_positives.0,
                r.false_positives.1
            );
            for (t, v) in tot.iter_mut().zip([
                r.handles,
                r.mapping,
                r.navigation,
                r.exploration,
                r.estimation,
            ]) {
                *t += v;
            }
        }
        let _ = writeln!(
            s,
            "| all | {} | {} | {} | {} | {} | |\n\n![Fig. 6](fig6.svg)\n",
            tot[0],
            pct(tot[1], tot[0]),
            pct(tot[2], tot[0]),
            pct(tot[3], tot[0]),
            pct(tot[4], tot[0])
        );
    }

    fn task_section(&self, s: &mut String) {
        if self.task_level.is_empty() {
            return;
        }
        let _ = writeln!(
            s,
            "## Task level on the authored model\n\nEvery goal file of \
             `examples/scenes/goals/` planned on the true kitchen with the lattice search, \
             re-checked by the independent validator, and the paper's Random and Paper \
             baselines (seed 1).\n"
        );
        let wall = self.config.wall_clock;
        let _ = writeln!(
            s,
            "| goal | search | steps | valid | Random | Paper |{}\n|---|---|---|---|---|---|{}",
            if wall { " time (ms) |" } else { "" },
            if wall { "---|" } else { "" }
        );
        for r in &self.task_level {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |{}",
                r.goal,
                r.search,
                r.steps,
                r.valid,
                r.random,
                r.paper,
                if wall {
                    format!(" {:.1} |", r.wall_ms)
                } else {
                    String::new()
                }
            );
        }
        let _ = writeln!(s);
    }

    fn closing(&self, s: &mut String) {
        if let Some(t) = &self.twin {
            let back = match &t.loaded_back {
                Ok(n) => format!("written and read back: {n} joints"),
                Err(e) => format!("could not be read back: {e}"),
            };
            let _ = writeln!(
                s,
                "## Digital twin\n\nThe estimated scene of run {} ({} joints) as URDF, \
                 `twin.urdf`, with the part boxes cut back to agree with what the robot saw, \
                 as the planner used it: {back}.\n",
                t.run, t.joints
            );
        }
        if !self.notes.is_empty() {
            let _ = writeln!(s, "## Notes\n");
            for n in &self.notes {
                let _ = writeln!(s, "- {n}");
            }
            let _ = writeln!(s);
        }
        if !self.files.is_empty() {
            let _ = writeln!(
                s,
                "## Files\n\n`plans/*.json`: the plan document (`MotionDocument`) of every \
                 planner call and Random order, with `*.exec.json` the execution record next \
                 to it; `top-*.svg`: top views of each sequence's plan (Ours, run 0) with base \
                 path, part sweeps and the executed trace; `fig5.svg`, `table1.svg`, \
                 `table2.svg`, `fig6.svg`: the plots; `twin.urdf`; this report. {} files.\n",
                self.files.len()
            );
        }
        if self.config.wall_clock && !self.wall.is_empty() {
            let _ = writeln!(s, "## Wall clock\n\n| phase | s |\n|---|---|");
            for (k, v) in &self.wall {
                let _ = writeln!(s, "| {k} | {v:.1} |");
            }
            let _ = writeln!(s);
        }
    }
}
