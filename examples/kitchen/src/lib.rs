//! The kitchen's simulator, pipeline and report, as a library for its binary (`kitchen`) and
//! its tests.
//!
//! - [`sim`]: the simulated world (rapier3d physics of the scene's parts and the robot,
//!   ray-cast depth cameras, a noisy handle detector, fault injection) behind the library's
//!   perception and hardware traits;
//! - [`pipeline`]: the paper's three stages (mapping, articulation discovery, scene-level
//!   manipulation) and its experiments;
//! - [`report`]: the report's pictures.

// The docs are for the kitchen's developers and link its private modules and items.
#![allow(rustdoc::private_intra_doc_links)]

use std::path::{Path, PathBuf};

pub mod pipeline;
pub mod report;
pub mod sim;

#[cfg(test)]
mod tests;

/// The kinscene repository's root, where the kitchen's scene URDF and goal files are
/// (`examples/scenes/`).
pub fn repository() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    root.canonicalize().unwrap_or(root)
}
