//! Every sample dimension the renderer draws, in one table, so no two effects can share one by
//! accident.
//!
//! A random number is keyed by (seed, frame, pixel, sample, dimension) ([`super::rng`]). Two
//! kinds of key are in use:
//!
//! - the **pixel key** (`sample` = [`PIXEL_PATTERNS`] − batch), shared by all of a pixel's
//!   camera samples so their points can be stratified across them: the anti-aliasing positions
//!   ([`PIXEL`]), the lens points ([`LENS`]), the shutter times ([`TIME`]), and, from
//!   [`FIRST_PATH_DIM`] upwards, one dimension per distribution effect a path meets (area
//!   lights, glossy cones), taken in order from the path's stream;
//! - the **camera-sample key** (`sample` = the sample's index), whose stream starts at
//!   [`FIRST_PATH_DIM`] too.
//!
//! Path dimensions count up from [`FIRST_PATH_DIM`] and a path takes a few per bounce, so the
//! fixed pixel-key dimensions sit below it or at the top of the range, where no path reaches.

/// `SampleKey::sample` of the pixel-level patterns of batch 0; batch `b` uses `PIXEL_PATTERNS - b`.
/// Camera samples count up from 0, so the two never meet (the noise rules cap batches).
pub const PIXEL_PATTERNS: u32 = u32::MAX;

/// Pixel key: the anti-aliasing positions.
pub const PIXEL: u32 = 0;

/// Pixel key: the lens points.
pub const LENS: u32 = 1;

/// First dimension of a path's stream; the pixel key's effect patterns are taken from here up.
pub const FIRST_PATH_DIM: u32 = 2;

/// Pixel key: the shutter times (only where something moves). At the top of the range: a path
/// never takes this many dimensions, so times are independent of every effect's points.
pub const TIME: u32 = u32::MAX - 1;

/// Index of a dimension's hash that seeds the permutation of its strata; points themselves use
/// indices `0..n` with `n` at most the camera samples of a pixel (below `u32::MAX`).
pub const PERMUTATION_SEED: u32 = u32::MAX;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fixed_dimensions_are_distinct_and_clear_of_the_path_range() {
        let fixed = [PIXEL, LENS, TIME];
        for (i, a) in fixed.iter().enumerate() {
            for b in &fixed[i + 1..] {
                assert_ne!(a, b);
            }
        }
        // Below the first path dimension, or far above any a path could take (a path takes a
        // few per ray, and the ray budget allows at most 2^24 secondary rays).
        let path_range = FIRST_PATH_DIM..=FIRST_PATH_DIM + (1 << 28);
        for d in fixed {
            assert!(!path_range.contains(&d), "dimension {d} is in the path range");
        }
    }
}
