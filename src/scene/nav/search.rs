//! Grid searches on the navigation grid for the task search: reachability (flood fill) and
//! travel distances (Dijkstra) of the robot base, and the inflated footprints they run on.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::NavGrid;

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

    /// Cells connected to `from` through free cells (8-connected, no corner cutting): the
    /// reference for [`Flood`].
    #[cfg(test)]
    pub fn component(&self, from: usize) -> Vec<bool> {
        let mut seen = vec![false; self.cells.len()];
        if self.cells[from] {
            return seen;
        }
        seen[from] = true;
        let mut queue = std::collections::VecDeque::from([from]);
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
#[derive(Debug, Clone, PartialEq)]
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

/// The disc of [`NavGrid::inflate`](crate::scene::nav::NavGrid::inflate) for one radius: for
/// each row offset `dj` in `-reach..=reach`, the half-width of the row span of cells whose
/// centre lies within `radius` of the square of the centre cell (`None`: none in that row).
/// Stamping it at every occupied cell marks exactly the cells `inflate` marks (it computes
/// the same spans with the same arithmetic), so inflating part by part and taking the union
/// equals inflating the union.
#[derive(Debug, Clone)]
pub(crate) struct Disc {
    reach: isize,
    span: Vec<Option<isize>>,
}

impl Disc {
    /// The disc of `radius` (m, finite, `>= 0`) on a `width × height` grid of cell size
    /// `resolution`.
    pub fn new(radius: f64, resolution: f64, width: usize, height: usize) -> Self {
        let (w, h) = (width as isize, height as isize);
        let reach = (radius / resolution + 0.5).ceil().min(w.max(h) as f64) as isize;
        let gap = |d: isize| ((d.abs() as f64) - 0.5).max(0.0) * resolution;
        let span = (-reach..=reach)
            .map(|dj| {
                (0..=reach)
                    .take_while(|&di| gap(di).hypot(gap(dj)) <= radius)
                    .last()
            })
            .collect();
        Disc { reach, span }
    }

    /// The cells within the disc of any of `cells` (row-major indices on a `width × height`
    /// grid), as a mask over their bounding box.
    pub fn inflate(&self, width: usize, height: usize, cells: &[u32]) -> CellMask {
        if cells.is_empty() {
            return CellMask::empty(width);
        }
        let (w, h) = (width as isize, height as isize);
        let (mut i0, mut j0, mut i1, mut j1) = (isize::MAX, isize::MAX, isize::MIN, isize::MIN);
        for &c in cells {
            let (i, j) = ((c as usize % width) as isize, (c as usize / width) as isize);
            (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
        }
        let (bi0, bj0) = ((i0 - self.reach).max(0), (j0 - self.reach).max(0));
        let (bi1, bj1) = ((i1 + self.reach).min(w - 1), (j1 + self.reach).min(h - 1));
        let (bw, bh) = ((bi1 - bi0 + 1) as usize, (bj1 - bj0 + 1) as usize);
        // Row-wise difference arrays over the box, as in `NavGrid::inflate`.
        let mut delta = vec![0i32; (bw + 1) * bh];
        for &c in cells {
            let (i, j) = ((c as usize % width) as isize, (c as usize / width) as isize);
            for (k, half) in self.span.iter().enumerate() {
                let nj = j + k as isize - self.reach;
                if let (Some(half), true) = (half, (0..h).contains(&nj)) {
                    let row = (nj - bj0) as usize * (bw + 1);
                    let lo = (i - half).max(0).max(bi0) - bi0;
                    let hi = (i + half + 1).min(w).min(bi1 + 1) - bi0;
                    delta[row + lo as usize] += 1;
                    delta[row + hi as usize] -= 1;
                }
            }
        }
        let mut bits = vec![false; bw * bh];
        for j in 0..bh {
            let mut running = 0;
            for i in 0..bw {
                running += delta[j * (bw + 1) + i];
                bits[j * bw + i] = running > 0;
            }
        }
        CellMask {
            grid_width: width,
            i0: bi0 as usize,
            j0: bj0 as usize,
            width: bw,
            height: bh,
            bits,
        }
    }
}

/// A set of cells of a grid, stored as a mask over a bounding box.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct CellMask {
    grid_width: usize,
    i0: usize,
    j0: usize,
    width: usize,
    height: usize,
    bits: Vec<bool>,
}

impl CellMask {
    /// The empty set on a grid `grid_width` cells wide.
    pub fn empty(grid_width: usize) -> Self {
        CellMask {
            grid_width,
            i0: 0,
            j0: 0,
            width: 0,
            height: 0,
            bits: Vec::new(),
        }
    }

    /// Whether `cell` (row-major index) is in the set.
    pub fn contains(&self, cell: usize) -> bool {
        let (i, j) = (cell % self.grid_width, cell / self.grid_width);
        i >= self.i0
            && j >= self.j0
            && i < self.i0 + self.width
            && j < self.j0 + self.height
            && self.bits[(j - self.j0) * self.width + (i - self.i0)]
    }

    /// The cells of the set, ascending.
    pub fn cells(&self) -> impl Iterator<Item = usize> + '_ {
        self.bits
            .iter()
            .enumerate()
            .filter(|(_, b)| **b)
            .map(|(k, _)| {
                (self.j0 + k / self.width.max(1)) * self.grid_width
                    + self.i0
                    + k % self.width.max(1)
            })
    }
}

/// Indices of the `true` entries of `cells`, ascending (skips zero words eight cells at a
/// time: footprints are sparse).
pub(crate) fn set_cells(cells: &[bool]) -> Vec<u32> {
    let mut out = Vec::new();
    let mut chunks = cells.chunks_exact(8);
    let mut base = 0usize;
    for chunk in &mut chunks {
        if chunk.iter().any(|b| *b) {
            for (k, b) in chunk.iter().enumerate() {
                if *b {
                    out.push((base + k) as u32);
                }
            }
        }
        base += 8;
    }
    for (k, b) in chunks.remainder().iter().enumerate() {
        if *b {
            out.push((base + k) as u32);
        }
    }
    out
}

/// The free component of one cell, explored on demand: [`Flood::reaches`] floods only until
/// the asked cell is found (or the component is exhausted), and keeps the work for the next
/// question. Same connectivity as [`Blocked::component`].
#[derive(Debug, Clone)]
pub(crate) struct Flood {
    seen: Vec<bool>,
    stack: Vec<usize>,
}

impl Flood {
    /// The flood from `from` on `blocked` (nothing reached if `from` is blocked).
    pub fn new(blocked: &Blocked, from: usize) -> Self {
        let mut seen = vec![false; blocked.cells.len()];
        let mut stack = Vec::new();
        if !blocked.cells[from] {
            seen[from] = true;
            stack.push(from);
        }
        Flood { seen, stack }
    }

    /// Whether `cell` is connected to the start through free cells of `blocked` (the grid the
    /// flood was made on).
    pub fn reaches(&mut self, blocked: &Blocked, cell: usize) -> bool {
        while !self.seen[cell] {
            if !self.step(blocked) {
                return false;
            }
        }
        true
    }

    /// The whole component (floods the rest).
    pub fn complete(&mut self, blocked: &Blocked) -> &[bool] {
        while self.step(blocked) {}
        &self.seen
    }

    /// Visits the next cell of the stack; false once it is empty. A diagonal step needs both
    /// side cells free, so it never connects cells that side steps do not: the flood only
    /// follows the four side neighbours.
    fn step(&mut self, blocked: &Blocked) -> bool {
        let Some(c) = self.stack.pop() else {
            return false;
        };
        let (w, h) = (blocked.width, blocked.height);
        let (i, j) = (c % w, c / w);
        let cells = &blocked.cells;
        let mut visit = |n: usize| {
            if !self.seen[n] && !cells[n] {
                self.seen[n] = true;
                self.stack.push(n);
            }
        };
        if i > 0 {
            visit(c - 1);
        }
        if i + 1 < w {
            visit(c + 1);
        }
        if j > 0 {
            visit(c - w);
        }
        if j + 1 < h {
            visit(c + w);
        }
        true
    }
}

/// Shortest path lengths from one cell, settled on demand (Dijkstra stopped early and
/// resumed): the lengths [`Blocked::distances`] returns, cell by cell.
#[derive(Debug, Clone)]
pub(crate) struct Distances {
    dist: Vec<f64>,
    done: Vec<bool>,
    heap: BinaryHeap<Entry>,
}

impl Distances {
    /// Dijkstra from `from` on `blocked`, nothing settled yet.
    pub fn new(blocked: &Blocked, from: usize) -> Self {
        let mut dist = vec![f64::INFINITY; blocked.cells.len()];
        let mut heap = BinaryHeap::new();
        if !blocked.cells[from] {
            dist[from] = 0.0;
            heap.push(Entry(0.0, from));
        }
        Distances {
            dist,
            done: vec![false; blocked.cells.len()],
            heap,
        }
    }

    /// A lower bound on the length of every cell not settled yet (`INFINITY` once all are).
    pub fn frontier(&self) -> f64 {
        self.heap.peek().map_or(f64::INFINITY, |e| e.0)
    }

    /// Settles the next cell: `(cell, length)`, in order of length; `None` when every cell
    /// connected to the source is settled.
    pub fn settle_next(&mut self, blocked: &Blocked) -> Option<(usize, f64)> {
        while let Some(Entry(d, c)) = self.heap.pop() {
            if self.done[c] || d > self.dist[c] {
                continue;
            }
            self.done[c] = true;
            for (n, len) in blocked.neighbours(c) {
                let nd = d + len;
                if nd < self.dist[n] {
                    self.dist[n] = nd;
                    self.heap.push(Entry(nd, n));
                }
            }
            return Some((c, d));
        }
        None
    }

    /// Whether `cell` is settled, and its length if so.
    pub fn settled(&self, cell: usize) -> Option<f64> {
        self.done[cell].then_some(self.dist[cell])
    }

    /// The length of `cell` (`INFINITY` if unreachable), settling as far as needed.
    pub fn to(&mut self, blocked: &Blocked, cell: usize) -> f64 {
        while !self.done[cell] {
            if self.settle_next(blocked).is_none() {
                return f64::INFINITY;
            }
        }
        self.dist[cell]
    }
}

#[cfg(test)]
mod tests {
    use super::NavGrid;
    use super::*;
    use nalgebra::Point2;

    /// A deterministic pseudo-random grid with about one cell in `density` occupied.
    fn grid(w: usize, h: usize, seed: u64, density: u64) -> NavGrid {
        let mut g = NavGrid::new(Point2::new(-1.0, 2.0), 0.05, w, h).expect("grid");
        let mut s = seed;
        for j in 0..h {
            for i in 0..w {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                if (s >> 33) % density == 0 {
                    g.set_occupied(i, j, true);
                }
            }
        }
        g
    }

    /// `Disc::inflate` of the occupied cells equals `NavGrid::inflate` (the reference), for
    /// radii around and between cell multiples and grids smaller than the disc.
    #[test]
    fn disc_matches_navgrid_inflate() {
        for (w, h, seed) in [(40, 30, 1), (7, 50, 2), (3, 3, 3), (60, 61, 4)] {
            for density in [5, 40, 400] {
                let g = grid(w, h, seed * density, density);
                let occupied = set_cells(g.cells());
                for radius in [0.0, 0.02, 0.025, 0.05, 0.1, 0.137, 0.3, 0.35, 1.0] {
                    let reference = g.inflate(radius).expect("inflate");
                    let mask = Disc::new(radius, 0.05, w, h).inflate(w, h, &occupied);
                    for c in 0..w * h {
                        assert_eq!(
                            mask.contains(c),
                            reference.cells()[c],
                            "{w}x{h} seed {seed} density {density} radius {radius} cell {c}"
                        );
                    }
                    let listed: Vec<usize> = mask.cells().collect();
                    let expected: Vec<usize> =
                        (0..w * h).filter(|&c| reference.cells()[c]).collect();
                    assert_eq!(listed, expected);
                }
            }
        }
    }

    /// The on-demand flood and distances agree with the whole-grid versions.
    #[test]
    fn lazy_flood_and_distances_match() {
        let g = grid(50, 40, 7, 4);
        let b = Blocked::from_grid(&g);
        let from = (0..b.cells.len())
            .find(|&c| !b.cells[c])
            .expect("a free cell");
        let component = b.component(from);
        let distances = b.distances(from);
        let mut flood = Flood::new(&b, from);
        let mut lazy = Distances::new(&b, from);
        for c in (0..b.cells.len()).rev().step_by(7) {
            assert_eq!(flood.reaches(&b, c), component[c], "cell {c}");
            assert_eq!(lazy.to(&b, c), distances[c], "cell {c}");
        }
        assert_eq!(flood.complete(&b), &component[..]);
        assert_eq!(
            set_cells(&component).len(),
            component.iter().filter(|x| **x).count()
        );
    }
}
