//! `kinscene validate --scene S.urdf --goal G.toml --plan plan.json [--package NAME=PATH ...]`:
//! replays a plan with the independent validator ([`kinscene::task::validate`], default
//! [`TaskSettings`]) and prints a JSON report on standard output.
//!
//! The plan's `steps` are replayed whatever its `status`: a `"timeout"` plan's partial steps
//! are checked (and usually leave goal joints unmet), an `"infeasible"` plan has no steps and
//! is valid only if the start state already meets the goal.
//!
//! Exit codes: 0 valid, 3 invalid (a step breaks a rule or the goal is unmet; one line on
//! standard error, `kinscene: invalid plan: <reason>`), 2 bad input — including a plan that
//! does not fit the scene (a step naming an unknown joint, or a `to` outside the joint's
//! limits), which is an error, not a verdict.
//!
//! # JSON schema
//!
//! ```text
#![doc = include_str!("validate_schema.txt")]
//! ```

use std::io::Write;
use std::path::PathBuf;

use kinscene::task::{Error, PlanStatus, TaskSettings, validate};
use serde::Serialize;

use crate::input::{SceneArgs, file_error, load_plan, load_problem};
use crate::{CliError, Verdict};

/// Identifies the report format; changes when a field changes meaning or disappears.
const FORMAT: &str = "kinscene-validate/1";

/// Arguments of `kinscene validate`.
#[derive(Debug, clap::Args)]
#[command(
    about = "Replay a plan with dense independent checks; print the verdict as JSON",
    long_about = "Loads a scene URDF, a goal file and a plan document, replays the plan's steps \
                  from the goal's start state with the independent validator (dense sweep \
                  samples, base pose and path, goal test) and prints a JSON report on stdout. \
                  The steps are replayed whatever the plan's status. Exit codes: 0 valid, \
                  3 invalid (one line on stderr: `kinscene: invalid plan: <reason>`), 2 bad \
                  input (including a step naming an unknown joint or a value outside the \
                  joint's limits).",
    after_long_help = concat!("Report (JSON):\n\n", include_str!("validate_schema.txt"))
)]
pub struct Args {
    /// The scene and its mesh packages.
    #[command(flatten)]
    input: SceneArgs,
    /// The goal file the plan was made for: TOML, or JSON if the name ends in `.json`.
    #[arg(long, value_name = "FILE")]
    goal: PathBuf,
    /// The plan document (JSON, as written by `kinscene plan`).
    #[arg(long, value_name = "FILE")]
    plan: PathBuf,
}

/// The report `validate` prints (see the module docs for the schema).
#[derive(Debug, Serialize)]
struct Report {
    format: &'static str,
    plan_status: PlanStatus,
    steps: usize,
    valid: bool,
    first_failure: Option<FirstFailure>,
    unmet: Vec<String>,
    checked_samples: usize,
}

#[derive(Debug, Serialize)]
struct FirstFailure {
    step: usize,
    reason: String,
}

/// Runs `validate`: loads the inputs, replays the plan and writes the report to `out`.
///
/// # Errors
/// A [`CliError`] naming the file for unreadable or malformed inputs, a goal that does not fit
/// the scene, or a plan step naming an unknown joint or a value outside the joint's limits.
pub fn run(args: &Args, out: &mut dyn Write) -> Result<Verdict, CliError> {
    let model = args.input.load()?;
    let problem = load_problem(&model, &args.goal)?;
    let plan = load_plan(&args.plan)?;
    let validation =
        validate(&model, &problem, &plan.steps, &TaskSettings::default()).map_err(|e| match e {
            Error::InvalidStep { .. } => file_error(&args.plan, e),
            _ => file_error(&args.goal, e),
        })?;
    let report = Report {
        format: FORMAT,
        plan_status: plan.status,
        steps: plan.steps.len(),
        valid: validation.valid,
        first_failure: validation
            .first_failure
            .clone()
            .map(|(step, reason)| FirstFailure { step, reason }),
        unmet: validation.unmet.clone(),
        checked_samples: validation.checked_samples,
    };
    serde_json::to_writer_pretty(&mut *out, &report)
        .map_err(|e| CliError::new(format!("cannot write JSON: {e}")))?;
    writeln!(out).map_err(|e| CliError::new(format!("cannot write JSON: {e}")))?;
    if validation.valid {
        return Ok(Verdict::Success);
    }
    let note = match &validation.first_failure {
        Some((step, reason)) => format!("invalid plan: step {step}: {reason}"),
        None => format!(
            "invalid plan: goal joints unmet after the last step: {}",
            validation.unmet.join(", ")
        ),
    };
    Ok(Verdict::Infeasible { note })
}
