//! The exact decision at the grid's boundary: base cells that the inflated base map blocks
//! only because of its rasterisation, freed when a concrete point in them keeps the robot's
//! disc clear of every base shape by the exact clearance.
//!
//! The inflated base map blocks a cell when its centre is within the robot radius `r` of a
//! cell square that touches a shadow, so a blocked cell can still hold base poses whose disc
//! clears every shadow by up to `resolution·√2`: a gap a few centimetres wider than the robot
//! can be closed on the grid. For each cell blocked by the inflation but not occupied itself,
//! [`Boundary::free`] measures exact 2-D distances ([`Shadow::distance_to`]) from
//! `SAMPLES × SAMPLES` points of the cell's closed square to the in-band base shadows, and
//! frees the cell when one point clears every shadow by `r + clearance`: that point is the
//! cell's *witness*, the base pose the task layer reports for it. The robot's moves between
//! neighbouring cells must stay sound too: the straight segment between the points of two
//! side neighbours (the witness of a freed cell, the centre of a free one) must keep the disc
//! clear of every shadow (distance `> r`); a freed cell with a failing segment to a free
//! neighbour is blocked again, and of two freed cells with a failing segment the one with
//! the smaller clearance, until every segment passes.
//!
//! Parts are not decided exactly: a freed cell counts as blocked at a state when a cell
//! within two cells of it (Chebyshev distance) is in a part's inflated footprint. Proof
//! sketch: a point `p` within `r` of a part square lies within half a cell diagonal of a
//! point nearer the square whose cell centre is within `r` of it, so that centre's cell
//! (inflated) is within one cell of `p`'s cell; the witness lies in the freed cell and its
//! segments in the cell or a side neighbour, hence two cells. Likewise a freed cell is in a
//! move's swept footprint when a cell within one cell of it is.

use std::collections::{BTreeMap, HashMap};

use nalgebra::Point2;

use crate::scene::nav::NavGrid;
use crate::scene::nav::search::CellMask;
use crate::scene::nav::shadow::Shadow;

/// Points per side of a cell tried as witnesses (spacing `resolution / (SAMPLES − 1)`).
const SAMPLES: usize = 5;

/// The cells freed by the exact decision, with their witnesses.
#[derive(Debug, Clone, Default)]
pub(crate) struct Boundary {
    /// The witness of each freed cell.
    points: HashMap<usize, Point2<f64>>,
    /// Cells within Chebyshev distance 2 of a freed cell (empty without freed cells).
    near: Vec<bool>,
    width: usize,
    height: usize,
}

/// An axis-aligned box `[x0, y0, x1, y1]` of a shadow grown by `grow`.
fn grown_box(s: &Shadow, grow: f64) -> [f64; 4] {
    let g = s.radius + grow;
    s.hull.iter().fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |b, p| {
            [
                b[0].min(p.x - g),
                b[1].min(p.y - g),
                b[2].max(p.x + g),
                b[3].max(p.y + g),
            ]
        },
    )
}

impl Boundary {
    /// Frees the cells of `inflated` (the base map `raw` inflated by `radius`) that the exact
    /// rule above admits, given the in-band base `shadows` and the `clearance` (m) a witness
    /// keeps beyond the radius; returns them with their witnesses.
    pub fn free(
        raw: &NavGrid,
        inflated: &mut NavGrid,
        shadows: &[Shadow],
        radius: f64,
        clearance: f64,
    ) -> Self {
        let (w, h, res) = (inflated.width(), inflated.height(), inflated.resolution());
        let reach = radius + clearance;
        let sample = |c: usize, k: usize| {
            let centre = inflated.cell_center(c % w, c / w);
            let step = res / (SAMPLES - 1) as f64;
            let off = |m: usize| (m as f64 - (SAMPLES - 1) as f64 / 2.0) * step;
            Point2::new(centre.x + off(k % SAMPLES), centre.y + off(k / SAMPLES))
        };
        // Per candidate cell, each sample's least distance to the shadows (only shadows
        // within `reach` of the cell can matter).
        let mut least: BTreeMap<usize, [f64; SAMPLES * SAMPLES]> = (0..w * h)
            .filter(|&c| inflated.cells()[c] && !raw.cells()[c])
            .map(|c| (c, [f64::INFINITY; SAMPLES * SAMPLES]))
            .collect();
        let o = inflated.origin();
        let index = |v: f64, o: f64, n: usize| {
            (((v - o) / res).floor().max(0.0) as usize).min(n.saturating_sub(1))
        };
        for s in shadows.iter().filter(|s| !s.hull.is_empty()) {
            let [x0, y0, x1, y1] = grown_box(s, reach);
            if x1 < o.x || y1 < o.y {
                continue;
            }
            for j in index(y0, o.y, h)..=index(y1, o.y, h) {
                for i in index(x0, o.x, w)..=index(x1, o.x, w) {
                    if let Some(d) = least.get_mut(&(j * w + i)) {
                        for (k, dk) in d.iter_mut().enumerate() {
                            *dk = dk.min(s.distance_to(&[sample(j * w + i, k)]));
                        }
                    }
                }
            }
        }
        // Witness: the sample with the most clearance (the first in row order on ties).
        let mut freed: BTreeMap<usize, (Point2<f64>, f64)> = BTreeMap::new();
        for (c, d) in &least {
            let (k, best) = d
                .iter()
                .enumerate()
                .fold(
                    (0, f64::NEG_INFINITY),
                    |b, (k, v)| if *v > b.1 { (k, *v) } else { b },
                );
            if best >= reach {
                freed.insert(*c, (sample(*c, k), best));
            }
        }
        let boxes: Vec<[f64; 4]> = shadows.iter().map(|s| grown_box(s, radius)).collect();
        let segment_clear = |a: Point2<f64>, b: Point2<f64>| {
            let (x0, y0, x1, y1) = (a.x.min(b.x), a.y.min(b.y), a.x.max(b.x), a.y.max(b.y));
            shadows.iter().zip(&boxes).all(|(s, bx)| {
                bx[2] < x0
                    || bx[0] > x1
                    || bx[3] < y0
                    || bx[1] > y1
                    || s.distance_to(&[a, b]) > radius
            })
        };
        // Prune until every side segment from a freed cell passes.
        loop {
            let mut drop = None;
            'cells: for (&c, &(p, clear)) in &freed {
                let (i, j) = (c % w, c / w);
                let sides = [
                    (i > 0).then(|| c - 1),
                    (i + 1 < w).then(|| c + 1),
                    (j > 0).then(|| c - w),
                    (j + 1 < h).then(|| c + w),
                ];
                for n in sides.into_iter().flatten() {
                    let (q, other) = match freed.get(&n) {
                        Some(&(q, cn)) => (q, Some(cn)),
                        None if !inflated.cells()[n] => (inflated.cell_center(n % w, n / w), None),
                        None => continue,
                    };
                    if !segment_clear(p, q) {
                        drop = Some(match other {
                            Some(cn) if cn < clear || (cn == clear && n > c) => n,
                            _ => c,
                        });
                        break 'cells;
                    }
                }
            }
            match drop {
                Some(c) => {
                    freed.remove(&c);
                }
                None => break,
            }
        }
        let mut near = if freed.is_empty() {
            Vec::new()
        } else {
            vec![false; w * h]
        };
        for &c in freed.keys() {
            inflated.set_occupied(c % w, c / w, false);
            for n in chebyshev(c, 2, w, h) {
                near[n] = true;
            }
        }
        Boundary {
            points: freed.into_iter().map(|(c, (p, _))| (c, p)).collect(),
            near,
            width: w,
            height: h,
        }
    }

    /// The witness of a freed cell; `None` for every other cell.
    pub fn point(&self, cell: usize) -> Option<Point2<f64>> {
        self.points.get(&cell).copied()
    }

    /// Number of freed cells.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether a part's inflated footprint at `cell` can block a freed cell (then the
    /// footprint must keep `cell` even where the inflated base map blocks it).
    pub fn near(&self, cell: usize) -> bool {
        self.near.get(cell).copied().unwrap_or(false)
    }

    /// Blocks in `blocked` every freed cell within two cells of a cell of `part_cells` (the
    /// parts' inflated footprints at one state).
    pub fn block_near(&self, blocked: &mut [bool], part_cells: impl Iterator<Item = usize>) {
        if self.points.is_empty() {
            return;
        }
        for c in part_cells.filter(|c| self.near(*c)) {
            for n in chebyshev(c, 2, self.width, self.height) {
                if self.points.contains_key(&n) {
                    blocked[n] = true;
                }
            }
        }
    }

    /// Whether the robot at `cell` can be inside the swept footprint `swept`: the cell is in
    /// it, or, for a freed cell, a cell within one cell of it is.
    pub fn in_sweep(&self, swept: &CellMask, cell: usize) -> bool {
        if self.points.contains_key(&cell) {
            chebyshev(cell, 1, self.width, self.height).any(|n| swept.contains(n))
        } else {
            swept.contains(cell)
        }
    }
}

/// The cells within Chebyshev distance `k` of `cell` on a `w × h` grid (itself included).
fn chebyshev(cell: usize, k: usize, w: usize, h: usize) -> impl Iterator<Item = usize> {
    let (i, j) = (cell % w, cell / w);
    let (i0, i1) = (i.saturating_sub(k), (i + k).min(w - 1));
    let (j0, j1) = (j.saturating_sub(k), (j + k).min(h - 1));
    (j0..=j1).flat_map(move |nj| (i0..=i1).map(move |ni| nj * w + ni))
}
