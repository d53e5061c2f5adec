//! Scene files: the RON format, its validation with file positions, and loading.
pub mod format;
pub mod spawn;

pub use format::*;
pub use spawn::spawn_world;
