//! The base's own navigation: A* on the inflated occupancy grid of the true scene, with the
//! path shortened by line-of-sight (string pulling).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use kinscene::scene::nav::NavGrid;
use nalgebra::Point2;

/// A driven route: the polyline from start to goal (m) and its length.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Route {
    /// Waypoints, start and goal included.
    pub points: Vec<Point2<f64>>,
    /// Length (m).
    pub length: f64,
}

/// Cells the base may cross: free cells, and occupied cells within `escape` of the start (a
/// robot parked close to a counter must be able to leave).
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

/// The shortest 8-connected grid route from `from` to `to` (no corner cutting), shortened by
/// string pulling. `Err` says why there is none: a point off the map, an occupied goal, or no
/// connection.
pub(super) fn route(
    grid: &NavGrid,
    from: Point2<f64>,
    to: Point2<f64>,
    escape: f64,
) -> Result<Route, String> {
    let pass = Passable {
        grid,
        start: from,
        escape,
    };
    let start = grid
        .cell_of(from)
        .ok_or_else(|| format!("start ({:.2}, {:.2}) is off the map", from.x, from.y))?;
    let goal = grid
        .cell_of(to)
        .ok_or_else(|| format!("goal ({:.2}, {:.2}) is off the map", to.x, to.y))?;
    if grid.is_occupied(goal.0, goal.1) {
        return Err(format!(
            "goal ({:.2}, {:.2}) is occupied (the robot's footprint does not fit there)",
            to.x, to.y
        ));
    }
    let w = grid.width();
    let index = |(i, j): (usize, usize)| j * w + i;
    let cells = w * grid.height();
    let mut cost = vec![f64::INFINITY; cells];
    let mut came: Vec<Option<usize>> = vec![None; cells];
    let mut open = BinaryHeap::new();
    let h = |(i, j): (usize, usize)| {
        let (dx, dy) = (i.abs_diff(goal.0) as f64, j.abs_diff(goal.1) as f64);
        (dx.max(dy) + (std::f64::consts::SQRT_2 - 1.0) * dx.min(dy)) * grid.resolution()
    };
    cost[index(start)] = 0.0;
    // Keys are non-negative floats, whose bit patterns order as the values do; ties break on
    // the cell index, so the search is deterministic.
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
            let step = if diagonal {
                std::f64::consts::SQRT_2
            } else {
                1.0
            } * grid.resolution();
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
        return Err(format!(
            "no free route from ({:.2}, {:.2}) to ({:.2}, {:.2})",
            from.x, from.y, to.x, to.y
        ));
    }
    let mut chain = vec![index(goal)];
    while let Some(prev) = came[chain[chain.len() - 1]] {
        chain.push(prev);
    }
    chain.reverse();
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
    // String pulling: from each kept point, jump to the farthest point in sight.
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
    let length = points.windows(2).map(|s| (s[1] - s[0]).norm()).sum();
    Ok(Route { points, length })
}
