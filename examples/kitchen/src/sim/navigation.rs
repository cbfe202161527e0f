//! The base's own navigation: A* on the inflated occupancy grid of the true scene, with the
//! path shortened by line-of-sight (string pulling), as the library computes it.

use kinscene::Outcome;
use kinscene::scene::nav::NavGrid;
use nalgebra::Point2;

/// A driven route: the polyline from start to goal (m) and its length.
pub(super) type Route = kinscene::scene::nav::Route;

/// The shortest 8-connected grid route from `from` to `to` (no corner cutting), shortened by
/// string pulling, crossing occupied cells only within `escape` of the start: the library's
/// [`kinscene::scene::nav::route`]. `Err` says why there is none.
pub(super) fn route(
    grid: &NavGrid,
    from: Point2<f64>,
    to: Point2<f64>,
    escape: f64,
) -> Result<Route, String> {
    match kinscene::scene::nav::route(grid, from, to, escape).map_err(|e| e.to_string())? {
        Outcome::Solved(route) => Ok(route),
        Outcome::Infeasible(why) => Err(why.to_string()),
        Outcome::Timeout(()) | Outcome::Cancelled(()) => Err("stopped".into()),
    }
}
