//! The base map's occupancy grid and the footprints of parts at a state.

use nalgebra::Point2;

use super::grid::NavGrid;
use super::settings::GridBounds;
use super::shadow::shadow;
use crate::scene::base::BaseMap;
use crate::scene::{Error, PartId, SceneData, SceneModel};

/// The grid of the base map: every base shape whose vertical extent overlaps the height band
/// is rasterised (see [`NavGridSettings`](super::NavGridSettings) and [`NavGrid`]).
pub(crate) fn base_grid(base: &BaseMap) -> Result<NavGrid, Error> {
    let s = &base.nav;
    let shadows: Vec<_> = base
        .shapes
        .iter()
        .map(|b| shadow(&b.shape, &b.world_from_shape))
        .collect();
    let bounds = match s.bounds {
        Some(b) => b,
        None => {
            let mut lo = Point2::new(f64::INFINITY, f64::INFINITY);
            let mut hi = Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
            for sh in &shadows {
                for p in &sh.hull {
                    lo = Point2::new(lo.x.min(p.x - sh.radius), lo.y.min(p.y - sh.radius));
                    hi = Point2::new(hi.x.max(p.x + sh.radius), hi.y.max(p.y + sh.radius));
                }
            }
            if shadows.is_empty() {
                (lo, hi) = (Point2::origin(), Point2::origin());
            }
            let pad = nalgebra::Vector2::repeat(s.padding);
            GridBounds {
                min: lo - pad,
                max: hi + pad,
            }
        }
    };
    let cells = |extent: f64| (extent / s.resolution).ceil().max(1.0);
    let (w, h) = (
        cells(bounds.max.x - bounds.min.x),
        cells(bounds.max.y - bounds.min.y),
    );
    if w * h > super::MAX_GRID_CELLS as f64 {
        return Err(Error::GridTooLarge {
            cells: (w * h).min(u64::MAX as f64) as u64,
            max: super::MAX_GRID_CELLS,
        });
    }
    let mut grid = NavGrid::new(bounds.min, s.resolution, w as usize, h as usize)?;
    for sh in shadows.iter().filter(|sh| s.in_band(sh.z_min, sh.z_max)) {
        grid.rasterize(sh);
    }
    Ok(grid)
}

/// The shadows of the base shapes whose vertical extent overlaps the height band: what
/// [`base_grid`] rasterises.
pub(crate) fn base_shadows(model: &SceneModel) -> Vec<super::shadow::Shadow> {
    let nav = &model.base.nav;
    model
        .base
        .shapes
        .iter()
        .map(|b| shadow(&b.shape, &b.world_from_shape))
        .filter(|sh| nav.in_band(sh.z_min, sh.z_max))
        .collect()
}

fn rasterize_part(model: &SceneModel, data: &SceneData, part: PartId, grid: &mut NavGrid) {
    let nav = &model.base.nav;
    let world_from_part = data.world_from_parts()[part.0];
    for c in &model.parts[part.0].colliders {
        let sh = shadow(&c.shape, &(world_from_part * c.part_from_shape));
        if nav.in_band(sh.z_min, sh.z_max) {
            grid.rasterize(&sh);
        }
    }
}

/// The footprint of one part at the state of the last
/// [`forward_kinematics`](crate::scene::forward_kinematics), on a grid with the geometry of
/// [`SceneModel::base_grid`]. Parts of the footprint outside the grid are dropped.
///
/// # Errors
/// [`Error::UnknownId`] for a foreign id; [`Error::DimensionMismatch`] if `data` is not sized
/// for `model`.
pub fn part_footprint(
    model: &SceneModel,
    data: &SceneData,
    part: PartId,
) -> Result<NavGrid, Error> {
    data.check(model)?;
    model.checked_part(part)?;
    let mut grid = model.base_grid.cleared();
    rasterize_part(model, data, part, &mut grid);
    Ok(grid)
}

/// The footprints of all parts at the state of the last forward kinematics (an open door
/// blocks the cells under it), without the base map.
///
/// # Errors
/// [`Error::DimensionMismatch`] if `data` is not sized for `model`.
pub fn footprint(model: &SceneModel, data: &SceneData) -> Result<NavGrid, Error> {
    data.check(model)?;
    let mut grid = model.base_grid.cleared();
    for part in &model.parts {
        rasterize_part(model, data, part.id, &mut grid);
    }
    Ok(grid)
}

/// The base map's grid with the footprints of all parts at the state of the last forward
/// kinematics: where the robot base may drive at that state.
///
/// # Errors
/// [`Error::DimensionMismatch`] if `data` is not sized for `model`.
pub fn occupancy(model: &SceneModel, data: &SceneData) -> Result<NavGrid, Error> {
    let mut grid = footprint(model, data)?;
    grid.union_with(&model.base_grid)?;
    Ok(grid)
}
