//! The simulator, pipeline and report, tested in place.

mod discovery_tests;
mod pipeline_tests;
mod sensors_tests;
mod sim_tests;
mod svg_tests;
mod viewpoint_tests;
mod whole_body_tests;
