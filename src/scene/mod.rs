//! Scene files: the RON format, its validation with file positions, and loading.
pub mod format;
