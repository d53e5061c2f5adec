//! Penumbra: a data-oriented CPU ray tracer.
#![forbid(unsafe_code)]
#![warn(missing_docs)]
pub mod scene;
