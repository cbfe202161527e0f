//! Occupancy of a lattice state: the blocked cells of the inflated footprints, assembled from
//! per-part footprints cached by pose or rasterised whole, with the start's free component.

use std::sync::{Arc, Mutex};

use super::caches::{CACHE_LIMIT, Caches, OCCUPANCY_LIMIT, bounded_to};
use super::{Checker, Error};
use crate::scene::nav::search::{Blocked, Flood, set_cells};
use crate::scene::nav::{footprint, part_footprint};
use crate::scene::{PartId, SceneData, State, forward_kinematics};

/// Occupancy of one state: blocked cells, and the start's free component explored on demand.
pub(crate) struct Occupancy {
    pub blocked: Blocked,
    flood: Mutex<Flood>,
}

/// Combinations of a part's placing joints' lattice values tried when looking for a floor
/// footprint ([`Checker::floor_joints`]).
const MAX_FLOOR_COMBINATIONS: usize = 256;

impl Occupancy {
    fn new(blocked: Blocked, start_cell: usize) -> Self {
        Occupancy {
            flood: Mutex::new(Flood::new(&blocked, start_cell)),
            blocked,
        }
    }

    /// Whether `cell` is in the start's free component.
    pub fn reaches(&self, cell: usize) -> bool {
        let mut flood = self.flood.lock().unwrap_or_else(|e| e.into_inner());
        flood.reaches(&self.blocked, cell)
    }

    /// The start's free component.
    pub fn component(&self) -> Vec<bool> {
        let mut flood = self.flood.lock().unwrap_or_else(|e| e.into_inner());
        flood.complete(&self.blocked).to_vec()
    }
}

impl Checker<'_> {
    /// Occupancy of a state, with every part (`all`) or only the parts `include` accepts.
    fn occupancy_of(
        &self,
        data: &mut SceneData,
        state: &State,
        all: bool,
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<Occupancy, Error> {
        forward_kinematics(self.model, data, state)?;
        // Inflation distributes over unions: inflate the parts' footprints alone (few cells)
        // and add the base map's inflated grid, computed once.
        let parts = if all {
            footprint(self.model, data)?
        } else {
            let mut grid = self.model.base_grid().cleared();
            for p in self.model.parts() {
                if include(p.id()) {
                    grid.union_with(&part_footprint(self.model, data, p.id())?)?;
                }
            }
            grid
        };
        let mut blocked = Blocked::from_grid(&self.base_blocked);
        let inflated = parts.inflate(self.radius)?;
        blocked.union_with(inflated.cells());
        let cells = inflated
            .occupied_cells()
            .map(|(i, j)| j * inflated.width() + i);
        self.boundary.block_near(&mut blocked.cells, cells);
        Ok(Occupancy::new(blocked, self.start_cell))
    }

    /// The cells part `part` blocks beyond the inflated base map at the state of the last
    /// forward kinematics: its footprint inflated by the robot radius (with the cells near
    /// the freed boundary cells, which block those).
    pub(super) fn part_blocks(&self, data: &SceneData, part: PartId) -> Result<Vec<u32>, Error> {
        let fp = part_footprint(self.model, data, part)?;
        let cells = set_cells(fp.cells());
        let (w, h) = (self.base_blocked.width(), self.base_blocked.height());
        let base = self.base_blocked.cells();
        Ok(self
            .disc
            .inflate(w, h, &cells)
            .cells()
            .filter(|&c| !base[c] || self.boundary.near(c))
            .map(|c| c as u32)
            .collect())
    }

    /// The joints whose values can change the occupancy of a lattice state: every joint that
    /// places (is the joint of, or an ancestor of) a part that blocks cells beyond the
    /// inflated base map at some combination of its placing joints' lattice values (the
    /// other joints as in `key`; a part's footprint depends only on those). A part with more
    /// than [`MAX_FLOOR_COMBINATIONS`] combinations is counted without looking
    /// (conservative). With `first`, stops after the first part found.
    pub fn floor_joints(
        &self,
        data: &mut SceneData,
        key: &[u16],
        first: bool,
    ) -> Result<Vec<bool>, Error> {
        let mut floor = vec![false; self.model.nq()];
        for p in self.model.parts() {
            let placing = &self.pose_context[p.id().index()];
            let sizes: Vec<usize> = placing
                .iter()
                .map(|j| self.lattice.values(*j).len())
                .collect();
            let combinations = sizes
                .iter()
                .try_fold(1usize, |n, s| n.checked_mul(*s))
                .filter(|n| *n <= MAX_FLOOR_COMBINATIONS);
            let blocks = match combinations {
                None => true,
                Some(n) => {
                    let mut any = false;
                    let mut at = key.to_vec();
                    for mut c in 0..n {
                        for (j, s) in placing.iter().zip(&sizes) {
                            at[j.index()] = (c % s) as u16;
                            c /= s;
                        }
                        forward_kinematics(self.model, data, &self.state_of(&at))?;
                        if !self.part_blocks(data, p.id())?.is_empty() {
                            any = true;
                            break;
                        }
                    }
                    any
                }
            };
            if blocks {
                for j in placing {
                    floor[j.index()] = true;
                }
                if first {
                    break;
                }
            }
        }
        Ok(floor)
    }

    /// Occupancy of a lattice state from the per-part footprints cached by pose (equal to
    /// [`Checker::occupancy_of`] with every part).
    fn assembled_occupancy(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<Occupancy, Error> {
        let mut blocked = Blocked::from_grid(&self.base_blocked);
        let mut posed = false;
        for p in self.model.parts() {
            if !include(p.id()) {
                continue;
            }
            let cells = self.cached_blocks(caches, data, key, p.id(), &mut posed)?;
            for &c in cells.iter() {
                blocked.cells[c as usize] = true;
            }
            let near = cells.iter().map(|c| *c as usize);
            self.boundary.block_near(&mut blocked.cells, near);
        }
        Ok(Occupancy::new(blocked, self.start_cell))
    }

    /// [`Checker::part_blocks`] of `part` at lattice state `key`, cached by the part's pose.
    /// `posed`: whether `data` already holds the forward kinematics of `key` (set when this
    /// call computes it).
    pub(super) fn cached_blocks(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        part: PartId,
        posed: &mut bool,
    ) -> Result<Arc<Vec<u32>>, Error> {
        let k = part.index();
        let fkey = (k, Self::values_of(key, &self.pose_context[k]));
        if let Some(c) = caches.footprints.get(&fkey) {
            return Ok(c.clone());
        }
        if !*posed {
            forward_kinematics(self.model, data, &self.state_of(key))?;
            *posed = true;
        }
        let c = Arc::new(self.part_blocks(data, part)?);
        bounded_to(&mut caches.footprints, 4 * CACHE_LIMIT);
        caches.footprints.insert(fkey, c.clone());
        Ok(c)
    }

    pub(super) fn cached_occupancy(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
    ) -> Result<Arc<Occupancy>, Error> {
        if let Some(o) = caches.occupancy.get(key) {
            return Ok(o.clone());
        }
        let o = Arc::new(if caches.per_part {
            self.assembled_occupancy(caches, data, key, &|_| true)?
        } else {
            self.occupancy_of(data, &self.state_of(key), true, &|_| true)?
        });
        bounded_to(&mut caches.occupancy, OCCUPANCY_LIMIT);
        caches.occupancy.insert(key.to_vec(), o.clone());
        Ok(o)
    }

    /// Occupancy of lattice state `key` with only the parts `include` accepts (not cached
    /// as a whole; per-part footprints are when `caches.per_part`).
    pub(super) fn filtered_occupancy(
        &self,
        caches: &mut Caches,
        data: &mut SceneData,
        key: &[u16],
        include: &dyn Fn(PartId) -> bool,
    ) -> Result<Occupancy, Error> {
        if caches.per_part {
            self.assembled_occupancy(caches, data, key, include)
        } else {
            self.occupancy_of(data, &self.state_of(key), false, include)
        }
    }
}
