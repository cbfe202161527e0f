//! Motion layer: OMPL paths, timing, base placement.

mod paths;
mod placement;
mod timing;
