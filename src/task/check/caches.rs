//! The memo of one search: sweep verdicts, occupancies, manipulation regions, swept
//! footprints, travel distances, per-part footprints and refiner verdicts, each bounded in size.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::occupancy::Occupancy;
use super::region::RegionCell;
use super::{Key, SweepKey, SweepVerdict};
use crate::scene::nav::search::{CellMask, Distances};
use crate::task::refine::Refinement;

/// Caches owned by one search (not shared across threads).
#[derive(Default)]
pub(crate) struct Caches {
    pub sweeps: HashMap<SweepKey, SweepVerdict>,
    pub(super) occupancy: HashMap<Key, Arc<Occupancy>>,
    /// Manipulation regions, keyed like sweeps with the joint's ancestors as context.
    pub(super) regions: HashMap<SweepKey, Arc<Vec<RegionCell>>>,
    /// Swept footprints, keyed like sweeps with ancestors and subtree as context.
    pub(super) swept: HashMap<SweepKey, Arc<CellMask>>,
    /// Travel distances from a robot cell in a state, settled on demand.
    pub(super) travel: HashMap<(Key, usize), Arc<Mutex<Distances>>>,
    /// Inflated footprint of one part at one pose (its joint's and its ancestors' values):
    /// the cells it blocks beyond the inflated base map. Used only when `per_part` is set.
    pub(super) footprints: HashMap<(usize, Vec<u16>), Arc<Vec<u32>>>,
    /// Build occupancies from cached per-part footprints (the search) instead of
    /// rasterising every part at every state (fresh checks).
    pub(super) per_part: bool,
    /// The refiner's verdicts, per (state, joint, target): asked once per move.
    pub(super) refinements: HashMap<(Key, usize, u16), Refinement>,
    /// Refiner calls that vetoed.
    pub vetoes: usize,
}

impl Caches {
    /// Caches for a search: occupancies are assembled from per-part footprints cached by
    /// pose (the same cells as rasterising the whole state: inflation distributes over
    /// unions).
    pub fn for_search() -> Self {
        Caches {
            per_part: true,
            ..Caches::default()
        }
    }
}

/// Entries kept per cache before it is cleared (bounds memory on long searches).
pub(super) const CACHE_LIMIT: usize = 4096;
/// Occupancies kept (each holds two grid-sized arrays).
pub(super) const OCCUPANCY_LIMIT: usize = 512;
/// Travel-distance tables kept (each holds about ten bytes per grid cell).
pub(super) const TRAVEL_LIMIT: usize = 128;

pub(super) fn bounded<K: std::hash::Hash + Eq, V>(m: &mut HashMap<K, V>) {
    bounded_to(m, CACHE_LIMIT);
}

pub(super) fn bounded_to<K: std::hash::Hash + Eq, V>(m: &mut HashMap<K, V>, limit: usize) {
    if m.len() >= limit {
        m.clear();
    }
}
