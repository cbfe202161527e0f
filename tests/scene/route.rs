//! The base route on a navigation grid (`scene::nav::route`): straight when nothing is in the
//! way, around a wall through its gap, and the reasons when there is none. Expected lengths
//! are hand-derived from the grid's geometry.

use kinscene::Outcome;
use kinscene::scene::nav::{NavGrid, NoRoute, route};
use nalgebra::Point2;

/// A 3 m × 2 m grid of 0.1 m cells; with `wall`, cells i = 14, 15 (x ∈ [1.4, 1.6)) are
/// occupied for j < `gap_from` (y < gap_from / 10).
fn grid(wall: Option<usize>) -> NavGrid {
    let mut g = NavGrid::new(Point2::origin(), 0.1, 30, 20).unwrap();
    if let Some(gap_from) = wall {
        for i in 14..16 {
            for j in 0..gap_from {
                g.set_occupied(i, j, true);
            }
        }
    }
    g
}

#[test]
fn a_free_grid_gives_the_straight_segment() {
    let (from, to) = (Point2::new(0.25, 0.35), Point2::new(2.45, 1.65));
    let r = route(&grid(None), from, to, 0.0).unwrap();
    let r = r.solved().expect("nothing in the way");
    assert_eq!(r.points, vec![from, to]);
    // √(2.2² + 1.3²)
    assert!((r.length - (2.2f64.powi(2) + 1.3f64.powi(2)).sqrt()).abs() < 1e-12);
}

#[test]
fn a_wall_is_passed_through_its_gap() {
    // Gap above y = 1.5. The shortest way passes the corners (1.4, 1.5) and (1.6, 1.5):
    // 2·√(1.15² + 1.35²) + 0.2 = 3.7468 m; the grid route may clip a quarter cell of a corner.
    let g = grid(Some(15));
    let (from, to) = (Point2::new(0.25, 0.15), Point2::new(2.75, 0.15));
    let r = route(&g, from, to, 0.0).unwrap();
    let r = r.solved().expect("the gap is open");
    let bound = 2.0 * (1.15f64.powi(2) + 1.35f64.powi(2)).sqrt() + 0.2;
    assert!(r.length > bound - 0.025, "{} < {bound}", r.length);
    assert!(r.length < bound + 0.3, "{} far above {bound}", r.length);
    assert_eq!((r.points[0], *r.points.last().unwrap()), (from, to));
    // Every waypoint is in a free cell, and the polyline's length is the sum of its segments.
    for p in &r.points {
        let (i, j) = g.cell_of(*p).unwrap();
        assert!(!g.is_occupied(i, j), "waypoint {p} in the wall");
    }
    let sum: f64 = r.points.windows(2).map(|s| (s[1] - s[0]).norm()).sum();
    assert!((sum - r.length).abs() < 1e-12);
}

#[test]
fn no_route_says_why() {
    let closed = grid(Some(20));
    let (from, to) = (Point2::new(0.25, 0.15), Point2::new(2.75, 0.15));
    assert_eq!(
        route(&closed, from, to, 0.0).unwrap(),
        Outcome::Infeasible(NoRoute::Disconnected { from, to })
    );
    let in_wall = Point2::new(1.45, 0.5);
    assert_eq!(
        route(&closed, from, in_wall, 0.0).unwrap(),
        Outcome::Infeasible(NoRoute::GoalOccupied(in_wall))
    );
    let off = Point2::new(3.5, 0.5);
    assert_eq!(
        route(&closed, from, off, 0.0).unwrap(),
        Outcome::Infeasible(NoRoute::GoalOffMap(off))
    );
    assert_eq!(
        route(&closed, off, from, 0.0).unwrap(),
        Outcome::Infeasible(NoRoute::StartOffMap(off))
    );
    assert!(route(&closed, Point2::new(f64::NAN, 0.0), to, 0.0).is_err());
}

#[test]
fn a_start_inside_an_obstacle_escapes_within_the_escape_radius() {
    // A 0.5 m thick wall (i = 12..17, x ∈ [1.2, 1.7)) across the whole grid, the start in its
    // middle cell (centre x = 1.45). Its neighbours are occupied too: no route without escape.
    // With 0.25 m every wall cell on its row (centres 0.2 m away at most) is passable, and the
    // way out is straight: 1.0 m to x = 0.45.
    let mut g = NavGrid::new(Point2::origin(), 0.1, 30, 20).unwrap();
    for i in 12..17 {
        for j in 0..20 {
            g.set_occupied(i, j, true);
        }
    }
    let (from, to) = (Point2::new(1.45, 0.55), Point2::new(0.45, 0.55));
    assert_eq!(
        route(&g, from, to, 0.0).unwrap(),
        Outcome::Infeasible(NoRoute::Disconnected { from, to })
    );
    let r = route(&g, from, to, 0.25).unwrap();
    let r = r.solved().expect("the escape radius covers the way out");
    assert_eq!(r.points, vec![from, to]);
    assert!((r.length - 1.0).abs() < 1e-12, "{}", r.length);
}
