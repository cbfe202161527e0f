//! Integration tests, compiled as one binary.

mod backends;
#[cfg(feature = "cli")]
mod cli;
mod scene;
mod task;
