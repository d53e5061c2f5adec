//! Noise-driven adaptive sampling: a pixel takes its camera samples in batches (a batch is
//! the `aa × lens × time` camera samples a fixed render would take, with their share of every
//! effect's budget), until the standard error of its mean, seen on the display, falls below a
//! target.
//!
//! A pixel's samples, counted over all its batches, take four independent replicates in turn,
//! and each replicate draws every dimension (position, lens, time, each area light
//! and glossy cone) from a progressive sequence of its own ([`super::sobol`]): whatever the
//! count a pixel stops at, each replicate's points are stratified over all of its samples, not
//! only within a batch. The spread of the replicates' means gives an unbiased estimate of the
//! variance of the pixel's mean (Blender Cycles compares two interleaved half sets; see
//! [`REPLICATES`] for why four); [`PixelEstimate`] keeps the sums it needs, in `f64`. That
//! estimate has three degrees of freedom per channel, so decisions use it [`pooled`] with the
//! pixel's neighbours'.
//!
//! The error a viewer sees is the error after the display encoding: the standard error of each
//! channel times the slope of the sRGB curve at the pixel's value ([`srgb_slope`]), so a dark
//! pixel needs a smaller linear error than a bright one, and a pixel clipped to white needs
//! little. The target is in display units (`0.01` ≈ 2.5/255).
//!
//! Rendering proceeds in rounds over the whole image. Round 0 gives every pixel
//! [`NoiseSettings::min_batches`]; after each round, a pixel whose pooled estimate, or any of
//! whose eight neighbours' pooled estimate, is above the target takes more ([`next_batches`]),
//! up to [`NoiseSettings::max_batches`]. Every decision depends only on the samples' values,
//! which are pure functions of (seed, pixel, sample): the image is the same bits for any thread
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
    /// Camera samples every pixel takes first, 1..=65536 (rounded up to whole batches, and to
    /// at least one sample per replicate). Default 16.
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
    /// samples, rounded up, and at least one sample per replicate (with fewer there is no
    /// spread to estimate from).
    pub fn min_batches(&self, batch: u32) -> u32 {
        let batch = batch.max(1);
        self.min_samples.max(REPLICATES as u32).div_ceil(batch)
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
        1.055 / 2.4 * libm::pow(v, 1.0 / 2.4 - 1.0)
    }
}

/// What a pixel's error estimate needs: per replicate, the count and sum of its finite samples.
///
/// A pixel's samples take [`REPLICATES`] independent replicates in turn, each stratified on its
/// own ([`crate::sample::sobol`]). The replicates' means are independent unbiased estimates of
/// the pixel, so their spread estimates the variance of the pixel's mean without bias (see
/// [`Self::variance_of_mean`]). Unlike the spread of independent batches, this does not ignore
/// the stratification between a pixel's samples.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PixelEstimate {
    count: [u32; REPLICATES],
    sum: [DVec3; REPLICATES],
}

/// Independent replicates a pixel's samples take in turn. Two are the classic "interleaved
/// half sets"; four give three degrees of freedom per channel, which measured far closer to
/// the true error on edge-dominated images (thin features whose replicates often tie, so two
/// replicates agreeing by chance stop a pixel early), for a little of the stratification.
pub const REPLICATES: usize = 4;

impl PixelEstimate {
    /// Adds a sample of replicate `replicate` (a non-finite sample is left out).
    pub fn add(&mut self, replicate: u32, sample: Vec3) {
        if sample.is_finite() {
            let r = replicate as usize % REPLICATES;
            self.count[r] += 1;
            self.sum[r] += sample.as_dvec3();
        }
    }

    /// Finite samples counted.
    pub fn samples(&self) -> u32 {
        self.count.iter().sum()
    }

    /// The mean of every finite sample (0 with none).
    pub fn mean(&self) -> DVec3 {
        match self.samples() {
            0 => DVec3::ZERO,
            n => self.sum.iter().sum::<DVec3>() / f64::from(n),
        }
    }

    /// The variance of the pixel's mean per channel, in linear units squared; infinite while a
    /// replicate has no sample. With replicate means `mᵣ` of `nᵣ` samples and the pixel's mean
    /// `m` of `N`: `Σ nᵣ (mᵣ − m)² / ((R − 1) N)`, which for two replicates is
    /// `(m₀ − m₁)² n₀n₁ / N²`.
    pub fn variance_of_mean(&self) -> DVec3 {
        if self.count.contains(&0) {
            return DVec3::INFINITY;
        }
        let (n, mean) = (f64::from(self.samples()), self.mean());
        let spread: DVec3 = (0..REPLICATES)
            .map(|r| {
                let d = self.sum[r] / f64::from(self.count[r]) - mean;
                d * d * f64::from(self.count[r])
            })
            .sum();
        spread / ((REPLICATES - 1) as f64 * n)
    }

    /// The estimated display error: the largest channel's standard error times the sRGB slope
    /// at that channel's mean. Infinite while a replicate has no sample.
    pub fn display_error(&self) -> f64 {
        let variance = self.variance_of_mean();
        if !variance.is_finite() {
            return f64::INFINITY;
        }
        let (mean, sd) = (self.mean(), variance.to_array().map(f64::sqrt));
        (0..3).map(|c| sd[c] * srgb_slope(mean[c])).fold(0.0, f64::max)
    }
}

/// Each pixel's display error pooled with its neighbours': the root of the mean of its own
/// squared error and the mean squared error of its 3 × 3 neighbourhood (itself included). One
/// pixel's replicates give few degrees of freedom per channel, a noisy estimate; pooling
/// steadies it while keeping half the weight on the pixel itself. Infinite errors stay infinite.
pub fn pooled(errors: &[f64], width: usize, height: usize) -> Vec<f64> {
    debug_assert_eq!(errors.len(), width * height);
    let mut out = vec![0.0; errors.len()];
    for y in 0..height {
        for x in 0..width {
            let (mut sum, mut count) = (0.0, 0.0);
            for ny in y.saturating_sub(1)..(y + 2).min(height) {
                for nx in x.saturating_sub(1)..(x + 2).min(width) {
                    let e = errors[ny * width + nx];
                    sum += e * e;
                    count += 1.0;
                }
            }
            let own = errors[y * width + x];
            out[y * width + x] = ((own * own + sum / count) / 2.0).sqrt();
        }
    }
    out
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
    use crate::sample::rng::{hash, SampleKey};

    #[test]
    fn batch_counts_round_up_and_keep_a_sample_per_replicate() {
        assert_eq!(REPLICATES, 4, "the counts below are for four replicates");
        let s = NoiseSettings { min_samples: 16, max_samples: 100, ..NoiseSettings::default() };
        assert_eq!((s.min_batches(4), s.max_batches(4)), (4, 25));
        assert_eq!((s.min_batches(64), s.max_batches(64)), (1, 2), "a batch holds every replicate");
        assert_eq!((s.min_batches(5), s.max_batches(5)), (4, 20));
        let tiny = NoiseSettings { min_samples: 1, max_samples: 1, ..s };
        assert_eq!((tiny.min_batches(1), tiny.max_batches(1)), (4, 4), "one sample per replicate");
        assert_eq!((tiny.min_batches(2), tiny.max_batches(2)), (2, 2));
        assert_eq!((tiny.min_batches(4), tiny.max_batches(4)), (1, 1));
    }

    #[test]
    fn the_estimate_is_the_spread_of_the_replicate_means() {
        assert_eq!(REPLICATES, 4, "the values below are for four replicates");
        let mut e = PixelEstimate::default();
        assert_eq!(e.display_error(), f64::INFINITY);
        for (r, m) in [(0, 0.2f32), (1, 0.4), (2, 0.3)] {
            e.add(r, Vec3::new(m, 0.3, 0.3));
        }
        assert_eq!(e.display_error(), f64::INFINITY, "a replicate has no sample");
        e.add(3, Vec3::new(0.5, 0.3, 0.3));
        e.add(0, Vec3::NAN);
        assert_eq!(e.samples(), 4);
        // One sample per replicate: the means' sample variance (0.05 / 3) over 4.
        let v = e.variance_of_mean();
        assert!((v.x - 0.05 / 12.0).abs() < 1e-7 && v.y.abs() < 1e-15, "{v}");
        assert!((e.mean().x - 0.35).abs() < 1e-6);
        let expected = (0.05f64 / 12.0).sqrt() * srgb_slope(0.35);
        assert!((e.display_error() / expected - 1.0).abs() < 1e-5);
        // Unequal counts weigh each replicate by its count: Σ nᵣ(mᵣ − m)² / ((R − 1) N), with
        // means 0.2 (two samples), 0.5, 0.3, 0.3 and m = 0.3: 0.06 / 15.
        let mut u = PixelEstimate::default();
        for (r, m) in [(0, 0.2f32), (0, 0.2), (1, 0.5), (2, 0.3), (3, 0.3)] {
            u.add(r, Vec3::splat(m));
        }
        assert!((u.variance_of_mean().x - 0.06 / 15.0).abs() < 1e-7);
    }

    #[test]
    fn the_estimate_is_unbiased_for_independent_replicates() {
        // Pixels whose samples are 0 or 1 with probability ½: the variance of the mean of n is
        // 1/(4n). The average estimate over many pixels must agree within a few per cent.
        let n = 16u32;
        let pixels = 20_000u32;
        let mut total = 0.0;
        for p in 0..pixels {
            let mut e = PixelEstimate::default();
            for j in 0..n {
                let bit = hash(&SampleKey { pixel: p, ..SampleKey::default() }, 0, j) >> 63;
                e.add(j % REPLICATES as u32, Vec3::splat(bit as f32));
            }
            total += e.variance_of_mean().x;
        }
        let (mean, truth) = (total / f64::from(pixels), 1.0 / (4.0 * f64::from(n)));
        assert!((mean / truth - 1.0).abs() < 0.05, "estimated {mean}, true {truth}");
    }

    #[test]
    fn pooling_keeps_half_the_weight_on_the_pixel() {
        // One noisy pixel among quiet ones: its pooled error is √((1 + 1/9)/2) of its own, a
        // neighbour's √((0 + 1/6)/2) at an edge of six (the window is clipped to the image).
        let mut errors = vec![0.0; 3 * 3];
        errors[4] = 1.0;
        let p = pooled(&errors, 3, 3);
        assert!((p[4] - ((1.0 + 1.0 / 9.0) / 2.0f64).sqrt()).abs() < 1e-12);
        assert!((p[1] - (1.0 / 6.0 / 2.0f64).sqrt()).abs() < 1e-12);
        assert!((p[0] - (1.0 / 4.0 / 2.0f64).sqrt()).abs() < 1e-12, "a corner's window is 2 × 2");
        let flat = pooled(&[0.3; 12], 4, 3);
        assert!(flat.iter().all(|&e| (e - 0.3).abs() < 1e-12), "a flat field pools to itself");
        errors[0] = f64::INFINITY;
        assert_eq!(pooled(&errors, 3, 3)[4], f64::INFINITY);
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
