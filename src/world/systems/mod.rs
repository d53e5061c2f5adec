//! The frame's systems, one file each: bounds, grid, snapshot.

pub mod bounds;
pub mod grid;
pub mod snapshot;

pub use bounds::update_bounds;
pub use grid::{grid_needs_rebuild, rebuild_grid};
pub use snapshot::build_snapshot;
