//! Why a move has no base pose, in numbers: the limit of the manipulation region
//! ([`ManipulationSettings`](super::ManipulationSettings)) that a handle's grasp trajectory
//! breaks from every free base cell (part of [`Cause::NoBasePose`](super::Cause::NoBasePose)).

use serde::{Deserialize, Serialize};

/// Why no free base cell can hold a handle along a move: the manipulation region's limit
/// ([`ManipulationSettings`](super::ManipulationSettings)) that its grasp trajectory breaks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReachShortfall {
    /// The handle (of the moving part) that gets furthest.
    pub handle: String,
    /// Waypoints of its grasp trajectory (`steps + 1`).
    pub waypoints: usize,
    /// Cells of the base map hold the handle throughout, but each lies in the footprint the
    /// moving part sweeps (inflated by the robot radius); `limit` is that of the cells outside
    /// it.
    #[serde(default)]
    pub swept: bool,
    /// The limit it breaks first.
    pub limit: ReachLimit,
}

/// A limit of the manipulation region, with the numbers that break it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum ReachLimit {
    /// A waypoint lies outside the grasp height band.
    Height {
        /// The waypoint (0 = the grasp at the start).
        waypoint: usize,
        /// Its height (m).
        z: f64,
        /// The band `[height_min, height_max]` (m).
        band: [f64; 2],
    },
    /// The handle faces up or down too steeply for a side grasp.
    Elevation {
        /// The outward normal's angle from the horizontal at the start (rad).
        elevation: f64,
        /// `max_normal_elevation` (rad).
        max: f64,
    },
    /// No free base cell holds this waypoint at all.
    Unreachable {
        /// The waypoint (0 = the grasp at the start, which needs a cell on the outward side).
        waypoint: usize,
        /// The grasp point (m, world frame).
        position: [f64; 3],
        /// The annulus `[reach_min, reach_max]` (m, horizontal).
        reach: [f64; 2],
        /// Horizontal distance (m) to the nearest free base cell (`None`: the map has none).
        nearest_free: Option<f64>,
        /// With an arm reach set: the least shoulder-to-wrist span (m) any free cell in the
        /// annulus needs, and the arm's largest span (m); `None` when no free cell is in the
        /// annulus.
        arm_span: Option<(f64, f64)>,
    },
    /// Every waypoint is held from some free cell, but no cell holds them all, and the
    /// allowed segments (release and regrasp) do not join them up.
    Split {
        /// The most leading waypoints one cell on the outward side holds.
        held: usize,
        /// `segments`: base positions allowed per move.
        segments: usize,
    },
}

impl std::fmt::Display for ReachShortfall {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (h, n) = (&self.handle, self.waypoints);
        if self.swept {
            f.write_str(
                "every base cell that holds the handle throughout lies where the part \
                 sweeps; clear of the sweep, ",
            )?;
        }
        match &self.limit {
            ReachLimit::Height { waypoint, z, band } => write!(
                f,
                "handle {h} at waypoint {waypoint} of {n} is at height {z:.3} m, outside the \
                 grasp band {:.3}–{:.3} m",
                band[0], band[1]
            ),
            ReachLimit::Elevation { elevation, max } => write!(
                f,
                "handle {h} faces {:.1}° from the horizontal, more than the {:.1}° a side \
                 grasp allows",
                elevation.to_degrees(),
                max.to_degrees()
            ),
            ReachLimit::Unreachable {
                waypoint,
                position: p,
                reach,
                nearest_free,
                arm_span,
            } => {
                write!(
                    f,
                    "handle {h} at waypoint {waypoint} of {n} ({:.3}, {:.3}, {:.3}) m: ",
                    p[0], p[1], p[2]
                )?;
                match (arm_span, nearest_free) {
                    (Some((need, has)), _) => write!(
                        f,
                        "from every free base cell {:.2}–{:.2} m from it the arm must span \
                         at least {need:.3} m from shoulder to wrist, and it spans at most \
                         {has:.3} m",
                        reach[0], reach[1]
                    ),
                    (None, Some(d)) => write!(
                        f,
                        "no free base cell {:.2}–{:.2} m from it holds it (nearest free cell \
                         {d:.3} m)",
                        reach[0], reach[1]
                    ),
                    (None, None) => f.write_str("the base map has no free cell"),
                }
            }
            ReachLimit::Split { held, segments } => write!(
                f,
                "handle {h}: every waypoint of {n} is held from some free base cell, but one \
                 cell holds at most the first {held}, and {segments} base position(s) per \
                 move do not cover the rest"
            ),
        }
    }
}
