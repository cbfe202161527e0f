//! The distance bounds found along one straight motion, every one kept per item (a checked
//! pair, or a link against one obstacle), and the best of them carried to another state.
//!
//! **Bound.** An entry `(t_k, d_k)` is a lower bound `d_k` on the item's distance at the
//! state `t_k` of the motion (parry's distance, or a pair's table bound). No point of the item
//! closes in faster than `speed` (m per unit of the motion's parameter, the lever bound of
//! [`levers`](super::levers)), so at any state `t` the distance is at least
//! `d_k − speed·|t − t_k|` for every entry, and so at least their largest. A motion checked in
//! bisection order visits states on both sides of one another: the entry nearest to `t` is
//! often not the latest one, which was all that was kept before (on MotionBenchMaker, half of
//! the pairs' parry calls along motions were certified by an earlier entry).

/// No entry.
const NONE: u32 = u32::MAX;

/// Per item, every `(t, d)` bound found along the motion being checked.
#[derive(Debug, Clone, Default)]
pub(super) struct Bounds {
    /// Per item, its latest entry in `entries` (`NONE`: none yet).
    latest: Vec<u32>,
    /// `(t, d, the item's previous entry)`.
    entries: Vec<(f64, f64, u32)>,
}

impl Bounds {
    /// No entries, for `items` items (a new motion).
    pub(super) fn reset(&mut self, items: usize) {
        self.latest.clear();
        self.latest.resize(items, NONE);
        self.entries.clear();
    }

    /// Records the lower bound `d` (m) on item `item`'s distance at parameter `t`.
    pub(super) fn push(&mut self, item: usize, t: f64, d: f64) {
        let Some(latest) = self.latest.get_mut(item) else {
            return;
        };
        // More than u32::MAX entries in one motion: the item's older entries are dropped
        // (fewer bounds, never a wrong one).
        let previous = std::mem::replace(latest, u32::try_from(self.entries.len()).unwrap_or(NONE));
        if *latest != NONE {
            self.entries.push((t, d, previous));
        }
    }

    /// The largest `d_k − speed·|t − t_k|` over item `item`'s entries (see the module's
    /// bound), `None` without entries.
    pub(super) fn at(&self, item: usize, t: f64, speed: f64) -> Option<f64> {
        let mut k = self.latest.get(item).copied().unwrap_or(NONE);
        let mut best: Option<f64> = None;
        while let Some(&(tk, dk, previous)) = self.entries.get(k as usize) {
            let b = dk - speed * (t - tk).abs();
            best = Some(best.map_or(b, |best| best.max(b)));
            k = previous;
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The best entry wins whatever its age; items are kept apart; a reset forgets.
    #[test]
    fn the_best_entry_is_carried() {
        let mut b = Bounds::default();
        b.reset(3);
        assert_eq!(b.at(0, 0.5, 1.0), None);
        b.push(0, 0.5, 0.1);
        b.push(0, 1.0, 0.0);
        b.push(2, 0.0, 1.0);
        // At 0.55: 0.1 − 0.05 from the older entry beats 0 − 0.45.
        assert!((b.at(0, 0.55, 1.0).unwrap() - 0.05).abs() < 1e-12);
        assert_eq!(b.at(1, 0.55, 1.0), None);
        assert_eq!(b.at(2, 0.25, 2.0), Some(0.5));
        assert_eq!(b.at(7, 0.25, 2.0), None);
        b.reset(3);
        assert_eq!(b.at(0, 0.5, 1.0), None);
    }
}
