//! A route for the robot base on a navigation grid: A* over free cells, shortened by line of
//! sight.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::f64::consts::SQRT_2;
use std::fmt;

use nalgebra::Point2;

use super::NavGrid;
use crate::Outcome;
use crate::scene::Error;
use crate::scene::validate::check_finite;

/// A route: the polyline from start to goal (m) and its length (m).
#[derive(Debug, Clone, PartialEq)]
pub struct Route {
    /// Waypoints, start and goal included; every segment crosses passable cells only.
    pub points: Vec<Point2<f64>>,
    /// Length of the polyline (m).
    pub length: f64,
}

/// Why [`route`] found no route.
#[derive(Debug, Clone, PartialEq)]
pub enum NoRoute {
    /// The start is outside the grid.
    StartOffMap(Point2<f64>),
    /// The goal is outside the grid.
    GoalOffMap(Point2<f64>),
    /// The goal's cell is occupied (`escape` does not apply to the goal).
    GoalOccupied(Point2<f64>),
    /// No chain of passable cells joins the start to the goal.
    Disconnected {
        /// The start.
        from: Point2<f64>,
        /// The goal.
        to: Point2<f64>,
    },
}

impl fmt::Display for NoRoute {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NoRoute::StartOffMap(p) => write!(f, "start ({:.2}, {:.2}) is off the map", p.x, p.y),
            NoRoute::GoalOffMap(p) => write!(f, "goal ({:.2}, {:.2}) is off the map", p.x, p.y),
            NoRoute::GoalOccupied(p) => write!(f, "goal ({:.2}, {:.2}) is occupied", p.x, p.y),
            NoRoute::Disconnected { from, to } => write!(
                f,
                "no free route from ({:.2}, {:.2}) to ({:.2}, {:.2})",
                from.x, from.y, to.x, to.y
            ),
        }
    }
}

/// Cells the base may cross: free cells, and occupied cells within `escape` of the start.
struct Passable<'a> {
    grid: &'a NavGrid,
    start: Point2<f64>,
    escape: f64,
}

impl Passable<'_> {
    fn cell(&self, i: usize, j: usize) -> bool {
        if i >= self.grid.width() || j >= self.grid.height() {
            return false;
        }
        !self.grid.is_occupied(i, j)
            || (self.grid.cell_center(i, j) - self.start).norm() <= self.escape
    }

    fn point(&self, p: &Point2<f64>) -> bool {
        self.grid.cell_of(*p).is_some_and(|(i, j)| self.cell(i, j))
    }

    /// Whether the segment `a`–`b` crosses passable cells only (sampled at a quarter cell).
    fn segment(&self, a: &Point2<f64>, b: &Point2<f64>) -> bool {
        let n = ((b - a).norm() / (self.grid.resolution() / 4.0))
            .ceil()
            .max(1.0) as usize;
        (0..=n).all(|k| self.point(&(a + (b - a) * (k as f64 / n as f64))))
    }
}

/// The shortest 8-connected route over the passable cells of `grid` from `from` to `to` (no
/// corner cutting: a diagonal step needs both side cells passable), shortened by string
/// pulling (from each kept point, the farthest later point in line of sight, checked at a
/// quarter cell).
///
/// `grid` is the robot's occupancy, usually inflated by its footprint
/// ([`NavGrid::inflate`]). A cell is passable when free, or when occupied and within `escape`
/// (m) of `from`: a robot parked close to a counter can still drive away (0 for none). Ties
/// break on the cell index, so the route is deterministic.
///
/// # Errors
/// [`Error::NonFinite`] for NaN or infinite coordinates or `escape`. No route is
/// [`Outcome::Infeasible`] with the reason; the call takes no termination condition, so it is
/// never stopped.
///
/// # Example
/// ```
/// use kinscene::scene::nav::{NavGrid, route};
/// use nalgebra::Point2;
///
/// // A 2 m × 1 m grid of 0.1 m cells with a wall at x ∈ [0.9, 1.1) up to y = 0.8.
/// let mut grid = NavGrid::new(Point2::origin(), 0.1, 20, 10)?;
/// for i in 9..11 {
///     for j in 0..8 {
///         grid.set_occupied(i, j, true);
///     }
/// }
/// let r = route(&grid, Point2::new(0.35, 0.15), Point2::new(1.65, 0.15), 0.0)?;
/// let r = r.solved().expect("a gap above the wall");
/// // Over the wall's top corners (0.9, 0.8) and (1.1, 0.8): at least 2·√(0.55² + 0.65²) + 0.2
/// // = 1.903 m (less a quarter cell the line-of-sight sampling may clip), and much shorter
/// // than the grid's staircase.
/// assert!(r.length > 1.903 - 0.025 && r.length < 2.2, "{}", r.length);
/// assert!(r.points.iter().all(|p| grid.cell_of(*p).is_some()));
/// # Ok::<(), kinscene::scene::Error>(())
/// ```
pub fn route(
    grid: &NavGrid,
    from: Point2<f64>,
    to: Point2<f64>,
    escape: f64,
) -> Result<Outcome<Route, NoRoute>, Error> {
    check_finite([from.x, from.y, to.x, to.y, escape], || {
        "route start, goal or escape".into()
    })?;
    let pass = Passable {
        grid,
        start: from,
        escape,
    };
    let Some(start) = grid.cell_of(from) else {
        return Ok(Outcome::Infeasible(NoRoute::StartOffMap(from)));
    };
    let Some(goal) = grid.cell_of(to) else {
        return Ok(Outcome::Infeasible(NoRoute::GoalOffMap(to)));
    };
    if grid.is_occupied(goal.0, goal.1) {
        return Ok(Outcome::Infeasible(NoRoute::GoalOccupied(to)));
    }
    let Some(chain) = astar(&pass, start, goal) else {
        return Ok(Outcome::Infeasible(NoRoute::Disconnected { from, to }));
    };
    let w = grid.width();
    let mut raw = Vec::with_capacity(chain.len() + 2);
    raw.push(from);
    raw.extend(
        chain
            .iter()
            .skip(1)
            .take(chain.len().saturating_sub(2))
            .map(|&k| grid.cell_center(k % w, k / w)),
    );
    raw.push(to);
    let points = pull_string(&pass, &raw);
    let length = points.windows(2).map(|s| (s[1] - s[0]).norm()).sum();
    Ok(Outcome::Solved(Route { points, length }))
}

/// The cells (row-major indices) of a shortest 8-connected chain from `start` to `goal`, both
/// included; `None` if they are not connected.
fn astar(pass: &Passable<'_>, start: (usize, usize), goal: (usize, usize)) -> Option<Vec<usize>> {
    let grid = pass.grid;
    let w = grid.width();
    let index = |(i, j): (usize, usize)| j * w + i;
    let cells = w * grid.height();
    let mut cost = vec![f64::INFINITY; cells];
    let mut came: Vec<Option<usize>> = vec![None; cells];
    let mut open = BinaryHeap::new();
    // Octile distance: admissible and consistent for 8-connected steps of 1 and √2 cells.
    let h = |(i, j): (usize, usize)| {
        let (dx, dy) = (i.abs_diff(goal.0) as f64, j.abs_diff(goal.1) as f64);
        (dx.max(dy) + (SQRT_2 - 1.0) * dx.min(dy)) * grid.resolution()
    };
    cost[index(start)] = 0.0;
    // Keys are non-negative floats, whose bit patterns order as the values do; ties break on
    // the cell index.
    open.push(Reverse((h(start).to_bits(), index(start))));
    let mut found = false;
    while let Some(Reverse((_, k))) = open.pop() {
        let (i, j) = (k % w, k / w);
        if (i, j) == goal {
            found = true;
            break;
        }
        for (di, dj) in [
            (-1, 0),
            (1, 0),
            (0, -1),
            (0, 1),
            (-1, -1),
            (-1, 1),
            (1, -1),
            (1, 1),
        ] {
            let (Some(ni), Some(nj)) = (i.checked_add_signed(di), j.checked_add_signed(dj)) else {
                continue;
            };
            if !pass.cell(ni, nj) {
                continue;
            }
            let diagonal = di != 0 && dj != 0;
            if diagonal && !(pass.cell(ni, j) && pass.cell(i, nj)) {
                continue;
            }
            let step = if diagonal { SQRT_2 } else { 1.0 } * grid.resolution();
            let n = index((ni, nj));
            let c = cost[k] + step;
            if c < cost[n] {
                cost[n] = c;
                came[n] = Some(k);
                open.push(Reverse(((c + h((ni, nj))).to_bits(), n)));
            }
        }
    }
    if !found {
        return None;
    }
    let mut chain = vec![index(goal)];
    while let Some(prev) = came[chain[chain.len() - 1]] {
        chain.push(prev);
    }
    chain.reverse();
    Some(chain)
}

/// From each kept point, the farthest later point of `raw` in line of sight.
fn pull_string(pass: &Passable<'_>, raw: &[Point2<f64>]) -> Vec<Point2<f64>> {
    let mut points = vec![raw[0]];
    let mut at = 0;
    while at + 1 < raw.len() {
        let mut next = at + 1;
        for k in (at + 2..raw.len()).rev() {
            if pass.segment(&raw[at], &raw[k]) {
                next = k;
                break;
            }
        }
        points.push(raw[next]);
        at = next;
    }
    points
}
