//! Free-space reasoning: a spherical range image of a cloud seen from its sensor origin.

use std::collections::HashMap;

use nalgebra::Point3;

/// Minimum range per angular bin (azimuth × elevation) of a cloud around its origin.
#[derive(Debug, Clone)]
pub(crate) struct RangeImage {
    origin: Point3<f64>,
    bin: f64,
    min_range: HashMap<(i64, i64), f64>,
}

impl RangeImage {
    /// Bins `points` seen from `origin` with square angular bins of `bin` rad.
    pub(crate) fn new(points: &[Point3<f64>], origin: Point3<f64>, bin: f64) -> Self {
        let mut min_range: HashMap<(i64, i64), f64> = HashMap::new();
        let mut image = RangeImage {
            origin,
            bin,
            min_range: HashMap::new(),
        };
        for p in points {
            if let Some((key, r)) = image.key(p) {
                let e = min_range.entry(key).or_insert(f64::INFINITY);
                *e = e.min(r);
            }
        }
        image.min_range = min_range;
        image
    }

    fn key(&self, p: &Point3<f64>) -> Option<((i64, i64), f64)> {
        let d = p - self.origin;
        let r = d.norm();
        if r <= 0.0 {
            return None;
        }
        let azimuth = d.y.atan2(d.x);
        let elevation = (d.z / r).asin();
        // Azimuth bins shrink with cos(elevation); scale so bins stay roughly square.
        let ka = (azimuth * elevation.cos().max(1e-3) / self.bin).floor() as i64;
        let ke = (elevation / self.bin).floor() as i64;
        Some(((ka, ke), r))
    }

    /// Whether something observed lies in front of `p` by more than `margin` (m), in `p`'s bin
    /// or one of its 8 neighbours: then `p` was hidden from the sensor and its absence from the
    /// cloud says nothing.
    pub(crate) fn occluded(&self, p: &Point3<f64>, margin: f64) -> bool {
        let Some(((ka, ke), r)) = self.key(p) else {
            return false;
        };
        (-1..=1).any(|da| {
            (-1..=1).any(|de| {
                self.min_range
                    .get(&(ka + da, ke + de))
                    .is_some_and(|&m| m < r - margin)
            })
        })
    }
    /// Whether the sensor saw through the place of `p`: nothing observed in front of it by more
    /// than `margin` ([`occluded`](Self::occluded) is false) and, in `p`'s bin or one of its 8
    /// neighbours, a return behind it by more than `margin`. A point outside the image (no
    /// return around it: outside the field of view or range, or dropped) was not seen
    /// through: its absence from the cloud says nothing either.
    pub(crate) fn seen_through(&self, p: &Point3<f64>, margin: f64) -> bool {
        let Some(((ka, ke), r)) = self.key(p) else {
            return false;
        };
        !self.occluded(p, margin)
            && (-1..=1).any(|da| {
                (-1..=1).any(|de| {
                    self.min_range
                        .get(&(ka + da, ke + de))
                        .is_some_and(|&m| m > r + margin)
                })
            })
    }
}
