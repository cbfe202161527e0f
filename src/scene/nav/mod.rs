//! The 2D navigation grid and the footprints of parts on it.
//!
//! The grid is the vertical projection ("shadow") of the 3D geometry that overlaps the robot's
//! height band, rasterised conservatively (a cell is occupied if its square touches a
//! shadow). The base map's grid is computed once, when the model is built
//! ([`SceneModel::base_grid`](crate::scene::SceneModel::base_grid)); the parts' footprints
//! depend on the state ([`footprint`], [`occupancy`]).

pub(crate) mod footprint;
mod grid;
mod route;
pub(crate) mod search;
mod settings;
pub(crate) mod shadow;

pub(crate) use footprint::base_shadows;
pub use footprint::{footprint, occupancy, part_footprint};
pub use grid::NavGrid;
pub use route::{NoRoute, Route, route};
pub use settings::{GridBounds, MAX_GRID_CELLS, NavGridSettings};
