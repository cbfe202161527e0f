//! Settings of the navigation grid.

use nalgebra::Point2;
use serde::{Deserialize, Serialize};

use crate::InvalidSetting;
use crate::scene::Error;
use crate::scene::validate::{check_setting_nonneg, check_setting_pos};

/// Largest number of cells a navigation grid may have (2^24, e.g. 200 m × 200 m at 5 cm).
pub const MAX_GRID_CELLS: u64 = 1 << 24;

/// An axis-aligned rectangle of the floor plane (world x, y in metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GridBounds {
    /// Lower-left corner.
    pub min: Point2<f64>,
    /// Upper-right corner.
    pub max: Point2<f64>,
}

/// How the 2D navigation grid is derived from 3D geometry.
///
/// A shape casts a shadow on the grid if its vertical extent overlaps the open interval
/// `(min_height, max_height)` (world z, metres), the height band the robot occupies: a floor
/// slab whose top is at or below `min_height` does not block, nor does a wall cabinet whose
/// bottom is at or above `max_height`. The whole shape's shadow is used, including parts of it
/// outside the band (conservative).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NavGridSettings {
    /// Cell edge length (m), > 0. Default 0.05.
    pub resolution: f64,
    /// Bottom of the robot height band (m). Default 0.01.
    pub min_height: f64,
    /// Top of the robot height band (m), > `min_height`. Default 2.0.
    pub max_height: f64,
    /// Grid extent. `None`: the bounding rectangle of all base shapes' shadows (or the origin
    /// if there are none), grown by `padding` on every side.
    pub bounds: Option<GridBounds>,
    /// Margin added around automatic bounds (m), >= 0. Default 1.0.
    pub padding: f64,
}

impl Default for NavGridSettings {
    fn default() -> Self {
        NavGridSettings {
            resolution: 0.05,
            min_height: 0.01,
            max_height: 2.0,
            bounds: None,
            padding: 1.0,
        }
    }
}

impl NavGridSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for a non-finite or out-of-range field (resolution <= 0,
    /// `max_height <= min_height`, negative padding, empty or non-finite bounds).
    pub fn validate(&self) -> Result<(), Error> {
        check_setting_pos(self.resolution, "nav.resolution")?;
        check_setting_nonneg(self.padding, "nav.padding")?;
        if !self.min_height.is_finite() {
            return Err(InvalidSetting::new("nav.min_height", self.min_height, "finite").into());
        }
        check_setting_pos(
            self.max_height - self.min_height,
            "nav.max_height - nav.min_height",
        )?;
        if let Some(b) = self.bounds {
            check_setting_pos(b.max.x - b.min.x, "nav.bounds.max.x - nav.bounds.min.x")?;
            check_setting_pos(b.max.y - b.min.y, "nav.bounds.max.y - nav.bounds.min.y")?;
            for (field, v) in [
                ("nav.bounds.min.x", b.min.x),
                ("nav.bounds.min.y", b.min.y),
                ("nav.bounds.max.x", b.max.x),
                ("nav.bounds.max.y", b.max.y),
            ] {
                if !v.is_finite() {
                    return Err(InvalidSetting::new(field, v, "finite").into());
                }
            }
        }
        Ok(())
    }

    /// Whether a vertical extent `[z_min, z_max]` overlaps the open band.
    pub fn in_band(&self, z_min: f64, z_max: f64) -> bool {
        z_max > self.min_height && z_min < self.max_height
    }
}
