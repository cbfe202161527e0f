//! Pictures of the kitchen example: SVG top views of the scene and its plans, and the charts
//! of the experiments.
//!
//! Every picture is a standalone SVG 1.1 document written by hand as text (no drawing
//! library). Text is escaped for XML; bad input (NaN, mismatched lengths, an unknown joint in a
//! plan) is an [`SvgError`], never a panic.
//!
//! - [`top_view()`] / [`top_view_with`]: the scene seen from above (x right, y up, metres), with
//!   each plan step's part sweep, base path and manipulation base pose, and an executed trace.
//! - [`bar_chart`]: grouped bars with an optional fixed maximum and error bars.
//! - [`stacked_bars`]: one stacked bar per category (shares, counts).
//! - [`line_chart`]: several series over a numeric x axis (for example a noise sweep).
//!
//! The SVG elements carry `class` attributes naming what they show (`base-shape` polygons,
//! `part` paths, `handle` dots, `sweep` groups of `sweep-outline` paths, `base-path` polylines,
//! `robot-pose` groups with a `footprint` circle and a `heading` line, the `trace` polyline;
//! `bar`, `error-bar`, `stack` groups of `segment`s, `line`s and `point`s, `tick` labels), so
//! tests and style sheets can find them.
//!
//! Files: `document` writes SVG text (escaping, number formats, palette, the document frame);
//! `check` validates input; `axes` and `charts` draw the charts; `geometry` projects colliders
//! on the floor; `top_view` draws the scene with `bodies`, `plan` and `view` (the world → pixel
//! map, the grid and the legend).

mod axes;
mod bodies;
mod charts;
mod check;
mod document;
mod geometry;
mod plan;
mod top_view;
mod view;

use kinscene::scene;

// The API of the pictures, at the paths the single file had (`report::svg::X`). The binary
// uses part of it and the tests the rest, so an unused re-export is expected in either build.
#[allow(unused_imports)]
pub use axes::NiceAxis;
#[allow(unused_imports)]
pub use charts::{bar_chart, line_chart, stacked_bars};
#[allow(unused_imports)]
pub use document::{TITLE_HEIGHT_PX, escape, format_value, palette};
#[allow(unused_imports)]
pub use top_view::{TopViewOptions, top_view, top_view_with};

/// A named series of values, one per category.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Shown in the legend.
    pub label: String,
    /// One value per category (or per x value of a [`line_chart`]).
    pub values: Vec<f64>,
}

impl Series {
    /// A series from a label and its values.
    pub fn new(label: impl Into<String>, values: Vec<f64>) -> Self {
        Series {
            label: label.into(),
            values,
        }
    }
}

/// Errors of drawing (bad input: NaN, mismatched lengths, a model computation failing).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SvgError {
    /// A value that must be finite is NaN or infinite.
    #[error("{what} is not finite ({value})")]
    NonFinite {
        /// Which value.
        what: String,
        /// The value found.
        value: f64,
    },
    /// A list does not have the length it must have.
    #[error("{what}: expected {expected} values, got {got}")]
    DimensionMismatch {
        /// Which list.
        what: String,
        /// The length it must have.
        expected: usize,
        /// The length it has.
        got: usize,
    },
    /// Nothing to draw (no categories, no series).
    #[error("nothing to draw: {what} is empty")]
    Empty {
        /// What is empty.
        what: String,
    },
    /// A finite value outside its allowed range (a negative share, a zero width).
    #[error("{what} must be {requirement}, got {value}")]
    OutOfRange {
        /// Which value.
        what: String,
        /// What it must be.
        requirement: &'static str,
        /// The value found.
        value: f64,
    },
    /// A plan step the scene model cannot replay (unknown joint, value outside its limits).
    #[error("plan step {step}: {source}")]
    Step {
        /// The step, counted from 1 as in the legend.
        step: usize,
        /// What the scene model said.
        source: scene::Error,
    },
    /// A scene computation failed (a state not sized for the model, a non-finite value).
    #[error(transparent)]
    Scene(#[from] scene::Error),
}
