//! The `kinscene` command-line tool (the `kinscene-cli` package; the library carries no argument
//! parser).
//!
//! ```text
//! kinscene inspect  --scene S.urdf [--package NAME=PATH ...]
//! kinscene plan     --scene S.urdf --goal G.toml [--budget 10s] [--out plan.json]
//!                   [--strategy search|random|paper] [--seed N]
//!                   [--robot ROBOT.toml|URDF|gen3] [--base holonomic|differential]
//!                   [--tool-link LINK] [--srdf FILE] [--arm-root LINK]
//!                   [--frozen JOINT=VALUE ...] [--contact-link LINK ...]
//!                   [--tool-approach X,Y,Z]
//!                   [--package NAME=PATH ...]
//! kinscene validate --scene S.urdf --goal G.toml --plan plan.json [--package NAME=PATH ...]
//! ```
//!
//! | subcommand | does |
//! |---|---|
//! | `inspect` | loads a scene URDF and prints its joints, handles, base shapes and navigation grid as JSON ([`inspect`]) |
//! | `plan` | plans the order of single-joint changes that reaches a goal and writes the plan document ([`plan`]); with `--robot`, refines it into base and arm motion with timing ([`motion`]) |
//! | `validate` | replays a plan with the independent validator and prints a JSON report ([`validate`]) |
//!
//! Every subcommand reads the scene with `--scene` (relative mesh paths resolve against the
//! URDF's directory) and `--package NAME=PATH` (repeatable: `package://NAME/rest` resolves to
//! `PATH/rest`).
//!
//! # Files
//!
//! - **Goal file** (`--goal`): TOML, or JSON if the name ends in `.json`. `[goal]` maps joint
//!   names to a number (exact, tolerance [`kinscene::task::DEFAULT_TOLERANCE`]) or to
//!   `{ min, max }` / `{ value, tolerance }`; optional `[start]` (joint values, others at 0
//!   clamped into their limits) and `[robot]` (`base = [x, y, yaw]`, `radius`, default
//!   [`kinscene::task::DEFAULT_ROBOT_RADIUS`]). Full schema: [`kinscene::task::GoalSpec`] and
//!   the `kinscene::task` goal module docs; `kinscene plan --help` prints it. Examples for
//!   the kitchen scene: `examples/scenes/goals/`.
//! - **Plan document** (`plan` writes it, `validate` reads it): JSON
//!   `{"status": "solved" | "infeasible" | "timeout", "steps": [{"joint", "from", "to",
//!   "handle", "base", "travel", "cost"}], "cost", "reason", "conflicts", "stats"}`, values in
//!   radians or metres. Full schema: [`kinscene::task::PlanFile`] and the `kinscene::task`
//!   plan module docs; `kinscene plan --help` prints it. Only `status`, `steps` and each
//!   step's `joint`, `from`, `to` are required when it is read back.
//! - **Validation report** (`validate` prints it): see [`validate`].
//!
//! # Exit codes
//!
//! | code | meaning |
//! |---|---|
//! | 0 | success: inspected, solved, or a valid plan (`--help` and `--version` too) |
//! | 2 | bad input: an unreadable or malformed file, a scene the model rejects, a goal or plan that does not fit the scene (unknown joint, value outside the limits, robot start in an obstacle), a malformed `--budget`, or a usage error |
//! | 3 | a negative verdict: `plan` found the goal infeasible, or `validate` found the plan invalid |
//! | 4 | `plan` ran out of its time budget |
//!
//! Codes 3 and 4 end in a [`Verdict`] other than [`Verdict::Success`], not in an error: the
//! subcommand's output (the plan document, the validation report) is written as usual, and
//! one line on standard error says why, **not** prefixed `error:` —
//! `kinscene: infeasible: <reason>`, `kinscene: timeout after <budget>: <reason>` or
//! `kinscene: invalid plan: <reason>`.
//!
//! # Errors
//!
//! Every error is reported as exactly one line on standard error,
//! `kinscene: error: <message>`, and exit code 2; standard output is then empty. Usage errors
//! (unknown options, missing arguments) are reported by clap, also with exit code 2.
//!
//! # Adding a subcommand
//!
//! One file per subcommand, holding its clap `Args` and a
//! `run(&Args, &mut dyn Write) -> Result<Verdict, CliError>` that writes its result to the
//! given output; add a variant to [`Command`] and an arm to [`run`]. Outcomes that are not
//! errors (no plan exists, the budget ran out) are [`Verdict`] variants with their own exit
//! code. Shared inputs (scene, goal, plan files) are read with the helpers of `input.rs`.

mod input;
mod inspect;
mod motion;
mod plan;
mod validate;

use std::fmt;
use std::io::{self, Write};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Model-based mobile manipulation of articulated scenes.
#[derive(Debug, Parser)]
#[command(
    name = "kinscene",
    version,
    about = "Model-based mobile manipulation of articulated scenes",
    after_help = "Exit codes: 0 success (solved, valid plan); 2 bad input or usage error; \
                  3 infeasible goal or invalid plan; 4 time budget exhausted. Errors are one \
                  line on stderr: `kinscene: error: <message>`; verdicts 3 and 4 write their \
                  output as usual plus one line on stderr: `kinscene: infeasible: ...`, \
                  `kinscene: timeout after ...: ...` or `kinscene: invalid plan: ...`. \
                  Goal and plan schemas: `kinscene plan --help`."
)]
struct Cli {
    /// What to do.
    #[command(subcommand)]
    command: Command,
}

/// The subcommands. Their help texts (`about`, `long_about`) are on their `Args`: a doc
/// comment here would replace them (clap takes a variant's doc comment as both).
#[derive(Debug, Subcommand)]
enum Command {
    // `kinscene inspect`: print a scene URDF's joints, handles, base shapes and grid as JSON.
    Inspect(inspect::Args),
    // `kinscene plan`: plan the order of single-joint changes that reaches a goal.
    Plan(Box<plan::Args>),
    // `kinscene validate`: replay a plan with dense independent checks.
    Validate(validate::Args),
}

/// How a subcommand that ran to completion ended. Bad input is not a verdict but a
/// [`CliError`] (exit code 2).
#[derive(Debug, Clone, PartialEq, Eq)]
enum Verdict {
    /// Exit code 0: the command did what was asked (for `validate`: the plan is valid).
    Success,
    /// Exit code 3: a negative verdict — no plan reaches the goal, or the plan is invalid.
    Infeasible {
        /// The line printed on standard error after `kinscene: ` (e.g. `infeasible: <reason>`).
        note: String,
    },
    /// Exit code 4: the time budget ran out before a verdict.
    Timeout {
        /// The line printed on standard error after `kinscene: `.
        note: String,
    },
}

/// Exit code of [`Verdict::Infeasible`].
const EXIT_INFEASIBLE: u8 = 3;

/// Exit code of [`Verdict::Timeout`].
const EXIT_TIMEOUT: u8 = 4;

impl Verdict {
    /// The process exit code of the verdict.
    fn exit_code(&self) -> ExitCode {
        match self {
            Verdict::Success => ExitCode::SUCCESS,
            Verdict::Infeasible { .. } => ExitCode::from(EXIT_INFEASIBLE),
            Verdict::Timeout { .. } => ExitCode::from(EXIT_TIMEOUT),
        }
    }

    /// The one-line note for standard error, if the verdict has one.
    fn note(&self) -> Option<&str> {
        match self {
            Verdict::Success => None,
            Verdict::Infeasible { note } | Verdict::Timeout { note } => Some(note),
        }
    }
}

/// Exit code for bad input: unreadable or malformed files, invalid scenes, usage errors.
const EXIT_BAD_INPUT: u8 = 2;

/// A failure of a subcommand (exit code 2), with a message for the user.
#[derive(Debug, Clone, PartialEq, Eq)]
struct CliError {
    message: String,
}

impl CliError {
    /// An error with the given message.
    fn new(message: impl Into<String>) -> Self {
        CliError {
            message: message.into(),
        }
    }
}

impl fmt::Display for CliError {
    /// The message on one line (see [`one_line`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&one_line(&self.message))
    }
}

/// `text` on one line: runs of whitespace, newlines included, become one space.
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Runs the parsed command, writing its result to `out`.
fn run(cli: &Cli, out: &mut dyn Write) -> Result<Verdict, CliError> {
    match &cli.command {
        Command::Inspect(args) => inspect::run(args, out),
        Command::Plan(args) => plan::run(args, out),
        Command::Validate(args) => validate::run(args, out),
    }
}

fn main() -> ExitCode {
    // Usage errors print clap's message and exit with code 2; --help and --version exit 0.
    let cli = Cli::parse();
    // The result is buffered so that a failing command leaves standard output empty.
    let mut buffer = Vec::new();
    let result = run(&cli, &mut buffer).and_then(|verdict| {
        let mut stdout = io::stdout().lock();
        stdout
            .write_all(&buffer)
            .and_then(|()| stdout.flush())
            .map_err(|e| CliError::new(format!("cannot write to standard output: {e}")))?;
        Ok(verdict)
    });
    match result {
        Ok(verdict) => {
            if let Some(note) = verdict.note() {
                // One line, like an error message, but a verdict: no `error:` prefix.
                eprintln!("kinscene: {}", one_line(note));
            }
            verdict.exit_code()
        }
        Err(e) => {
            eprintln!("kinscene: error: {e}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}
