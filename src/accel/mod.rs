//! Acceleration: a uniform voxel grid in compressed rows and its 3D DDA traversal.
//!
//! The grid holds `u32` ids of bounded objects; what an id means is the caller's business
//! (the snapshot maps ids to objects). Layout lives in [`grid`], the parallel build in
//! [`grid_build`], the walk in [`dda`], the nearest-hit and any-hit walks both grid levels
//! share in [`walk`] (their statistics through a [`Tally`]), the
//! packet walk (coherent grid traversal) in [`packet`].

pub mod dda;
pub mod grid;
pub mod grid_build;
pub mod packet;
pub mod tally;
pub mod walk;

pub use dda::{CellSpan, GridWalk};
pub use grid::UniformGrid;
pub use grid_build::{GridBuilder, DEFAULT_LAMBDA, MESH_LAMBDA};
pub use tally::{NoTally, Tally};
