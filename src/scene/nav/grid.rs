//! The 2D occupancy grid the robot base drives on.

use nalgebra::Point2;
use serde::{Deserialize, Serialize};

use super::settings::MAX_GRID_CELLS;
use super::shadow::{Shadow, hull_rect_distance};
use crate::InvalidSetting;
use crate::scene::Error;
use crate::scene::validate::check_setting_pos;

/// Slack (m) added to the rasterisation test so that rounding never frees a touched cell.
const RASTER_SLACK: f64 = 1e-9;

/// An occupancy grid on the floor plane (world x, y).
///
/// Conventions: cell `(i, j)` (column `i` along x, row `j` along y) is the square
/// `[x0 + i·res, x0 + (i+1)·res) × [y0 + j·res, y0 + (j+1)·res)` where `(x0, y0)` is
/// [`origin`](NavGrid::origin), the lower-left corner of cell `(0, 0)`; its centre is
/// `(x0 + (i+½)·res, y0 + (j+½)·res)`. Cells are stored row-major, index `j·width + i`.
/// Rasterisation is conservative: a cell is occupied if its closed square touches or
/// intersects a shadow.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NavGrid {
    origin: Point2<f64>,
    resolution: f64,
    width: usize,
    height: usize,
    occupied: Vec<bool>,
}

impl NavGrid {
    /// An all-free grid of `width × height` cells of edge `resolution` (m), cell `(0, 0)`
    /// having its lower-left corner at `origin`.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a non-positive or non-finite resolution or a non-finite
    /// origin; [`Error::GridTooLarge`] for more than [`MAX_GRID_CELLS`] cells.
    pub fn new(
        origin: Point2<f64>,
        resolution: f64,
        width: usize,
        height: usize,
    ) -> Result<Self, Error> {
        check_setting_pos(resolution, "nav resolution")?;
        for v in [origin.x, origin.y] {
            if !v.is_finite() {
                return Err(InvalidSetting::new("nav origin", v, "finite").into());
            }
        }
        let cells = (width as u64).saturating_mul(height as u64);
        if cells > MAX_GRID_CELLS {
            return Err(Error::GridTooLarge {
                cells,
                max: MAX_GRID_CELLS,
            });
        }
        Ok(NavGrid {
            origin,
            resolution,
            width,
            height,
            occupied: vec![false; width * height],
        })
    }

    /// Lower-left corner of cell `(0, 0)` (m).
    pub fn origin(&self) -> Point2<f64> {
        self.origin
    }
    /// Cell edge length (m).
    pub fn resolution(&self) -> f64 {
        self.resolution
    }
    /// Number of columns (along x).
    pub fn width(&self) -> usize {
        self.width
    }
    /// Number of rows (along y).
    pub fn height(&self) -> usize {
        self.height
    }

    /// Whether cell `(i, j)` is occupied. Cells outside the grid count as occupied (the robot
    /// may not leave the map).
    pub fn is_occupied(&self, i: usize, j: usize) -> bool {
        i >= self.width || j >= self.height || self.occupied[j * self.width + i]
    }

    /// Sets cell `(i, j)`; returns false (and does nothing) if it is outside the grid.
    pub fn set_occupied(&mut self, i: usize, j: usize, occupied: bool) -> bool {
        if i < self.width && j < self.height {
            self.occupied[j * self.width + i] = occupied;
            true
        } else {
            false
        }
    }

    /// The cell containing a point, or `None` outside the grid (or for NaN).
    pub fn cell_of(&self, p: Point2<f64>) -> Option<(usize, usize)> {
        let i = ((p.x - self.origin.x) / self.resolution).floor();
        let j = ((p.y - self.origin.y) / self.resolution).floor();
        if i >= 0.0 && j >= 0.0 && i < self.width as f64 && j < self.height as f64 {
            Some((i as usize, j as usize))
        } else {
            None
        }
    }

    /// Centre of cell `(i, j)` (m); defined for any indices.
    pub fn cell_center(&self, i: usize, j: usize) -> Point2<f64> {
        Point2::new(
            self.origin.x + (i as f64 + 0.5) * self.resolution,
            self.origin.y + (j as f64 + 0.5) * self.resolution,
        )
    }

    /// All occupied cells `(i, j)`, row by row.
    pub fn occupied_cells(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let w = self.width;
        self.occupied
            .iter()
            .enumerate()
            .filter(|(_, o)| **o)
            .map(move |(k, _)| (k % w, k / w))
    }

    /// The occupancy of every cell, row-major (index `j·width + i`).
    pub fn cells(&self) -> &[bool] {
        &self.occupied
    }

    /// Number of occupied cells.
    pub fn occupied_count(&self) -> usize {
        self.occupied.iter().filter(|o| **o).count()
    }

    /// A free grid with the same origin, resolution and size.
    pub fn cleared(&self) -> NavGrid {
        NavGrid {
            occupied: vec![false; self.occupied.len()],
            ..self.clone()
        }
    }

    /// Marks every cell occupied in `other` as occupied here.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if the grids differ in size (origin and resolution are
    /// assumed equal; grids from the same model always agree).
    pub fn union_with(&mut self, other: &NavGrid) -> Result<(), Error> {
        if other.width != self.width || other.height != self.height {
            return Err(Error::DimensionMismatch {
                what: "navigation grid cells".into(),
                expected: self.occupied.len(),
                got: other.occupied.len(),
            });
        }
        for (a, b) in self.occupied.iter_mut().zip(&other.occupied) {
            *a |= *b;
        }
        Ok(())
    }

    /// The grid grown by a disc of `radius` (m): a cell is occupied in the result if its
    /// centre is within `radius` of the square of an occupied cell. A disc robot of that radius
    /// centred on a free cell's centre therefore does not overlap any occupied square.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] if `radius` is negative or not finite.
    pub fn inflate(&self, radius: f64) -> Result<NavGrid, Error> {
        crate::scene::validate::check_setting_nonneg(radius, "inflation radius")?;
        let (w, h) = (self.width as isize, self.height as isize);
        // No need to reach further than the grid is wide.
        let reach = (radius / self.resolution + 0.5).ceil().min(w.max(h) as f64) as isize;
        let gap = |d: isize| ((d.abs() as f64) - 0.5).max(0.0) * self.resolution;
        // Half-width of the disc's row span at each row offset (None: row out of reach).
        let span: Vec<Option<isize>> = (-reach..=reach)
            .map(|dj| {
                (0..=reach)
                    .take_while(|&di| gap(di).hypot(gap(dj)) <= radius)
                    .last()
            })
            .collect();
        // Row-wise difference arrays: +1 where a span starts, -1 one past its end.
        let mut delta = vec![0i32; (self.width + 1) * self.height];
        for (i, j) in self.occupied_cells() {
            for (k, half) in span.iter().enumerate() {
                let nj = j as isize + k as isize - reach;
                if let (Some(half), true) = (half, (0..h).contains(&nj)) {
                    let row = nj as usize * (self.width + 1);
                    let lo = (i as isize - half).max(0) as usize;
                    let hi = (i as isize + half + 1).min(w) as usize;
                    delta[row + lo] += 1;
                    delta[row + hi] -= 1;
                }
            }
        }
        let mut out = self.clone();
        for j in 0..self.height {
            let mut running = 0;
            for i in 0..self.width {
                running += delta[j * (self.width + 1) + i];
                if running > 0 {
                    out.occupied[j * self.width + i] = true;
                }
            }
        }
        Ok(out)
    }

    /// Marks every cell whose closed square is within the shadow's disc radius of its hull.
    pub(crate) fn rasterize(&mut self, s: &Shadow) {
        if s.hull.is_empty() {
            return;
        }
        let r = s.radius + RASTER_SLACK;
        let (mut x0, mut y0) = (f64::INFINITY, f64::INFINITY);
        let (mut x1, mut y1) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in &s.hull {
            (x0, y0, x1, y1) = (x0.min(p.x), y0.min(p.y), x1.max(p.x), y1.max(p.y));
        }
        let res = self.resolution;
        let index = |v: f64, o: f64, n: usize| {
            (((v - o) / res).floor().max(0.0) as usize).min(n.saturating_sub(1))
        };
        if x1 + r < self.origin.x || y1 + r < self.origin.y || self.width == 0 || self.height == 0 {
            return;
        }
        let (i0, i1) = (
            index(x0 - r, self.origin.x, self.width),
            index(x1 + r, self.origin.x, self.width),
        );
        let (j0, j1) = (
            index(y0 - r, self.origin.y, self.height),
            index(y1 + r, self.origin.y, self.height),
        );
        for j in j0..=j1 {
            for i in i0..=i1 {
                let lo = Point2::new(
                    self.origin.x + i as f64 * res,
                    self.origin.y + j as f64 * res,
                );
                let hi = Point2::new(lo.x + res, lo.y + res);
                if hull_rect_distance(&s.hull, &lo, &hi) <= r {
                    self.occupied[j * self.width + i] = true;
                }
            }
        }
    }
}
