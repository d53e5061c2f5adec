//! Sampling: one module that produces point sets over the unit square and disk, and the
//! counter-based randomness behind them. Every distribution effect maps these points onto its
//! own area: the pixel footprint (anti-aliasing), an area light (soft shadows), a cone around
//! the mirror or refracted direction (glossy and blurry surfaces) and the lens (depth of field).
//! Adaptive supersampling refines pixels by recursive corner subdivision, or takes batches of
//! samples until a pixel's estimated noise is below a target ([`noise`]).

pub mod adaptive;
pub mod dims;
pub mod noise;
pub mod pattern;
pub mod rng;
pub mod sobol;
pub mod warp;

pub use adaptive::{refine_pixel, AdaptiveSettings, AdaptiveStats, LatticePoint, PointSample};
pub use noise::NoiseSettings;
pub use pattern::{disk_point, sample_square, square_point, square_points, strata};
pub use rng::{hash, permute, uniform, uniform2, SampleKey, SampleStream};

use serde::Deserialize;

/// How `n` points are placed over the unit square (and, through the concentric map, the disk).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize)]
pub enum Pattern {
    /// Stratum centres of an `nx × ny` grid: regular, no randomness.
    Grid,
    /// Independent uniform points.
    Random,
    /// One uniform point in each stratum of an `nx × ny` grid (stratified sampling).
    #[default]
    Jittered,
}

/// Pixel reconstruction filter of anti-aliasing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize)]
pub enum Filter {
    /// Samples spread uniformly over the pixel footprint, equal weights.
    #[default]
    Box,
    /// Samples spread over a two-pixel-wide footprint with tent-shaped density, equal weights.
    Tent,
}
