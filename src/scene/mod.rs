//! Scene files: the RON format, its validation with file positions, and loading.
pub mod format;
pub mod locate;
