//! The finite-film policy: a camera sample whose radiance is not finite (NaN or ±∞) is never
//! written into the image. It is dropped where the pixel accumulates it and counted, and the
//! pixel is the mean of the samples it kept (black when it kept none), as pbrt-v4 warns about
//! and skips NaN radiance.
//!
//! With adaptive supersampling a sample is a corner of a leaf square: a leaf averages its
//! finite corners, a square the sub-squares that kept any, and a lattice point counts once for
//! each leaf that would have averaged it.
//!
//! Counts are kept per pixel and merged by pixel index, so the count and the list of the first
//! pixels affected (the lowest row-major indices, not the first a thread found) are the same
//! for any thread count or tile order. `--stats` reports them, the CLI warns on standard error,
//! and `--strict` turns any dropped sample into a failure with nothing written.

use glam::DVec3;
use serde::Serialize;

use crate::math::Vec3;

/// `c` with every channel above `f32::MAX` (that is, +∞) set to `f32::MAX`; NaN stays NaN, so
/// that it is still caught where the sample is accumulated. Radiance that a legal scene can
/// push past the float range (a light of intensity near `f32::MAX`, many lights or bounces
/// summed) is kept finite with this.
#[inline]
pub fn clamp_radiance(c: Vec3) -> Vec3 {
    let max = Vec3::splat(f32::MAX);
    Vec3::select(c.cmpgt(max), max, c)
}

/// How many of the affected pixels [`DroppedSamples::first`] lists.
pub const FIRST_PIXELS: usize = 8;

/// The running mean of one pixel's camera samples, dropping non-finite ones.
///
/// The mean of finite samples is their `f32` sum divided by their count, bit for bit what a
/// plain mean gives; where that sum overflows (samples near `f32::MAX`), an `f64` sum kept
/// beside it gives the mean instead, which cannot exceed the largest sample.
#[derive(Debug, Clone, Copy, Default)]
pub struct SampleMean {
    sum: Vec3,
    wide: DVec3,
    kept: u32,
    dropped: u32,
}

impl SampleMean {
    /// Accumulates one sample, or drops it when any channel is NaN or infinite.
    #[inline]
    pub fn add(&mut self, c: Vec3) {
        if c.is_finite() {
            self.sum += c;
            self.wide += c.as_dvec3();
            self.kept += 1;
        } else {
            self.dropped += 1;
        }
    }

    /// Samples dropped so far.
    #[inline]
    pub fn dropped(&self) -> u32 {
        self.dropped
    }

    /// Samples kept so far.
    #[inline]
    pub fn kept(&self) -> u32 {
        self.kept
    }

    /// The mean of the samples kept; black when none was.
    #[inline]
    pub fn mean(&self) -> Vec3 {
        if self.kept == 0 {
            return Vec3::ZERO;
        }
        let mean = self.sum / self.kept as f32;
        if mean.is_finite() {
            mean
        } else {
            (self.wide / f64::from(self.kept)).as_vec3().min(Vec3::splat(f32::MAX))
        }
    }
}

/// Dropped samples of a set of pixels (a tile, then the image): counts, and the lowest
/// [`FIRST_PIXELS`] pixel indices affected.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DropTally {
    samples: u64,
    pixels: u64,
    first: Vec<u32>,
}

impl DropTally {
    /// Counts `dropped` samples of pixel `index` (row-major); nothing when `dropped` is 0.
    #[inline]
    pub fn record(&mut self, index: u32, dropped: u32) {
        if dropped == 0 {
            return;
        }
        self.samples += u64::from(dropped);
        self.pixels += 1;
        self.keep_first(index);
    }

    /// Adds another tally (of other pixels); the result does not depend on the order of adding.
    pub fn add(&mut self, other: &DropTally) {
        self.samples += other.samples;
        self.pixels += other.pixels;
        other.first.iter().for_each(|&i| self.keep_first(i));
    }

    fn keep_first(&mut self, index: u32) {
        if let Err(at) = self.first.binary_search(&index) {
            if at < FIRST_PIXELS {
                self.first.insert(at, index);
                self.first.truncate(FIRST_PIXELS);
            }
        }
    }

    /// The figures for an image `width` pixels wide.
    pub fn finish(&self, width: u32) -> DroppedSamples {
        let w = width.max(1);
        DroppedSamples {
            samples: self.samples,
            pixels: self.pixels,
            first: self.first.iter().map(|&i| [i % w, i / w]).collect(),
        }
    }
}

/// Samples dropped from a frame because their radiance was not finite (all zero on a sound
/// render).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct DroppedSamples {
    /// Samples dropped.
    pub samples: u64,
    /// Pixels that dropped at least one sample.
    pub pixels: u64,
    /// The affected pixels with the lowest row-major indices, at most [`FIRST_PIXELS`], as `[x, y]`.
    pub first: Vec<[u32; 2]>,
}

/// A frame that dropped non-finite samples, refused under `--strict`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("--strict: {0}; nothing written")]
pub struct NonFiniteFilm(pub String);

impl DroppedSamples {
    /// The pixels in [`Self::first`] as `(x, y), (x, y)`, with `…` when there are more.
    fn pixel_list(&self) -> String {
        let list: Vec<String> = self.first.iter().map(|[x, y]| format!("({x}, {y})")).collect();
        let more = if self.pixels > self.first.len() as u64 { ", …" } else { "" };
        format!("{}{more}", list.join(", "))
    }

    /// One line saying what was dropped (`None` when nothing was).
    pub fn describe(&self) -> Option<String> {
        (self.samples > 0).then(|| {
            format!(
                "{} non-finite sample{} dropped in {} pixel{} (first {}); each such pixel is the \
                 mean of its finite samples, black if none",
                self.samples,
                if self.samples == 1 { "" } else { "s" },
                self.pixels,
                if self.pixels == 1 { "" } else { "s" },
                self.pixel_list(),
            )
        })
    }

    /// The line of the `--stats` summary.
    pub fn summary_line(&self) -> String {
        match self.samples {
            0 => "non-finite 0 samples dropped".to_string(),
            n => format!(
                "non-finite {n} samples dropped in {} pixels, first {}",
                self.pixels,
                self.pixel_list()
            ),
        }
    }

    /// What the command line does with the frame: `Ok(None)` when nothing was dropped,
    /// `Ok(Some(warning))` for a one-line warning on standard error, and an error (exit 1,
    /// nothing written) under `strict`.
    pub fn verdict(&self, strict: bool) -> Result<Option<String>, NonFiniteFilm> {
        match (self.describe(), strict) {
            (None, _) => Ok(None),
            (Some(line), false) => Ok(Some(format!("warning: {line}"))),
            (Some(line), true) => Err(NonFiniteFilm(line)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nan_sample_is_dropped_and_counted_and_the_pixel_is_the_mean_of_the_rest() {
        let samples = [Vec3::new(0.25, 0.5, 1.0), Vec3::new(f32::NAN, 0.0, 0.0), Vec3::new(0.75, 0.5, 0.0)];
        let mut mean = SampleMean::default();
        samples.iter().for_each(|&c| mean.add(c));
        assert_eq!(mean.dropped(), 1);
        assert_eq!(mean.mean(), Vec3::new(0.5, 0.5, 0.5));
        let mut inf = SampleMean::default();
        [Vec3::splat(f32::INFINITY), Vec3::new(0.0, f32::NEG_INFINITY, 0.0), Vec3::ONE]
            .iter()
            .for_each(|&c| inf.add(c));
        assert_eq!((inf.dropped(), inf.mean()), (2, Vec3::ONE));
    }

    #[test]
    fn a_pixel_that_kept_nothing_is_black_and_an_empty_one_too() {
        let mut mean = SampleMean::default();
        assert_eq!(mean.mean(), Vec3::ZERO);
        mean.add(Vec3::splat(f32::NAN));
        assert_eq!((mean.dropped(), mean.mean()), (1, Vec3::ZERO));
    }

    #[test]
    fn clamping_radiance_caps_infinity_and_keeps_nan_visible() {
        let c = clamp_radiance(Vec3::new(f32::INFINITY, 2.0, f32::NAN));
        assert_eq!(c.x, f32::MAX);
        assert_eq!(c.y, 2.0);
        assert!(c.z.is_nan());
        let ordinary = Vec3::new(0.3, -0.0, 3e38);
        assert_eq!(
            clamp_radiance(ordinary).to_array().map(f32::to_bits),
            ordinary.to_array().map(f32::to_bits)
        );
    }

    #[test]
    fn finite_samples_give_the_bits_of_a_plain_f32_mean() {
        let samples: Vec<Vec3> =
            (0..7).map(|i| Vec3::new(0.1 * i as f32, 1.0 / (i + 1) as f32, -0.0)).collect();
        let mut mean = SampleMean::default();
        samples.iter().for_each(|&c| mean.add(c));
        let plain = samples.iter().fold(Vec3::ZERO, |s, &c| s + c) / samples.len() as f32;
        assert_eq!(mean.mean().to_array().map(f32::to_bits), plain.to_array().map(f32::to_bits));
        assert_eq!(mean.dropped(), 0);
    }

    #[test]
    fn samples_near_the_largest_float_average_without_overflow() {
        let mut mean = SampleMean::default();
        (0..4).for_each(|_| mean.add(Vec3::splat(3e38)));
        assert_eq!(mean.mean(), Vec3::splat(3e38));
        let mut max = SampleMean::default();
        (0..4096).for_each(|_| max.add(Vec3::new(f32::MAX, 0.0, 1.0)));
        assert_eq!(max.mean(), Vec3::new(f32::MAX, 0.0, 1.0));
    }

    #[test]
    fn the_tally_keeps_the_lowest_indices_whatever_the_order_of_recording_and_adding() {
        let pixels: Vec<u32> = (0..40).map(|i| (i * 37 + 11) % 97).collect();
        let mut forward = DropTally::default();
        pixels.iter().for_each(|&p| forward.record(p, 2));
        forward.record(3, 0);
        // Split into "tiles" recorded in reverse and added in another order.
        let mut parts: Vec<DropTally> = pixels
            .chunks(7)
            .map(|c| {
                let mut t = DropTally::default();
                c.iter().rev().for_each(|&p| t.record(p, 2));
                t
            })
            .collect();
        parts.reverse();
        let mut merged = DropTally::default();
        parts.iter().for_each(|t| merged.add(t));
        assert_eq!(forward, merged);
        let mut lowest = pixels.clone();
        lowest.sort_unstable();
        assert_eq!(forward.first, lowest[..FIRST_PIXELS]);
        let figures = forward.finish(10);
        assert_eq!((figures.samples, figures.pixels), (80, 40));
        assert_eq!(figures.first[0], [lowest[0] % 10, lowest[0] / 10]);
    }

    #[test]
    fn warning_summary_and_strict_verdict() {
        let clean = DroppedSamples::default();
        assert_eq!(clean.verdict(true), Ok(None));
        assert_eq!(clean.verdict(false), Ok(None));
        assert_eq!(clean.summary_line(), "non-finite 0 samples dropped");

        let mut tally = DropTally::default();
        tally.record(5, 3);
        tally.record(1, 1);
        let dropped = tally.finish(4);
        let warning = dropped.verdict(false).unwrap().unwrap();
        assert_eq!(
            warning,
            "warning: 4 non-finite samples dropped in 2 pixels (first (1, 0), (1, 1)); each such pixel \
             is the mean of its finite samples, black if none"
        );
        assert!(!warning.contains('\n'));
        let err = dropped.verdict(true).unwrap_err().to_string();
        assert!(
            err.starts_with("--strict: 4 non-finite samples dropped") && err.ends_with("nothing written")
        );
        assert_eq!(dropped.summary_line(), "non-finite 4 samples dropped in 2 pixels, first (1, 0), (1, 1)");

        let mut many = DropTally::default();
        (0..20).for_each(|i| many.record(i, 1));
        let one = many.finish(100);
        assert!(one.describe().unwrap().contains("(7, 0), …)"), "{:?}", one.describe());
        let mut single = DropTally::default();
        single.record(0, 1);
        assert!(single
            .finish(1)
            .describe()
            .unwrap()
            .starts_with("1 non-finite sample dropped in 1 pixel (first (0, 0))"));
    }
}
