//! The output folder: files collected during the run (plan documents, execution records, top
//! views) and the plots drawn from the report at the end.

use std::path::Path;

use serde::Serialize;

use super::PipelineError;
use super::manipulation::{Attempt, Category};
use super::summary::{Report, fig5_tally, table1_summary, table2_summary};
use super::svg::{self, Series};

/// Files to write, relative to the output folder, in the order produced.
#[derive(Debug, Default)]
pub struct Outputs {
    /// (relative path, contents).
    pub files: Vec<(String, String)>,
}

/// The execution record written next to a plan document.
#[derive(Serialize)]
struct ExecutionRecord<'a> {
    verdict: &'a super::manipulation::Verdict,
    execution: Option<&'a super::sim::Execution>,
    trace: Vec<[f64; 3]>,
}

impl Outputs {
    /// Adds a file.
    pub fn add(&mut self, path: impl Into<String>, contents: String) {
        self.files.push((path.into(), contents));
    }

    /// Adds the plan document and the execution record of an attempt as `plans/<stem>.json`
    /// and `plans/<stem>.exec.json`.
    pub fn add_attempt(&mut self, stem: &str, a: &Attempt) {
        if let Some(doc) = &a.document {
            self.add(format!("plans/{stem}.json"), doc.to_json());
        }
        let record = ExecutionRecord {
            verdict: &a.verdict,
            execution: a.execution.as_ref(),
            trace: a.trace.iter().map(super::stages::pose_array).collect(),
        };
        if let Ok(json) = serde_json::to_string_pretty(&record) {
            self.add(format!("plans/{stem}.exec.json"), json);
        }
    }

    /// Writes every file under `out` (creating folders).
    ///
    /// # Errors
    /// [`PipelineError::Io`] naming the file that could not be written.
    pub fn write(&self, out: &Path) -> Result<(), PipelineError> {
        for (rel, contents) in &self.files {
            let path = out.join(rel);
            let io = |e: std::io::Error| PipelineError::Io {
                path: path.display().to_string(),
                message: e.to_string(),
            };
            if let Some(dir) = path.parent() {
                std::fs::create_dir_all(dir).map_err(io)?;
            }
            std::fs::write(&path, contents).map_err(io)?;
        }
        Ok(())
    }
}

/// Draws the plots of `report` (those whose experiment ran) into `outputs`; a plot that cannot
/// be drawn becomes a note.
pub fn plots(report: &Report, outputs: &mut Outputs, notes: &mut Vec<String>) {
    let mut put = |name: &str, svg: Result<String, svg::SvgError>| match svg {
        Ok(s) => outputs.add(name, s),
        Err(e) => notes.push(format!("{name} could not be drawn: {e}")),
    };
    if !report.fig5.is_empty() {
        let tally = fig5_tally(&report.fig5);
        let categories: Vec<String> = tally.iter().map(|(m, _, _)| m.name().to_string()).collect();
        let layers: Vec<Series> = Category::ALL
            .into_iter()
            .map(|c| {
                Series::new(
                    c.name(),
                    tally
                        .iter()
                        .map(|(_, n, counts)| {
                            100.0 * counts.get(&c).copied().unwrap_or(0) as f64 / *n as f64
                        })
                        .collect(),
                )
            })
            .collect();
        put(
            "fig5.svg",
            svg::stacked_bars(
                "Scene-level manipulation (Fig. 5): outcome of every attempt",
                &categories,
                &layers,
                "attempts (%)",
            ),
        );
    }
    if !report.table1.is_empty() {
        let summary = table1_summary(&report.table1);
        let categories = vec![
            "base".to_string(),
            "arm (revolute)".to_string(),
            "arm (prismatic)".to_string(),
        ];
        let series: Vec<Series> = summary
            .iter()
            .map(|r| {
                Series::new(
                    r.method.clone(),
                    vec![
                        r.base.unwrap_or(0.0),
                        r.arm_rev.unwrap_or(0.0),
                        r.arm_pris.unwrap_or(0.0),
                    ],
                )
            })
            .collect();
        put(
            "table1.svg",
            svg::bar_chart(
                "Single-object manipulation (Table I): simulated time until 30° / 5 cm",
                &categories,
                &series,
                "time (s)",
                None,
                None,
            ),
        );
    }
    if !report.table2.is_empty() || !report.type_checks.is_empty() {
        let summary = table2_summary(&report.table2, &report.type_checks);
        let categories = vec![
            "prismatic: angle (°)".to_string(),
            "revolute: angle (°)".to_string(),
            "revolute: position (cm)".to_string(),
        ];
        let series: Vec<Series> = summary
            .iter()
            .map(|r| {
                Series::new(
                    r.estimator.clone(),
                    vec![
                        r.pris_angle.unwrap_or(0.0),
                        r.rev_angle.unwrap_or(0.0),
                        100.0 * r.rev_position.unwrap_or(0.0),
                    ],
                )
            })
            .collect();
        put(
            "table2.svg",
            svg::bar_chart(
                "Articulation estimation (Table II): mean errors",
                &categories,
                &series,
                "error",
                None,
                None,
            ),
        );
    }
    if !report.fig6.is_empty() {
        let categories: Vec<String> = report
            .fig6
            .iter()
            .map(|r| format!("run {}", r.run))
            .collect();
        let share = |f: &dyn Fn(&super::summary::Fig6Row) -> usize| -> Vec<f64> {
            report
                .fig6
                .iter()
                .map(|r| {
                    if r.handles == 0 {
                        0.0
                    } else {
                        100.0 * f(r) as f64 / r.handles as f64
                    }
                })
                .collect()
        };
        let layers = vec![
            Series::new("discovered", share(&|r| r.estimation)),
            Series::new(
                "failed: estimation",
                share(&|r| r.exploration - r.estimation.min(r.exploration)),
            ),
            Series::new(
                "failed: exploration",
                share(&|r| r.navigation - r.exploration.min(r.navigation)),
            ),
            Series::new(
                "failed: navigation",
                share(&|r| r.mapping - r.navigation.min(r.mapping)),
            ),
            Series::new(
                "failed: mapping",
                share(&|r| r.handles - r.mapping.min(r.handles)),
            ),
        ];
        put(
            "fig6.svg",
            svg::stacked_bars(
                "Discovery error analysis (Fig. 6): true handles per run",
                &categories,
                &layers,
                "handles (%)",
            ),
        );
    }
}
