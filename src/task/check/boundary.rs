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
//! the smaller clearance.
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
    /// Whether each cell is freed (empty without freed cells).
    freed: Vec<bool>,
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
        // Candidates: blocked by the inflation, not occupied, and not provably too close.
        // A cell's points lie within res/√2 of its centre, and the shadow that marks a
        // square lies within res·√2 of any point of it, so a cell whose centre is within
        // `r + m − 1.5·res·√2` of an occupied square has no point with clearance `r + m`.
        let deep = reach - 1.5 * std::f64::consts::SQRT_2 * res - 1e-6;
        let deep = if deep > 0.0 {
            raw.inflate(deep).ok()
        } else {
            None
        };
        let mut slot = vec![u32::MAX; w * h];
        // Per candidate cell, each sample's least distance to the shadows so far (only
        // shadows within `reach` of the cell can matter; a sample below `reach` is out).
        let mut least: Vec<(usize, [f64; SAMPLES * SAMPLES])> = Vec::new();
        for (c, slot) in slot.iter_mut().enumerate() {
            let too_close = deep.as_ref().is_some_and(|d| d.cells()[c]);
            if inflated.cells()[c] && !raw.cells()[c] && !too_close {
                *slot = least.len() as u32;
                least.push((c, [f64::INFINITY; SAMPLES * SAMPLES]));
            }
        }
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
                    let Some((c, d)) = least.get_mut(slot[j * w + i] as usize) else {
                        continue;
                    };
                    for (k, dk) in d.iter_mut().enumerate().filter(|(_, dk)| **dk >= reach) {
                        *dk = dk.min(s.distance_to_point(&sample(*c, k)));
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
        prune(&mut freed, inflated, shadows, radius);
        let mut near = vec![false; if freed.is_empty() { 0 } else { w * h }];
        let mut is_freed = near.clone();
        for &c in freed.keys() {
            inflated.set_occupied(c % w, c / w, false);
            is_freed[c] = true;
            for n in chebyshev(c, 2, w, h) {
                near[n] = true;
            }
        }
        Boundary {
            points: freed.into_iter().map(|(c, (p, _))| (c, p)).collect(),
            freed: is_freed,
            near,
            width: w,
            height: h,
        }
    }

    /// The witness of a freed cell; `None` for every other cell.
    pub fn point(&self, cell: usize) -> Option<Point2<f64>> {
        self.points.get(&cell).copied()
    }

    fn is_freed(&self, cell: usize) -> bool {
        self.freed.get(cell).copied().unwrap_or(false)
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
                if self.is_freed(n) {
                    blocked[n] = true;
                }
            }
        }
    }

    /// Whether a part's inflated footprint at `cell` blocks a freed cell that `which` accepts
    /// (the rule of [`Boundary::block_near`]).
    pub fn blocks_any(&self, cell: usize, which: &dyn Fn(usize) -> bool) -> bool {
        self.near(cell)
            && chebyshev(cell, 2, self.width, self.height).any(|n| self.is_freed(n) && which(n))
    }

    /// Whether the robot at `cell` can be inside the swept footprint `swept`: the cell is in
    /// it, or, for a freed cell, a cell within one cell of it is.
    pub fn in_sweep(&self, swept: &CellMask, cell: usize) -> bool {
        if self.is_freed(cell) {
            chebyshev(cell, 1, self.width, self.height).any(|n| swept.contains(n))
        } else {
            swept.contains(cell)
        }
    }
}

/// Side of the square buckets that index the shadows for segment queries (m).
const BUCKET: f64 = 1.0;

/// Drops freed cells until the straight segment from every freed cell's witness to each side
/// neighbour's point (its witness if freed, its centre if free in `inflated`) keeps the disc
/// of `radius` off every shadow: a failing segment to a free cell drops the freed one, between
/// two freed cells the one with less clearance (the higher index on ties). One pass in cell
/// order suffices: dropping a cell only removes segments, so no segment that passed fails.
fn prune(
    freed: &mut BTreeMap<usize, (Point2<f64>, f64)>,
    inflated: &NavGrid,
    shadows: &[Shadow],
    radius: f64,
) {
    let (w, h) = (inflated.width(), inflated.height());
    // Shadows by the buckets their box grown by the radius overlaps.
    let key = |v: f64| (v / BUCKET).floor() as i64;
    let boxes: Vec<[f64; 4]> = shadows.iter().map(|s| grown_box(s, radius)).collect();
    let mut buckets: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (k, b) in boxes.iter().enumerate().filter(|(_, b)| b[0] <= b[2]) {
        for bx in key(b[0])..=key(b[2]) {
            for by in key(b[1])..=key(b[3]) {
                buckets.entry((bx, by)).or_default().push(k);
            }
        }
    }
    let segment_clear = |a: Point2<f64>, b: Point2<f64>| {
        let (x0, y0, x1, y1) = (a.x.min(b.x), a.y.min(b.y), a.x.max(b.x), a.y.max(b.y));
        (key(x0)..=key(x1)).all(|bx| {
            (key(y0)..=key(y1)).all(|by| {
                buckets.get(&(bx, by)).is_none_or(|ks| {
                    ks.iter().all(|&k| {
                        let bb = boxes[k];
                        bb[2] < x0
                            || bb[0] > x1
                            || bb[3] < y0
                            || bb[1] > y1
                            || shadows[k].distance_to(&[a, b]) > radius
                    })
                })
            })
        })
    };
    let cells: Vec<usize> = freed.keys().copied().collect();
    for c in cells {
        let Some(&(p, clear)) = freed.get(&c) else {
            continue;
        };
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
            if segment_clear(p, q) {
                continue;
            }
            match other {
                Some(cn) if cn < clear || (cn == clear && n > c) => {
                    freed.remove(&n);
                }
                _ => {
                    freed.remove(&c);
                    break;
                }
            }
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
