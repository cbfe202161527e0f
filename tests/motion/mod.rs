//! Motion layer: OMPL paths, timing, base placement.

mod edges;
mod paths;
mod placement;
mod timing;
mod whole_body;
