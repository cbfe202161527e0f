//! Integration tests of kinscene-ompl against the real OMPL shim.
//!
//! Every test that plans holds [`common::serial`]: OMPL's random seed generator is global, and
//! the seeded-determinism tests need no other planner drawing from it meanwhile.

mod common;
mod errors;
mod maze;
mod motion;
mod outcomes;
mod planners;
mod settings;
