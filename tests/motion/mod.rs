//! Motion layer: OMPL paths, timing, base placement.

mod paths;
mod placement;
mod timing;
mod whole_body;
