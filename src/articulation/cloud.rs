//! Point clouds: the observation type and its validation.

use nalgebra::{Point3, Vector3};

use super::error::{ArticulationError, InputKind};

/// An observation: points in the map (world) frame with optional colours.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PointCloud {
    /// Points in the map (world) frame, metres.
    pub points: Vec<Point3<f64>>,
    /// RGB colours in [0, 1], one per point when present.
    pub colors: Option<Vec<[f32; 3]>>,
    /// Sensor position in the map frame (for visibility reasoning), metres.
    pub origin: Point3<f64>,
    /// Acquisition time, seconds.
    pub stamp: f64,
}

impl PointCloud {
    /// A cloud without colours.
    pub fn new(points: Vec<Point3<f64>>, origin: Point3<f64>, stamp: f64) -> Self {
        PointCloud {
            points,
            colors: None,
            origin,
            stamp,
        }
    }

    /// Checks that every number is finite and that colours, when present, match the points.
    ///
    /// # Errors
    /// [`ArticulationError::NonFinite`] for a NaN or infinite point, colour, origin or stamp;
    /// [`ArticulationError::ColorCountMismatch`] when the colour list has the wrong length.
    pub fn validate(&self, input: InputKind) -> Result<(), ArticulationError> {
        let non_finite = |what, index| ArticulationError::NonFinite { input, what, index };
        if let Some(index) = self
            .points
            .iter()
            .position(|p| !p.coords.iter().all(|c| c.is_finite()))
        {
            return Err(non_finite("point", index));
        }
        if let Some(colors) = &self.colors {
            if colors.len() != self.points.len() {
                return Err(ArticulationError::ColorCountMismatch {
                    input,
                    points: self.points.len(),
                    colors: colors.len(),
                });
            }
            if let Some(index) = colors.iter().position(|c| !c.iter().all(|v| v.is_finite())) {
                return Err(non_finite("colour", index));
            }
        }
        if !self.origin.coords.iter().all(|c| c.is_finite()) {
            return Err(non_finite("origin", 0));
        }
        if !self.stamp.is_finite() {
            return Err(non_finite("stamp", 0));
        }
        Ok(())
    }
}

/// The centroid of `points` (the origin for an empty slice).
pub(crate) fn centroid<'p>(points: impl IntoIterator<Item = &'p Point3<f64>>) -> Point3<f64> {
    let mut sum = Vector3::zeros();
    let mut n = 0usize;
    for p in points {
        sum += p.coords;
        n += 1;
    }
    Point3::from(if n == 0 { sum } else { sum / n as f64 })
}
