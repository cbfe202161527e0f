//! The validator's own grid search: blocked cells, reachability (breadth-first) and the
//! robot's start cell.

use std::collections::VecDeque;

use nalgebra::Point2;

use crate::scene::nav::{NavGrid, occupancy};
use crate::scene::{SceneData, SceneModel, forward_kinematics};
use crate::task::Error;
use crate::task::goal::Problem;

/// Cells of a grid that the robot centre may not occupy, row-major.
pub(super) struct Cells {
    pub(super) width: usize,
    pub(super) height: usize,
    pub(super) blocked: Vec<bool>,
}

impl Cells {
    pub(super) fn of(grid: &NavGrid) -> Self {
        let (width, height) = (grid.width(), grid.height());
        let mut blocked = vec![false; width * height];
        for (i, j) in grid.occupied_cells() {
            blocked[j * width + i] = true;
        }
        Cells {
            width,
            height,
            blocked,
        }
    }

    /// Cells reachable from `from` through free cells: breadth-first, 8 neighbours, a
    /// diagonal step allowed only when both cells it passes between are free.
    pub(super) fn reachable_from(&self, from: usize) -> Vec<bool> {
        let mut seen = vec![false; self.blocked.len()];
        if self.blocked[from] {
            return seen;
        }
        let free = |i: isize, j: isize| {
            i >= 0
                && j >= 0
                && (i as usize) < self.width
                && (j as usize) < self.height
                && !self.blocked[j as usize * self.width + i as usize]
        };
        seen[from] = true;
        let mut queue = VecDeque::from([from]);
        while let Some(c) = queue.pop_front() {
            let (i, j) = ((c % self.width) as isize, (c / self.width) as isize);
            for dj in -1..=1 {
                for di in -1..=1 {
                    let (ni, nj) = (i + di, j + dj);
                    if (di, dj) == (0, 0) || !free(ni, nj) {
                        continue;
                    }
                    if di != 0 && dj != 0 && !(free(ni, j) && free(i, nj)) {
                        continue;
                    }
                    let n = nj as usize * self.width + ni as usize;
                    if !seen[n] {
                        seen[n] = true;
                        queue.push_back(n);
                    }
                }
            }
        }
        seen
    }
}

/// The robot's start cell: the search's rule, re-implemented.
pub(super) fn start_cell(
    model: &SceneModel,
    data: &mut SceneData,
    problem: &Problem,
) -> Result<usize, Error> {
    let radius = problem.robot.radius;
    forward_kinematics(model, data, &problem.start)?;
    let grid = occupancy(model, data)?.inflate(radius)?;
    let cells = Cells::of(&grid);
    let (i, j) = match problem.robot.base {
        Some([x, y, _]) => {
            grid.cell_of(Point2::new(x, y))
                .ok_or_else(|| Error::InvalidRobotStart {
                    x,
                    y,
                    why: "outside the navigation grid".into(),
                })?
        }
        None => (grid.width() / 2, grid.height() / 2),
    };
    let cell = j * cells.width + i;
    if !cells.blocked[cell] {
        return Ok(cell);
    }
    // The free cell nearest to (i, j) in cell units, lowest index on ties.
    let mut nearest: Option<(f64, usize)> = None;
    for (c, _) in cells.blocked.iter().enumerate().filter(|(_, b)| !**b) {
        let d = ((c % cells.width) as f64 - i as f64).hypot((c / cells.width) as f64 - j as f64);
        if nearest.is_none_or(|(best, _)| d < best) {
            nearest = Some((d, c));
        }
    }
    match (nearest, problem.robot.base) {
        (Some((_, c)), Some([x, y, _])) => {
            let p = grid.cell_center(c % cells.width, c / cells.width);
            if (p.x - x).hypot(p.y - y) <= radius + grid.resolution() {
                Ok(c)
            } else {
                Err(Error::InvalidRobotStart {
                    x,
                    y,
                    why: "inside an obstacle (inflated by the robot radius)".into(),
                })
            }
        }
        (Some((_, c)), None) => Ok(c),
        (None, _) => {
            let p = grid.cell_center(i, j);
            Err(Error::InvalidRobotStart {
                x: p.x,
                y: p.y,
                why: "on a grid with no free cell".into(),
            })
        }
    }
}
