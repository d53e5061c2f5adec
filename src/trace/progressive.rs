//! Noise-driven adaptive sampling over the image: rounds of batches, each pixel's error
//! estimated from its own batches, decisions spread to neighbours between rounds (see
//! [`crate::sample::noise`]).

use std::time::Instant;

use rayon::prelude::*;

use super::camera_samples::{trace_camera_ray, CameraSampler};
use super::finite::DropTally;
use super::packet::LANES;
use super::packet_tile::{camera_packets, lens_packets, shade_packet, BLOCK};
use super::stats::{NoiseStats, NoiseStop, RayCounts};
use super::tiles::{assemble, saturate, Assembled, TileResult, TILE};
use crate::math::{RayPacket, Vec3};
use crate::sample::noise::{next_batches, pooled, spread, NoiseSettings, PixelEstimate};
use crate::simd::SimdLevel;
use crate::store::PrimitiveStore;
use crate::trace::{RenderSettings, TraceScene};

/// One pixel's samples so far.
#[derive(Debug, Clone, Copy, Default)]
struct PixelState {
    /// Each replicate's count and sum of finite samples, in `f64` (a pixel may take tens of
    /// thousands).
    estimate: PixelEstimate,
    /// Non-finite samples, left out.
    dropped: u32,
    /// Batches traced, and the batches this round brings it to.
    batches: u32,
    goal: u32,
    /// Rays traced for the pixel (the cost AOV).
    rays: u64,
}

impl PixelState {
    fn colour(&self) -> Vec3 {
        self.estimate.mean().as_vec3().min(Vec3::splat(f32::MAX))
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

    // Pinhole blocks take one sample of each pixel in turn; a lens camera's packets take each
    // pixel's samples together.
    let packets = camera_packets(scene, settings, want_cost)
        .map(|level| (level, false))
        .or_else(|| lens_packets(scene, settings, want_cost).map(|level| (level, true)));
    let mut rounds = 0;
    let mut errors = vec![0.0f64; w as usize * h as usize];
    let stopped_by = loop {
        let round_started = Instant::now();
        let traced: u64 = tiles
            .par_iter_mut()
            .map(|tile| {
                // Strips of a tile in parallel too: in late rounds a few tiles hold all the
                // pending work.
                let [x0, y0, x1, y1] = tile.area;
                let (samples, rays) = tile
                    .pixels
                    .par_chunks_mut((STRIP * (x1 - x0)) as usize)
                    .enumerate()
                    .map(|(i, pixels)| {
                        let top = y0 + i as u32 * STRIP;
                        let strip = [x0, top, x1, (top + STRIP).min(y1)];
                        let mut rays = RayCounts::default();
                        let samples = crate::simd::with_single_ray_level(settings.simd, || match packets {
                            Some(how) => trace_round_packets(&sampler, how, strip, pixels, &mut rays),
                            None => trace_round(&sampler, strip, pixels, &mut rays),
                        });
                        (samples, rays)
                    })
                    .reduce(
                        || (0, RayCounts::default()),
                        |(a, mut rays), (b, more)| {
                            rays.add(&more);
                            (a + b, rays)
                        },
                    );
                tile.rays.add(&rays);
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
        errors = pooled(&errors, w as usize, h as usize);
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

/// Rows of a tile traced as one task of a round: a block of packets high.
const STRIP: u32 = BLOCK[1];

/// Traces every pixel of the strip `area` (`pixels`, row-major) up to its goal, batch by
/// batch, counting its rays into `rays`; the camera samples traced.
fn trace_round<S: PrimitiveStore>(
    sampler: &CameraSampler<'_, S>,
    area: [u32; 4],
    pixels: &mut [PixelState],
    rays: &mut RayCounts,
) -> u64 {
    let [x0, y0, x1, _] = area;
    let tw = x1 - x0;
    let mut samples = 0;
    for (k, p) in pixels.iter_mut().enumerate() {
        let (x, y) = (x0 + k as u32 % tw, y0 + k as u32 / tw);
        let before = rays.total();
        while p.batches < p.goal {
            for i in 0..sampler.n {
                let (ray, camera, time) = sampler.sample_in(x, y, p.batches, i, rays);
                let c = trace_camera_ray(sampler.scene, sampler.settings, &ray, camera, time, rays);
                let replicate = camera.progressive.map_or(0, |r| r.replicate);
                p.estimate.add(replicate, c);
                p.dropped += u32::from(!c.is_finite());
            }
            p.batches += 1;
            samples += u64::from(sampler.n);
        }
        p.rays += rays.total() - before;
    }
    samples
}

/// [`trace_round`] with camera rays in packets: each block of [`BLOCK`] pixels of the strip sends its pending
/// samples as packets of [`LANES`], filled by taking one sample of each pixel in turn, in the
/// order of each pixel's samples; for a lens camera (`by_pixel`), all of one pixel's pending
/// samples before the next pixel's (they converge on the pixel's footprint in the plane in
/// focus, as [`super::packet_tile::lens_tile`]'s do). Every pixel thus adds its samples in the same order as
/// [`trace_round`], from the same radiance: the same sums, the same bits. Rays are counted for
/// the strip only (the cost AOV traces single rays).
fn trace_round_packets<S: PrimitiveStore>(
    sampler: &CameraSampler<'_, S>,
    (level, by_pixel): (SimdLevel, bool),
    area: [u32; 4],
    pixels: &mut [PixelState],
    rays: &mut RayCounts,
) -> u64 {
    let [x0, y0, x1, y1] = area;
    let (tw, n) = (x1 - x0, sampler.n);
    let mut samples = 0;
    for by in (y0..y1).step_by(BLOCK[1] as usize) {
        for bx in (x0..x1).step_by(BLOCK[0] as usize) {
            // The block's pixels: position, index in the tile, next sample and end (counted
            // over the pixel's batches).
            let mut pending: Vec<(u32, u32, usize, u32, u32)> = (0..BLOCK[0] * BLOCK[1])
                .filter_map(|i| {
                    let (x, y) = (bx + i % BLOCK[0], by + i / BLOCK[0]);
                    let k = ((y - y0) * tw + x - x0) as usize;
                    let p = pixels.get(k).filter(|_| x < x1 && y < y1)?;
                    (p.goal > p.batches).then_some((x, y, k, p.batches * n, p.goal * n))
                })
                .collect();
            while !pending.is_empty() {
                let mut owners = [usize::MAX; LANES];
                let mut packet = RayPacket::<LANES>::default();
                let mut cameras = [None; LANES];
                let mut filled = 0;
                'fill: loop {
                    let mut took = false;
                    for (x, y, k, next, end) in pending.iter_mut() {
                        while *next < *end {
                            let (ray, camera, _) = sampler.sample_in(*x, *y, *next / n, *next % n, rays);
                            packet.set(filled, &ray, 0.0, f32::INFINITY);
                            (cameras[filled], owners[filled]) = (Some(camera), *k);
                            (*next, filled, took) = (*next + 1, filled + 1, true);
                            if filled == LANES {
                                break 'fill;
                            }
                            if !by_pixel {
                                break;
                            }
                        }
                    }
                    if !took {
                        break;
                    }
                }
                let colours = shade_packet((sampler.scene, sampler.settings), level, &packet, &cameras, rays);
                for (lane, colour) in colours.into_iter().enumerate() {
                    let (Some(c), Some(camera)) = (colour, cameras[lane]) else { continue };
                    let p = &mut pixels[owners[lane]];
                    p.estimate.add(camera.progressive.map_or(0, |r| r.replicate), c);
                    p.dropped += u32::from(!c.is_finite());
                }
                samples += filled as u64;
                pending.retain(|&(.., next, end)| next < end);
            }
        }
    }
    for p in pixels.iter_mut() {
        p.batches = p.batches.max(p.goal);
    }
    samples
}
