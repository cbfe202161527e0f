//! Grid search on the navigation grid: reachability and travel distances for the robot base.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, VecDeque};

use crate::scene::nav::NavGrid;

/// The 8 neighbour offsets and their step lengths in cells.
const STEPS: [(isize, isize, f64); 8] = [
    (1, 0, 1.0),
    (-1, 0, 1.0),
    (0, 1, 1.0),
    (0, -1, 1.0),
    (1, 1, std::f64::consts::SQRT_2),
    (1, -1, std::f64::consts::SQRT_2),
    (-1, 1, std::f64::consts::SQRT_2),
    (-1, -1, std::f64::consts::SQRT_2),
];

/// Blocked cells of an inflated occupancy grid, flattened row-major (`j·width + i`).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Blocked {
    pub width: usize,
    pub height: usize,
    pub cells: Vec<bool>,
}

impl Blocked {
    pub fn from_grid(g: &NavGrid) -> Self {
        Blocked {
            width: g.width(),
            height: g.height(),
            cells: g.cells().to_vec(),
        }
    }

    /// Marks every cell blocked in `other` (same size) as blocked here.
    pub fn union_with(&mut self, other: &[bool]) {
        for (a, b) in self.cells.iter_mut().zip(other) {
            *a |= *b;
        }
    }

    fn neighbours(&self, c: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (i, j) = ((c % self.width) as isize, (c / self.width) as isize);
        STEPS.iter().filter_map(move |&(di, dj, len)| {
            let (ni, nj) = (i + di, j + dj);
            if ni < 0 || nj < 0 || ni >= self.width as isize || nj >= self.height as isize {
                return None;
            }
            let n = nj as usize * self.width + ni as usize;
            // No corner cutting: a diagonal step needs both side cells free.
            let side_a = j as usize * self.width + ni as usize;
            let side_b = nj as usize * self.width + i as usize;
            let ok = !self.cells[n]
                && (di == 0 || dj == 0 || (!self.cells[side_a] && !self.cells[side_b]));
            ok.then_some((n, len))
        })
    }

    /// Cells connected to `from` through free cells (8-connected, no corner cutting).
    pub fn component(&self, from: usize) -> Vec<bool> {
        let mut seen = vec![false; self.cells.len()];
        if self.cells[from] {
            return seen;
        }
        seen[from] = true;
        let mut queue = VecDeque::from([from]);
        while let Some(c) = queue.pop_front() {
            for (n, _) in self.neighbours(c) {
                if !seen[n] {
                    seen[n] = true;
                    queue.push_back(n);
                }
            }
        }
        seen
    }

    /// Shortest path lengths (in cells) from `from` to every cell, `INFINITY` where
    /// unreachable (Dijkstra, 8-connected with √2 diagonals, no corner cutting).
    pub fn distances(&self, from: usize) -> Vec<f64> {
        let mut dist = vec![f64::INFINITY; self.cells.len()];
        if self.cells[from] {
            return dist;
        }
        dist[from] = 0.0;
        let mut heap = BinaryHeap::from([Entry(0.0, from)]);
        while let Some(Entry(d, c)) = heap.pop() {
            if d > dist[c] {
                continue;
            }
            for (n, len) in self.neighbours(c) {
                let nd = d + len;
                if nd < dist[n] {
                    dist[n] = nd;
                    heap.push(Entry(nd, n));
                }
            }
        }
        dist
    }

    /// The free cell nearest (Euclidean, in cells) to cell `(i, j)`, if any is free.
    pub fn nearest_free(&self, i: usize, j: usize) -> Option<usize> {
        (0..self.cells.len())
            .filter(|&c| !self.cells[c])
            .min_by(|&a, &b| {
                let d = |c: usize| {
                    let (ci, cj) = ((c % self.width) as f64, (c / self.width) as f64);
                    (ci - i as f64).hypot(cj - j as f64)
                };
                d(a).total_cmp(&d(b)).then(a.cmp(&b))
            })
    }
}

/// Min-heap entry (distance, cell).
#[derive(PartialEq)]
struct Entry(f64, usize);

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
