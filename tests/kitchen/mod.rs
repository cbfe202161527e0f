//! The kitchen example's simulator and pipeline (examples/kitchen), tested in place: the
//! example's modules are compiled into this test binary.

#[allow(dead_code)]
#[path = "../../examples/kitchen/sim/mod.rs"]
pub mod sim;

#[allow(dead_code)]
#[path = "../../examples/kitchen/report/mod.rs"]
pub mod report;

#[allow(dead_code)]
#[path = "../../examples/kitchen/pipeline/mod.rs"]
pub mod pipeline;

mod pipeline_tests;
mod sensors_tests;
mod sim_tests;
mod svg_tests;
