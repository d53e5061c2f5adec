//! Noise-driven adaptive sampling over the image: rounds of batches, each pixel's error
//! estimated from its own batches, decisions spread to neighbours between rounds (see
//! [`crate::sample::noise`]).

use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;

use super::camera_samples::{trace_camera_ray, CameraSampler};
use super::finite::{DropTally, SampleMean};
use super::stats::{NoiseStats, NoiseStop, RayCounts};
use super::tiles::{assemble, saturate, Assembled, TileResult, TILE};
use crate::math::Vec3;
use crate::sample::noise::{next_batches, spread, NoiseSettings, PixelEstimate};
use crate::store::PrimitiveStore;
use crate::trace::{RenderSettings, TraceScene};

/// One pixel's samples so far.
#[derive(Debug, Clone, Copy, Default)]
struct PixelState {
    /// Sum of every kept sample, in `f64` (a pixel may take tens of thousands).
    sum: DVec3,
    kept: u32,
    dropped: u32,
    /// The batch means' sums.
    estimate: PixelEstimate,
    /// Batches traced, and the batches this round brings it to.
    batches: u32,
    goal: u32,
    /// Rays traced for the pixel (the cost AOV).
    rays: u64,
}

impl PixelState {
    fn colour(&self) -> Vec3 {
        match self.kept {
            0 => Vec3::ZERO,
            n => (self.sum / f64::from(n)).as_vec3().min(Vec3::splat(f32::MAX)),
        }
    }
}

/// A tile's pixels (row-major) and the rays its workers traced.
struct TileState {
    area: [u32; 4],
    pixels: Vec<PixelState>,
    rays: RayCounts,
}

/// Renders with noise-driven adaptive sampling: round 0 gives every pixel
/// `noise.min_batches`; each later round gives more to the pixels whose estimated display
/// error, or a neighbour's, is above the target, until none is, they reach the maximum, or
/// the next round would not fit in the time limit. Tiles run in parallel within a round.
pub(super) fn render_noise<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    noise: &NoiseSettings,
    want_cost: bool,
    tile_done: &(dyn Fn() + Sync),
) -> (Assembled, NoiseStats) {
    let started = Instant::now();
    let sampler = CameraSampler::new(scene, settings);
    let batch = sampler.n;
    let (min_batches, max_batches) = (noise.min_batches(batch), noise.max_batches(batch));
    let target = f64::from(noise.target_error);
    let (w, h) = (settings.width, settings.height);
    let tiles_x = w.div_ceil(TILE);
    let mut tiles: Vec<TileState> = (0..tiles_x * h.div_ceil(TILE))
        .map(|tile| {
            let (x0, y0) = (tile % tiles_x * TILE, tile / tiles_x * TILE);
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            let start = PixelState { goal: min_batches, ..PixelState::default() };
            TileState {
                area: [x0, y0, x1, y1],
                pixels: vec![start; ((x1 - x0) * (y1 - y0)) as usize],
                rays: RayCounts::default(),
            }
        })
        .collect();

    let mut rounds = 0;
    let mut errors = vec![0.0f64; w as usize * h as usize];
    let stopped_by = loop {
        let round_started = Instant::now();
        let traced: u64 = tiles
            .par_iter_mut()
            .map(|tile| {
                let samples =
                    crate::simd::with_single_ray_level(settings.simd, || trace_round(&sampler, tile));
                if rounds == 0 {
                    tile_done();
                }
                samples
            })
            .sum();
        rounds += 1;
        let round_seconds = round_started.elapsed().as_secs_f64();

        for tile in &tiles {
            let [x0, y0, x1, _] = tile.area;
            let tw = x1 - x0;
            for (k, p) in tile.pixels.iter().enumerate() {
                let (x, y) = (x0 + k as u32 % tw, y0 + k as u32 / tw);
                errors[(y * w + x) as usize] = p.estimate.display_error();
            }
        }
        let active = spread(&errors, w as usize, h as usize, target);
        let mut wanted = 0u64;
        for tile in &mut tiles {
            let [x0, y0, x1, _] = tile.area;
            let tw = x1 - x0;
            for (k, p) in tile.pixels.iter_mut().enumerate() {
                let (x, y) = (x0 + k as u32 % tw, y0 + k as u32 / tw);
                if let Some(error) = active[(y * w + x) as usize] {
                    p.goal = next_batches(p.batches, error, target, max_batches);
                    wanted += u64::from(p.goal - p.batches);
                }
            }
        }
        if wanted == 0 {
            break match errors.iter().all(|&e| e <= target) {
                true => NoiseStop::Target,
                false => NoiseStop::MaxSamples,
            };
        }
        if noise.rounds.is_some_and(|r| rounds >= r) {
            break NoiseStop::Rounds;
        }
        if let Some(limit) = noise.time_limit {
            // The next round's time, at this round's seconds per camera sample.
            let per_sample = round_seconds / traced.max(1) as f64;
            let next = per_sample * (wanted * u64::from(batch)) as f64;
            if started.elapsed().as_secs_f64() + next > f64::from(limit) {
                break NoiseStop::TimeLimit;
            }
        }
    };

    let mut counts: Vec<u32> = Vec::with_capacity(errors.len());
    let results: Vec<TileResult> = tiles
        .iter()
        .map(|tile| {
            let [x0, y0, x1, _] = tile.area;
            let tw = x1 - x0;
            let mut dropped = DropTally::default();
            for (k, p) in tile.pixels.iter().enumerate() {
                dropped.record((y0 + k as u32 / tw) * w + x0 + k as u32 % tw, p.dropped);
                counts.push(p.batches * batch);
            }
            let colours = tile.pixels.iter().map(PixelState::colour).collect();
            let costs = match want_cost {
                true => tile.pixels.iter().map(|p| saturate(p.rays)).collect(),
                false => Vec::new(),
            };
            (colours, costs, tile.rays, dropped)
        })
        .collect();
    let image = assemble(settings, &results, want_cost);

    let pixels = tiles.iter().flat_map(|t| &t.pixels);
    let variance: f64 = pixels.clone().map(|p| p.estimate.variance_of_mean().element_sum()).sum();
    counts.sort_unstable();
    let n = counts.len().max(1);
    let stats = NoiseStats {
        rounds,
        batch,
        samples_mean: counts.iter().map(|&c| f64::from(c)).sum::<f64>() / n as f64,
        samples_p99: counts.get((n * 99).div_ceil(100).saturating_sub(1)).copied().unwrap_or(0),
        samples_min: counts.first().copied().unwrap_or(0),
        samples_max: counts.last().copied().unwrap_or(0),
        estimated_rmse: (variance / (3 * n) as f64).sqrt(),
        mean_display_error: errors.iter().sum::<f64>() / n as f64,
        pixels_above_target: errors.iter().filter(|&&e| e > target).count() as u64,
        stopped_by,
        seconds: started.elapsed().as_secs_f64(),
    };
    (image, stats)
}

/// Traces every pixel of `tile` up to its goal, batch by batch; the camera samples traced.
fn trace_round<S: PrimitiveStore>(sampler: &CameraSampler<'_, S>, tile: &mut TileState) -> u64 {
    let [x0, y0, x1, _] = tile.area;
    let tw = x1 - x0;
    let mut samples = 0;
    for (k, p) in tile.pixels.iter_mut().enumerate() {
        let (x, y) = (x0 + k as u32 % tw, y0 + k as u32 / tw);
        let before = tile.rays.total();
        while p.batches < p.goal {
            let mut mean = SampleMean::default();
            for i in 0..sampler.n {
                let (ray, camera, time) = sampler.sample_in(x, y, p.batches, i, &mut tile.rays);
                let c = trace_camera_ray(sampler.scene, sampler.settings, &ray, camera, time, &mut tile.rays);
                mean.add(c);
                if c.is_finite() {
                    p.sum += c.as_dvec3();
                    p.kept += 1;
                } else {
                    p.dropped += 1;
                }
            }
            p.estimate.add(if mean.kept() > 0 { mean.mean() } else { Vec3::NAN });
            p.batches += 1;
            samples += u64::from(sampler.n);
        }
        p.rays += tile.rays.total() - before;
    }
    samples
}
