//! Noise-driven adaptive sampling: a pixel takes its camera samples in batches, each batch one
//! whole stratified set (the `aa × lens × time` samples a fixed render would take, with their
//! own share of every effect's budget), until the standard error of its mean, seen on the
//! display, falls below a target.
//!
//! Batches are independent stratified estimates of the pixel, so the spread of their means
//! gives an unbiased estimate of the variance of the pixel's mean (the "two interleaved half
//! sets" estimate generalised to `B` sets). [`PixelEstimate`] keeps the sums it needs, in `f64`.
//!
//! The error a viewer sees is the error after the display encoding: the standard error of each
//! channel times the slope of the sRGB curve at the pixel's value ([`srgb_slope`]), so a dark
//! pixel needs a smaller linear error than a bright one, and a pixel clipped to white needs
//! little. The target is in display units (`0.01` ≈ 2.5/255).
//!
//! Rendering proceeds in rounds over the whole image. Round 0 gives every pixel
//! [`NoiseSettings::min_batches`]; after each round, a pixel whose estimate, or any of whose
//! eight neighbours' estimate, is above the target takes more ([`next_batches`]), up to
//! [`NoiseSettings::max_batches`]. Every decision depends only on the samples' values, which are
//! pure functions of (seed, pixel, batch, sample): the image is the same bits for any thread
//! count, tile order or shard.

use glam::{DVec3, Vec3};

/// Settings of noise-driven adaptive sampling: the scene file's `settings.noise` (every pixel
/// takes batches of the scene's `aa` set, with lens and time samples, in rounds until its
/// estimated error on the display is below `target_error`; not together with `adaptive`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct NoiseSettings {
    /// A pixel stops when the standard error of its mean, on the display (sRGB, 0..1; 0.01 is
    /// about 2.5/255), is at most this; finite, in [0, 1]. 0 samples every pixel to
    /// `max_samples` (or the time limit). Default 0.01.
    pub target_error: f32,
    /// Camera samples every pixel takes first, 1..=65536 (rounded up to whole batches, at
    /// least two). Default 16.
    pub min_samples: u32,
    /// Camera samples no pixel exceeds, `min_samples..=65536` (rounded up to whole batches).
    /// Default 1024.
    pub max_samples: u32,
    /// Stop after the last round that fits in this many seconds of tracing (the image is
    /// always complete), finite and > 0; `None`: no limit. Default none.
    pub time_limit: Option<f32>,
    /// Stop after this many rounds (round 0 included), at least 1; `None`: no limit. Default
    /// none. A render stopped by its time limit records the rounds it ran here (and no time
    /// limit) in its provenance, so that it renders again exactly on any machine.
    pub rounds: Option<u32>,
}

impl Default for NoiseSettings {
    fn default() -> Self {
        Self { target_error: 0.01, min_samples: 16, max_samples: 1024, time_limit: None, rounds: None }
    }
}

impl NoiseSettings {
    /// Batches every pixel takes in round 0: `min_samples` in batches of `batch` camera
    /// samples, rounded up, and at least two (one batch has no spread to estimate from).
    pub fn min_batches(&self, batch: u32) -> u32 {
        self.min_samples.div_ceil(batch.max(1)).max(2)
    }

    /// Most batches a pixel takes: `max_samples` in batches, rounded up, and at least
    /// [`Self::min_batches`].
    pub fn max_batches(&self, batch: u32) -> u32 {
        self.max_samples.div_ceil(batch.max(1)).max(self.min_batches(batch))
    }
}

/// The slope of the sRGB encoding at linear value `v` clamped to `[0, 1]`: how much a small
/// linear error moves the displayed value (12.92 in the linear toe, about 0.42 at white).
pub fn srgb_slope(v: f64) -> f64 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92
    } else {
        1.055 / 2.4 * v.powf(1.0 / 2.4 - 1.0)
    }
}

/// What a pixel's error estimate needs from its batches: their count and the sums of their
/// means and squared means, per channel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PixelEstimate {
    batches: u32,
    sum: DVec3,
    squares: DVec3,
}

impl PixelEstimate {
    /// Adds one batch's mean (a non-finite mean, from a batch that kept no sample, is left out).
    pub fn add(&mut self, mean: Vec3) {
        if mean.is_finite() {
            let m = mean.as_dvec3();
            self.batches += 1;
            self.sum += m;
            self.squares += m * m;
        }
    }

    /// Batches counted.
    pub fn batches(&self) -> u32 {
        self.batches
    }

    /// The variance of the pixel's mean per channel, in linear units squared: the batch means'
    /// sample variance over the batch count; infinite with fewer than two batches.
    pub fn variance_of_mean(&self) -> DVec3 {
        if self.batches < 2 {
            return DVec3::INFINITY;
        }
        let b = f64::from(self.batches);
        let spread = (self.squares - self.sum * self.sum / b).max(DVec3::ZERO);
        spread / (b - 1.0) / b
    }

    /// The estimated display error: the largest channel's standard error times the sRGB slope
    /// at that channel's mean. Infinite with fewer than two batches.
    pub fn display_error(&self) -> f64 {
        if self.batches < 2 {
            return f64::INFINITY;
        }
        let mean = self.sum / f64::from(self.batches);
        let sd = self.variance_of_mean().to_array().map(f64::sqrt);
        (0..3).map(|c| sd[c] * srgb_slope(mean[c])).fold(0.0, f64::max)
    }
}

/// The batches a pixel with `batches` takes next round, given its `error` (or, for a pixel
/// kept going by a neighbour, the neighbourhood's largest) against `target`: enough to bring
/// the error to the target if it falls as `1/√n`, at least one more and at most double, capped
/// at `max`. With a target of 0, double.
pub fn next_batches(batches: u32, error: f64, target: f64, max: u32) -> u32 {
    let wanted = if target > 0.0 && error.is_finite() {
        let ratio = error / target;
        (f64::from(batches) * ratio * ratio).ceil().min(f64::from(u32::MAX)) as u32
    } else {
        batches.saturating_mul(2)
    };
    wanted.clamp(batches + 1, batches.saturating_mul(2)).min(max).max(batches)
}

/// The pixels of a `width × height` image whose own error, or a neighbour's (8-connected), is
/// above `target`, each with the largest such error around it; `None` for a pixel at rest.
pub fn spread(errors: &[f64], width: usize, height: usize, target: f64) -> Vec<Option<f64>> {
    debug_assert_eq!(errors.len(), width * height);
    let mut out = vec![None; errors.len()];
    for y in 0..height {
        for x in 0..width {
            let mut worst: Option<f64> = None;
            for ny in y.saturating_sub(1)..(y + 2).min(height) {
                for nx in x.saturating_sub(1)..(x + 2).min(width) {
                    let e = errors[ny * width + nx];
                    if e > target && worst.is_none_or(|w| e > w) {
                        worst = Some(e);
                    }
                }
            }
            out[y * width + x] = worst;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batch_counts_round_up_and_keep_two_for_an_estimate() {
        let s = NoiseSettings { min_samples: 16, max_samples: 100, ..NoiseSettings::default() };
        assert_eq!((s.min_batches(4), s.max_batches(4)), (4, 25));
        assert_eq!((s.min_batches(64), s.max_batches(64)), (2, 2), "one batch has no spread");
        assert_eq!((s.min_batches(5), s.max_batches(5)), (4, 20));
        let tiny = NoiseSettings { min_samples: 1, max_samples: 1, ..s };
        assert_eq!((tiny.min_batches(1), tiny.max_batches(1)), (2, 2));
    }

    #[test]
    fn the_estimate_is_the_variance_of_the_mean_of_the_batch_means() {
        let mut e = PixelEstimate::default();
        assert_eq!(e.display_error(), f64::INFINITY);
        for m in [0.2f32, 0.4, 0.3, 0.5] {
            e.add(Vec3::new(m, 0.3, 0.3));
        }
        e.add(Vec3::NAN);
        assert_eq!(e.batches(), 4);
        // Sample variance of (0.2, 0.4, 0.3, 0.5) is 1/60; over 4 batches, 1/240.
        let v = e.variance_of_mean();
        assert!((v.x - 1.0 / 240.0).abs() < 1e-9 && v.y.abs() < 1e-15, "{v}");
        let expected = (1.0f64 / 240.0).sqrt() * srgb_slope(0.35);
        assert!((e.display_error() / expected - 1.0).abs() < 1e-6);
    }

    #[test]
    fn display_error_weighs_dark_pixels_more() {
        assert_eq!(srgb_slope(0.0), 12.92);
        assert_eq!(srgb_slope(-3.0), 12.92);
        assert!((srgb_slope(1.0) - 1.055 / 2.4).abs() < 1e-12);
        assert_eq!(srgb_slope(7.0), srgb_slope(1.0), "clipped to white");
        assert!(srgb_slope(0.01) > 3.0 * srgb_slope(0.5));
        // Continuous where the toe meets the curve, within a few per cent.
        assert!((srgb_slope(0.003_130_9) / 12.92 - 1.0).abs() < 0.03);
    }

    #[test]
    fn rounds_grow_towards_the_target_by_at_most_double() {
        assert_eq!(next_batches(4, 0.02, 0.01, 100), 8, "4× the variance wanted: capped at double");
        assert_eq!(next_batches(4, 0.011, 0.01, 100), 5, "just above: one more at least");
        assert_eq!(next_batches(10, 0.0125, 0.01, 100), 16);
        assert_eq!(next_batches(64, 1.0, 0.01, 100), 100, "capped at the maximum");
        assert_eq!(next_batches(4, 0.5, 0.0, 100), 8, "no target: double");
        assert_eq!(next_batches(100, 0.5, 0.01, 100), 100, "at the maximum: no more");
    }

    #[test]
    fn noise_spreads_to_the_eight_neighbours_only() {
        let mut errors = vec![0.0; 5 * 4];
        errors[5 + 1] = 0.5;
        errors[3 * 5 + 4] = 0.2;
        let s = spread(&errors, 5, 4, 0.1);
        let active: Vec<usize> = (0..20).filter(|&i| s[i].is_some()).collect();
        assert_eq!(active, [0, 1, 2, 5, 6, 7, 10, 11, 12, 13, 14, 18, 19]);
        assert_eq!(s[12], Some(0.5), "the worst neighbour's error");
        assert_eq!(s[13], Some(0.2));
        assert_eq!(spread(&errors, 5, 4, 0.6), vec![None; 20], "all under the target");
    }
}
