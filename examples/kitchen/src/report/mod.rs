//! Outputs of the kitchen example.
pub mod svg;
