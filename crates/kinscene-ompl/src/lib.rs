//! OMPL geometric motion planning for kinscene, with the state validity check in Rust.
//!
//! Wraps OMPL 1.5 (Debian `libompl-dev`): planning in SE(2) (a mobile base: bounded x, y, free
//! yaw) and in bounded real vector spaces (an arm's joint space) with one of eleven geometric
//! planners ([`Planner`]), OMPL's path simplifier and interpolation, and termination by a time
//! budget and/or a cancel flag ([`Termination`]).
//!
//! The layering follows OMPL: a [`StateSpace`] and a [`Problem`] (start, goal, tolerance), a
//! [`StateValidityChecker`] you implement (any `Fn(&[f64]) -> bool + Sync` closure is one),
//! optionally a [`MotionValidator`] for whole motions ([`plan_with_motion`]),
//! [`PlanSettings`], and [`plan`], which returns a [`PlanOutcome`] with a [`PlanStatus`].
//! Not finding a path is an outcome inside `Ok`; [`Error`] is for bad input and backend
//! failures.
//!
//! # Isolation
//! OMPL lives in a C++ shim (`cpp/shim.cpp`) with a plain C ABI, compiled by `build.rs` into
//! its own shared object and loaded lazily, once per process, with
//! `dlopen(RTLD_LOCAL | RTLD_DEEPBIND)` (crate `kinscene-shim`), so OMPL's boost does not mix
//! with other backends'. Set `KINSCENE_OMPL_SHIM` to load another build of the shim. Every
//! shim function catches C++ exceptions (they become [`Error::Backend`]); the validity checker
//! is called through an `extern "C"` trampoline that catches panics (they count as invalid
//! states, [`PlanOutcome::checker_panics`]). OMPL's console output is off by default
//! ([`set_log_level`]).
//!
//! # Example
//! ```
//! use std::time::Duration;
//! use kinscene_ompl::{plan, PlanSettings, PlanStatus, Problem, StateSpace, Termination};
//!
//! // A base in a 4 m × 4 m room with a wall x ∈ [1.9, 2.1], y ≤ 3.
//! let space = StateSpace::Se2 { x: [0.0, 4.0], y: [0.0, 4.0] };
//! let problem = Problem::new(space, vec![1.0, 1.0, 0.0], vec![3.0, 1.0, 1.57]);
//! let free = |q: &[f64]| !(q[0] > 1.9 && q[0] < 2.1 && q[1] < 3.0);
//! let outcome = plan(&problem, &free, &PlanSettings::default(),
//!                    Termination::after(Duration::from_secs(1)))?;
//! assert_eq!(outcome.status, PlanStatus::ExactSolution);
//! # Ok::<(), kinscene_ompl::Error>(())
//! ```

#![warn(missing_docs)]

#[cfg(feature = "bench")]
pub mod bench;
mod checker;
mod error;
mod ffi;
mod global;
mod plan;
mod settings;
mod space;

pub use checker::{MotionValidator, StateValidityChecker};
pub use error::Error;
pub use global::{DEFAULT_LOG_LEVEL, LogLevel, load, set_log_level, set_seed};
pub use plan::{PlanOutcome, PlanStatus, plan, plan_with_motion};
pub use settings::{PlanSettings, Planner, Simplifier, Termination};
pub use space::{Problem, StateSpace};
