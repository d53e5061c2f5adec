//! The parallel renderer: rayon over tiles, one pure function per pixel.
//!
//! A pixel is the mean of `aa.samples × lens.samples` camera samples (lens samples only when
//! the camera has an aperture): sample positions come from the anti-aliasing pattern over the
//! pixel footprint (a box, or a tent two pixels wide), lens points from the lens pattern over
//! the unit disk, stratified across all of the pixel's samples. One sample per pixel goes
//! through the pixel centre. With adaptive supersampling the pixel corners are traced once for
//! the whole image, then each pixel is subdivided where its corners disagree
//! ([`crate::sample::adaptive`]).
//!
//! Every random number is keyed by (seed, frame, pixel, sample, dimension), so the image is
//! bit-identical for any thread count or tile order. A sample whose radiance is not finite is
//! dropped and counted where its pixel accumulates it ([`super::finite`]).

use std::collections::HashMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use super::aov::first_hit_aovs;
use super::finite::{DropTally, SampleMean};
use super::integrator::{
    radiance, radiance_at, CameraSample, PathContext, ShadingPoint, ShadowHint, DEFAULT_MAX_SECONDARY_RAYS,
    HINTED_LIGHTS,
};
use super::packet::{closest_hits, shadow_passes, LANES, MIN_LANES};
use super::scene::TraceScene;
use super::stats::{
    AdaptiveCounts, BudgetStats, GridStats, MeshGridStats, MotionStats, NoiseStats, RayCounts, RenderStats,
};
use crate::film::{AovSet, Aovs, Film};
use crate::math::{Ray, RayPacket, Vec2, Vec3, SHADOW_EPSILON};
use crate::sample::adaptive::{refine_pixel, AdaptiveSettings, AdaptiveStats, LatticePoint};
use crate::sample::pattern::{disk_point, disk_point_in, square_point_in, strata};
use crate::sample::rng::{permute, uniform2, Dimension, SampleKey};
use crate::sample::warp::tent;
use crate::sample::{Filter, Pattern};
use crate::simd::SimdLevel;
use crate::store::{MeshEntry, PrimitiveStore, TraversalCost};

/// Edge length of a square render tile in pixels.
pub const TILE: u32 = 16;

/// `SampleKey::sample` of the pixel-level patterns (positions and lens points), kept apart
/// from every camera sample's own key.
const PIXEL_PATTERNS: u32 = u32::MAX;
/// Dimension of the anti-aliasing pattern in the pixel-level key.
const DIM_PIXEL: u32 = 0;
/// Dimension of the lens pattern in the pixel-level key.
const DIM_LENS: u32 = 1;
/// Dimension of the shutter times in the pixel-level key (only where something moves).
const DIM_TIME: u32 = 2;

/// A sample count and the pattern that places the samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sampling {
    /// Number of samples (at least 1).
    pub samples: u32,
    /// Placement.
    pub pattern: Pattern,
}

impl Default for Sampling {
    fn default() -> Self {
        Self { samples: 1, pattern: Pattern::Jittered }
    }
}

/// Anti-aliasing: samples per pixel, their pattern and the filter footprint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AntiAliasing {
    /// Samples per pixel and their placement.
    pub sampling: Sampling,
    /// Footprint: the pixel (box) or a tent two pixels wide.
    pub filter: Filter,
}

/// How to render a snapshot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Maximum reflection/refraction depth.
    pub max_depth: u32,
    /// Minimum path weight worth tracing.
    pub min_contribution: f32,
    /// Seed of all randomness.
    pub seed: u64,
    /// Frame number (part of every random sample's key).
    pub frame: u32,
    /// Anti-aliasing (ignored when `adaptive` is on).
    pub aa: AntiAliasing,
    /// Adaptive supersampling by corner subdivision; replaces `aa` when set.
    pub adaptive: Option<AdaptiveSettings>,
    /// Noise-driven adaptive sampling: batches of the fixed sample set (`aa` × lens × time)
    /// until each pixel's estimated error is low; ignored when `adaptive` is set.
    pub noise: Option<crate::sample::NoiseSettings>,
    /// Lens samples per camera sample (only when the camera has an aperture).
    pub lens: Sampling,
    /// Rays per glossy reflection or blurry refraction at the first bounce.
    pub glossy: Sampling,
    /// Secondary rays (reflection, refraction, glossy, blurry) one camera sample may trace;
    /// see [`super::integrator::RayBudget`].
    pub max_secondary_rays: u32,
    /// Which path traces the rays: packets at an instruction-set level, or single rays (the
    /// image is the same bits on every one).
    pub simd: crate::simd::SimdLevel,
    /// When the shutter is open (motion blur). The tracer reads only the snapshot's motion,
    /// which the World derives over this interval; kept here so it is in every frame's
    /// provenance.
    pub shutter: Option<crate::camera::Shutter>,
    /// Time samples per camera sample where something moves while the shutter is open (each
    /// AA position and lens point is traced at this many times); ignored elsewhere.
    pub time: Sampling,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            max_depth: 5,
            min_contribution: 1e-3,
            seed: 0,
            frame: 0,
            aa: AntiAliasing::default(),
            adaptive: None,
            noise: None,
            lens: Sampling::default(),
            glossy: Sampling { samples: 8, pattern: Pattern::Jittered },
            max_secondary_rays: DEFAULT_MAX_SECONDARY_RAYS,
            simd: crate::simd::SimdLevel::Auto,
            shutter: None,
            time: Sampling::default(),
        }
    }
}

/// The number of tiles an image of `width` × `height` pixels is rendered in (what progress
/// observers count to).
pub fn tile_count(width: u32, height: u32) -> u32 {
    width.div_ceil(TILE) * height.div_ceil(TILE)
}

/// Renders a snapshot into a linear film. Pure: the same inputs give the same bits for any
/// thread count or tile order, because each pixel depends only on its coordinates.
pub fn render<S: PrimitiveStore>(scene: &TraceScene<S>, settings: &RenderSettings) -> (Film, RenderStats) {
    let (film, _, stats) = render_with_aovs(scene, settings, AovSet::default());
    (film, stats)
}

/// [`render`], plus the requested AOVs (`None` when the set is empty: no buffer, no extra
/// ray). First-hit AOVs come from one geometric probe ray per pixel through its centre (counted
/// as `aov` rays); the cost AOV counts every ray the pixel traced.
pub fn render_with_aovs<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    wanted: AovSet,
) -> (Film, Option<Aovs>, RenderStats) {
    render_observed(scene, settings, wanted, &|_, _| {})
}

/// [`render_with_aovs`], calling `on_tile(done, total)` from the worker threads as each tile
/// is finished (for progress bars). The image does not depend on the observer.
pub fn render_observed<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    wanted: AovSet,
    on_tile: &(dyn Fn(u32, u32) + Sync),
) -> (Film, Option<Aovs>, RenderStats) {
    let started = Instant::now();
    let total = tile_count(settings.width, settings.height);
    let done = AtomicU32::new(0);
    let tile_done = || on_tile(done.fetch_add(1, Ordering::Relaxed) + 1, total);
    if settings.width == 0 || settings.height == 0 {
        let empty = (!wanted.is_empty()).then(|| Aovs::new(wanted, settings.width, settings.height));
        return (Film::new(settings.width, settings.height), empty, RenderStats::default());
    }
    let mut noise_stats = NoiseStats::default();
    let (Assembled { film, mut rays, cost, dropped }, adaptive) = match (settings.adaptive, settings.noise) {
        (Some(adaptive), _) => render_adaptive(scene, settings, &adaptive, wanted.cost, &tile_done),
        (None, Some(noise)) => {
            let (image, stats) =
                super::progressive::render_noise(scene, settings, &noise, wanted.cost, &tile_done);
            noise_stats = stats;
            (image, AdaptiveCounts::default())
        }
        // Packets need no per-pixel ray counts; the cost AOV, which does, traces single rays. So
        // do lens cameras: each lane's lens point differs, so a block's rays do not form a
        // frustum worth walking (measured: 20 % slower on effects_dof). Shadow packets remain.
        // Motion blur gives every lane its own time: single rays.
        (None, None)
            if settings.simd.packets()
                && !wanted.cost
                && !scene.camera.has_lens()
                && scene.motion.is_none() =>
        {
            let level = settings.simd.resolve();
            let sampler = CameraSampler::new(scene, settings);
            let tile = |area: [u32; 4], rays: &mut RayCounts, out: &mut TileOut| {
                packet_tile(&sampler, level, area, rays, out)
            };
            (render_tiles(settings, false, tile, &tile_done), AdaptiveCounts::default())
        }
        (None, None) => {
            let want_cost = wanted.cost;
            let sampler = CameraSampler::new(scene, settings);
            let tile = |[x0, y0, x1, y1]: [u32; 4], rays: &mut RayCounts, out: &mut TileOut| {
                for y in y0..y1 {
                    for x in x0..x1 {
                        let before = rays.total();
                        out.pixels.push(fixed_pixel(&sampler, x, y, rays));
                        if want_cost {
                            out.costs.push(saturate(rays.total() - before));
                        }
                    }
                }
            };
            (render_tiles(settings, want_cost, tile, &tile_done), AdaptiveCounts::default())
        }
    };
    let aovs = (!wanted.is_empty()).then(|| {
        let mut aovs = first_hit_aovs(scene, settings, wanted, &mut rays);
        aovs.cost = cost;
        aovs
    });
    let mut stats = RenderStats {
        width: settings.width,
        height: settings.height,
        threads: rayon::current_num_threads(),
        rays,
        adaptive,
        effects: scene.effects,
        aov_bytes: aovs.as_ref().map_or(0, |a| a.memory_bytes() as u64),
        dropped: dropped.finish(settings.width),
        samples_per_pixel: match (settings.adaptive, settings.noise) {
            (None, None) => CameraSampler::new(scene, settings).n,
            _ => 0,
        },
        noise: noise_stats,
        ..Default::default()
    };
    stats.times.trace = started.elapsed().as_secs_f64();
    stats.simd = settings.simd.resolve();
    stats.grid = GridStats {
        dims: scene.grid.dims,
        objects: scene.store.bounded_count(),
        references: scene.grid.reference_count() as u64,
        grid_bytes: scene.grid.memory_bytes() as u64,
        store_bytes: scene.store.memory_bytes() as u64,
        meshes: mesh_grid_stats(scene.store.meshes()),
    };
    stats.traversal = stats.rays.traversal.summary();
    if let Some(m) = &scene.motion {
        stats.motion = MotionStats {
            moving_objects: m.objects().len() as u32,
            camera_moves: m.camera.is_some(),
            timed_samples: stats.rays.timed,
        };
    }
    stats.ray_budget = BudgetStats::new(settings.max_secondary_rays, &stats.rays.budget);
    (film, aovs, stats)
}

/// The output of one tile: colours, rays per pixel when the cost AOV is wanted, and the
/// samples its pixels dropped.
pub(super) type TileResult = (Vec<Vec3>, Vec<u32>, RayCounts, DropTally);

/// A rendered image before statistics: the film, ray counts, the cost image (when wanted) and
/// the dropped non-finite samples.
pub(super) struct Assembled {
    pub(super) film: Film,
    pub(super) rays: RayCounts,
    pub(super) cost: Option<Vec<u32>>,
    pub(super) dropped: DropTally,
}

/// What one tile's shader writes: per pixel in row-major order, its colour and the samples it
/// dropped, and (only when the cost AOV is wanted) the rays it traced.
#[derive(Debug, Default)]
struct TileOut {
    pixels: Vec<(Vec3, u32)>,
    costs: Vec<u32>,
}

/// Runs `shade` over every tile (`[x0, y0, x1, y1]`, ends exclusive), tiles in parallel, and
/// assembles the film (and the cost image when `want_cost`: every tile then reports costs) in
/// tile order.
fn render_tiles<F>(
    settings: &RenderSettings,
    want_cost: bool,
    shade: F,
    tile_done: &(dyn Fn() + Sync),
) -> Assembled
where
    F: Fn([u32; 4], &mut RayCounts, &mut TileOut) + Sync,
{
    let (w, h) = (settings.width, settings.height);
    let tiles_x = w.div_ceil(TILE);
    let tiles: Vec<TileResult> = (0..tiles_x * h.div_ceil(TILE))
        .into_par_iter()
        .map(|tile| {
            let (x0, y0) = (tile % tiles_x * TILE, tile / tiles_x * TILE);
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            let mut rays = RayCounts::default();
            let mut out = TileOut { pixels: Vec::with_capacity((TILE * TILE) as usize), costs: Vec::new() };
            crate::simd::with_single_ray_level(settings.simd, || {
                shade([x0, y0, x1, y1], &mut rays, &mut out)
            });
            debug_assert_eq!(out.pixels.len() as u32, (x1 - x0) * (y1 - y0), "one entry per pixel");
            let mut dropped = DropTally::default();
            let tw = x1 - x0;
            for (k, &(_, n)) in out.pixels.iter().enumerate() {
                dropped.record((y0 + k as u32 / tw) * w + x0 + k as u32 % tw, n);
            }
            tile_done();
            (out.pixels.into_iter().map(|(c, _)| c).collect(), out.costs, rays, dropped)
        })
        .collect();
    assemble(settings, &tiles, want_cost)
}

/// The film, total counts, (if wanted) cost image and dropped samples from per-tile results
/// in tile order.
pub(super) fn assemble(settings: &RenderSettings, tiles: &[TileResult], want_cost: bool) -> Assembled {
    let (w, h) = (settings.width, settings.height);
    let tiles_x = w.div_ceil(TILE);
    let mut film = Film::new(w, h);
    let mut cost = want_cost.then(|| vec![0u32; w as usize * h as usize]);
    let mut rays = RayCounts::default();
    let mut dropped = DropTally::default();
    for (tile, (pixels, costs, counts, drops)) in tiles.iter().enumerate() {
        let (x0, y0) = (tile as u32 % tiles_x * TILE, tile as u32 / tiles_x * TILE);
        let tw = TILE.min(w - x0);
        for (k, &c) in pixels.iter().enumerate() {
            let (x, y) = (x0 + k as u32 % tw, y0 + k as u32 / tw);
            // Every path (fixed samples or adaptive) reaches the film here, finite by construction.
            debug_assert!(c.is_finite(), "non-finite radiance at pixel ({x}, {y})");
            film.set(x, y, c);
            if let (Some(cost), Some(&n)) = (cost.as_mut(), costs.get(k)) {
                cost[(y * w + x) as usize] += n;
            }
        }
        rays.add(counts);
        dropped.add(drops);
    }
    Assembled { film, rays, cost, dropped }
}

pub(super) fn saturate(n: u64) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// A pixel as the mean of its fixed set of camera samples, less those dropped as non-finite,
/// and how many were dropped.
fn fixed_pixel<S: PrimitiveStore>(
    sampler: &CameraSampler<'_, S>,
    x: u32,
    y: u32,
    rays: &mut RayCounts,
) -> (Vec3, u32) {
    let mut mean = SampleMean::default();
    for sample in 0..sampler.n {
        let (ray, camera, time) = sampler.sample(x, y, sample, rays);
        mean.add(trace_camera_ray(sampler.scene, sampler.settings, &ray, camera, time, rays));
    }
    (mean.mean(), mean.dropped())
}

/// The fixed camera samples of a frame: what every sample shares (counts and their strata),
/// worked out once rather than once per sample.
pub(super) struct CameraSampler<'a, S: PrimitiveStore> {
    pub(super) scene: &'a TraceScene<S>,
    pub(super) settings: &'a RenderSettings,
    /// AA positions per pixel, and their strata.
    n_aa: u32,
    aa_strata: (u32, u32),
    /// Lens points per AA position (1 for a pinhole).
    n_lens: u32,
    /// Times per AA position and lens point (1 where nothing moves).
    n_time: u32,
    /// Whether pixels take batches of samples (noise-driven sampling): a single AA sample then
    /// lands anywhere in the pixel instead of at its centre.
    batched: bool,
    /// Camera samples per pixel (`n_aa · n_lens · n_time`), and the strata lens points are
    /// drawn from.
    pub(super) n: u32,
    lens_strata: (u32, u32),
}

impl<'a, S: PrimitiveStore> CameraSampler<'a, S> {
    pub(super) fn new(scene: &'a TraceScene<S>, settings: &'a RenderSettings) -> Self {
        let n_aa = settings.aa.sampling.samples.max(1);
        let n_lens = if scene.camera.has_lens() { settings.lens.samples.max(1) } else { 1 };
        let n_time = if scene.motion.is_some() { settings.time.samples.max(1) } else { 1 };
        // The scene's camera-samples rule keeps the product within 32 bits.
        let n = n_aa.saturating_mul(n_lens).saturating_mul(n_time);
        let batched = settings.noise.is_some() && settings.adaptive.is_none();
        Self {
            scene,
            settings,
            n_aa,
            aa_strata: strata(n_aa),
            n_lens,
            n_time,
            batched,
            n,
            lens_strata: strata(n),
        }
    }

    /// Camera sample `sample` of pixel `(x, y)`: its ray (counted as a camera or lens ray), its
    /// key and its time in the shutter interval. Samples `i · n_lens · n_time ..` are AA
    /// position `i` (through `n_lens` lens points, each at `n_time` times). Where something
    /// moves, times are stratified over the pixel's samples (one stratum of `1/n` each, in an
    /// order decorrelated from positions and lens points, placed by the time pattern);
    /// elsewhere every time is 0 and none is drawn.
    #[inline]
    fn sample(&self, x: u32, y: u32, sample: u32, rays: &mut RayCounts) -> (Ray, CameraSample, f32) {
        self.sample_in(x, y, 0, sample, rays)
    }

    /// [`Self::sample`] of batch `batch` of the pixel: every batch is a whole stratified set of
    /// `n` samples with patterns of its own (batch 0 is the fixed render's set), for
    /// noise-driven sampling.
    #[inline]
    pub(super) fn sample_in(
        &self,
        x: u32,
        y: u32,
        batch: u32,
        sample: u32,
        rays: &mut RayCounts,
    ) -> (Ray, CameraSample, f32) {
        let (scene, settings) = (self.scene, self.settings);
        let pixel = y * settings.width + x;
        let patterns =
            SampleKey { seed: settings.seed, frame: settings.frame, pixel, sample: PIXEL_PATTERNS - batch };
        let i = sample / (self.n_lens * self.n_time);
        let u = uniform2(&patterns, DIM_PIXEL, i);
        let offset = pixel_offset(&settings.aa, self.n_aa, self.aa_strata, i, u, self.batched);
        let (px, py) = (x as f32 + offset.x, y as f32 + offset.y);
        let time = match scene.motion {
            Some(_) => {
                rays.timed += 1;
                let times = Dimension::new(&patterns, DIM_TIME);
                let k = permute(sample, self.n, times.hash(u32::MAX));
                stratum_time(settings.time.pattern, k, self.n, times.uniform2(k).x)
            }
            None => 0.0,
        };
        let camera = scene.camera_at(time);
        let ray = if camera.has_lens() {
            // Lens points are stratified over all n samples, in an order decorrelated from the
            // pixel positions.
            let lens_points = Dimension::new(&patterns, DIM_LENS);
            let k = permute(sample, self.n, lens_points.hash(u32::MAX));
            let lens = disk_point_in(settings.lens.pattern, self.lens_strata, k, lens_points.uniform2(k));
            rays.lens += 1;
            camera.lens_ray(px, py, settings.width, settings.height, lens)
        } else {
            rays.camera += 1;
            camera.ray(px, py, settings.width, settings.height)
        };
        // Batches stay far below `PIXEL_PATTERNS - batch` (the noise rules cap their samples).
        let index = batch.wrapping_mul(self.n).wrapping_add(sample);
        let key = SampleKey { seed: settings.seed, frame: settings.frame, pixel, sample: index };
        (ray, CameraSample { key, pixel: patterns, slot: sample, spp: self.n }, time)
    }
}

/// Time sample `k` of `n` placed by `pattern` with `u ∈ [0, 1)`: jittered, at offset `u` in
/// stratum `[k/n, (k+1)/n)` (a sum that rounds up to the stratum's end is pulled back below
/// it); grid, at the stratum's middle; random, `u` anywhere in `[0, 1)`.
#[inline]
fn stratum_time(pattern: Pattern, k: u32, n: u32, u: f32) -> f32 {
    let u = match pattern {
        Pattern::Jittered => u,
        Pattern::Grid => 0.5,
        Pattern::Random => return u,
    };
    let t = (k as f32 + u) / n as f32;
    t.min(((k + 1) as f32 / n as f32).next_down())
}

/// Width and height in pixels of the block whose camera rays form one packet.
const BLOCK: [u32; 2] = [4, 4];

/// A tile traced in packets: each block of [`BLOCK`] pixels sends its camera samples as one
/// packet per sample index, finds their first hits together ([`closest_hits`], compiled for
/// `level`), and shades each lane on its own. Every pixel accumulates its samples in the same
/// order as [`fixed_pixel`], from the same hits, so the image is the same bits.
fn packet_tile<S: PrimitiveStore>(
    sampler: &CameraSampler<'_, S>,
    level: SimdLevel,
    [x0, y0, x1, y1]: [u32; 4],
    rays: &mut RayCounts,
    out: &mut TileOut,
) {
    const { assert!((BLOCK[0] * BLOCK[1]) as usize == LANES) };
    let tw = x1 - x0;
    out.pixels.resize(((y1 - y0) * tw) as usize, (Vec3::ZERO, 0));
    let (scene, settings, n) = (sampler.scene, sampler.settings, sampler.n);
    for by in (y0..y1).step_by(BLOCK[1] as usize) {
        for bx in (x0..x1).step_by(BLOCK[0] as usize) {
            let mut means = [SampleMean::default(); LANES];
            let pixel = |lane: usize| {
                let (x, y) = (bx + lane as u32 % BLOCK[0], by + lane as u32 / BLOCK[0]);
                (x < x1 && y < y1).then_some((x, y))
            };
            for sample in 0..n {
                let mut packet = RayPacket::<LANES>::default();
                let mut cameras = [None; LANES];
                for (lane, camera) in cameras.iter_mut().enumerate() {
                    if let Some((x, y)) = pixel(lane) {
                        let (ray, key, _) = sampler.sample(x, y, sample, rays);
                        packet.set(lane, &ray, 0.0, f32::INFINITY);
                        *camera = Some(key);
                    }
                }
                let mut cost = TraversalCost::default();
                let hits = level.run(
                    #[inline(always)]
                    || closest_hits(scene, &packet, &mut cost),
                );
                let lane_cost = cost.per_ray(cameras.iter().flatten().count() as u32);
                // Each hit's surface, found once: the shadow packets start from it, and so does
                // the lane's shading.
                let surfaces: [Option<ShadingPoint>; LANES] = std::array::from_fn(|lane| {
                    let ray = packet.ray(lane);
                    hits.hit[lane].map(|hit| ShadingPoint::new(scene.store.surface(&hit, &ray), ray.dir))
                });
                let hints = point_light_shadows(scene, &surfaces, level, rays);
                for (lane, camera) in cameras.iter().enumerate() {
                    if let Some(camera) = *camera {
                        let mut ctx = PathContext::new(settings, camera, rays);
                        ctx.shadow_hint = hints[lane];
                        ctx.surface_hint = surfaces[lane];
                        let ray = packet.ray(lane);
                        means[lane].add(radiance_at(
                            scene,
                            &ray,
                            hits.hit[lane],
                            lane_cost,
                            0,
                            1.0,
                            &mut ctx,
                        ));
                        ctx.finish();
                    }
                }
            }
            for (lane, mean) in means.iter().enumerate() {
                if let Some((x, y)) = pixel(lane) {
                    out.pixels[((y - y0) * tw + x - x0) as usize] = (mean.mean(), mean.dropped());
                }
            }
        }
    }
}

/// The shadow rays from a packet's camera hits towards each of the first [`HINTED_LIGHTS`]
/// point or directional lights, traced as one packet per light (a common end point, or a
/// common direction): per lane, the transmittance [`super::phong::direct_light`] would find,
/// computed from the same shading point (`surfaces`: each camera hit's, as `radiance_at` sees
/// it).
fn point_light_shadows<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    surfaces: &[Option<ShadingPoint>; LANES],
    level: SimdLevel,
    rays: &mut RayCounts,
) -> [Option<ShadowHint>; LANES] {
    let mut hints = [None; LANES];
    let lights = scene.lights.iter().enumerate().take(HINTED_LIGHTS).filter(|(_, l)| !l.is_area());
    if scene.lights.iter().take(HINTED_LIGHTS).all(|l| l.is_area()) {
        return hints;
    }
    for (j, light) in lights {
        let mut shadow = RayPacket::<LANES>::default();
        let mut lanes = 0;
        for (lane, surface) in surfaces.iter().enumerate() {
            let Some(ShadingPoint { sp, ns, above, .. }) = *surface else { continue };
            let (to_light, dist, _) = light.towards(sp.point);
            if ns.dot(to_light) <= 0.0 {
                continue;
            }
            shadow.set(lane, &Ray::new(above, to_light), 0.0, dist * (1.0 - SHADOW_EPSILON));
            lanes += 1;
        }
        if (lanes as usize) < MIN_LANES {
            // Too few to pay for a packet: `direct_light` traces them alone.
            continue;
        }
        let mut cost = TraversalCost::default();
        let pass = level.run(
            #[inline(always)]
            || shadow_passes(scene, &shadow, &mut cost),
        );
        let each = cost.per_ray(lanes);
        for lane in 0..LANES {
            if shadow.active[lane] {
                rays.traversal.record(each);
                let hint = hints[lane].get_or_insert([None; HINTED_LIGHTS]);
                hint[j] = Some(pass[lane]);
            }
        }
    }
    hints
}

/// Where in the pixel (in pixel units from its top-left corner) sample `i` of `n` lands. A
/// single sample goes through the pixel's centre, unless `batched`: one of many batches of
/// noise-driven sampling, which together must cover the footprint.
fn pixel_offset(aa: &AntiAliasing, n: u32, strata: (u32, u32), i: u32, u: Vec2, batched: bool) -> Vec2 {
    if n == 1 && !batched {
        return Vec2::splat(0.5);
    }
    let p = square_point_in(aa.sampling.pattern, strata, i, u);
    match aa.filter {
        Filter::Box => p,
        Filter::Tent => Vec2::new(0.5 + tent(p.x), 0.5 + tent(p.y)),
    }
}

pub(super) fn trace_camera_ray<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    ray: &Ray,
    camera: CameraSample,
    time: f32,
    rays: &mut RayCounts,
) -> Vec3 {
    let mut ctx = PathContext::new(settings, camera, rays);
    if scene.motion.is_some() {
        ctx = ctx.at_time(time);
    }
    let colour = radiance(scene, ray, 0, 1.0, &mut ctx);
    ctx.finish();
    colour
}

/// Adaptive supersampling: the `(W+1) × (H+1)` pixel corners first (each traced once), then
/// every pixel refined by corner subdivision, tiles in parallel with a cache per tile. In the
/// cost image a corner's rays count for the pixel whose top-left corner it is (clamped).
/// Non-finite lattice samples are dropped by [`refine_pixel`] and counted per pixel.
fn render_adaptive<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    adaptive: &AdaptiveSettings,
    want_cost: bool,
    tile_done: &(dyn Fn() + Sync),
) -> (Assembled, AdaptiveCounts) {
    let (w, h) = (settings.width, settings.height);
    let res = adaptive.resolution();
    let point = |p: LatticePoint, rays: &mut RayCounts| {
        crate::simd::with_single_ray_level(settings.simd, || lattice_sample(scene, settings, res, p, rays))
    };

    // Pass 1: the corner lattice, rows in parallel, with each corner's ray count.
    let rows: Vec<(Vec<Vec3>, Vec<u32>, RayCounts)> = (0..=h)
        .into_par_iter()
        .map(|cy| {
            let mut rays = RayCounts::default();
            let mut costs = Vec::with_capacity(w as usize + 1);
            let row = (0..=w)
                .map(|cx| {
                    let before = rays.total();
                    let c = point(LatticePoint { x: cx * res, y: cy * res }, &mut rays);
                    costs.push(saturate(rays.total() - before));
                    c
                })
                .collect();
            (row, costs, rays)
        })
        .collect();
    let corner = |cx: u32, cy: u32| rows[cy as usize].0[cx as usize];

    // Pass 2: refinement, tiles in parallel, each with its own cache and adaptive figures.
    let tiles_x = w.div_ceil(TILE);
    let refined: Vec<(TileResult, AdaptiveStats)> = (0..tiles_x * h.div_ceil(TILE))
        .into_par_iter()
        .map(|tile| {
            let (x0, y0) = (tile % tiles_x * TILE, tile / tiles_x * TILE);
            let mut rays = RayCounts::default();
            let mut stats = AdaptiveStats::default();
            let mut cache = HashMap::new();
            let mut pixels = Vec::with_capacity((TILE * TILE) as usize);
            let mut costs = Vec::new();
            let mut dropped = DropTally::default();
            for y in y0..(y0 + TILE).min(h) {
                for x in x0..(x0 + TILE).min(w) {
                    let corners = [corner(x, y), corner(x + 1, y), corner(x, y + 1), corner(x + 1, y + 1)];
                    let before = rays.total();
                    let dropped_before = stats.dropped;
                    let mut trace = |p: LatticePoint| point(p, &mut rays);
                    pixels.push(refine_pixel(x, y, corners, adaptive, &mut cache, &mut trace, &mut stats));
                    dropped.record(y * w + x, saturate(stats.dropped - dropped_before));
                    if want_cost {
                        costs.push(saturate(rays.total() - before));
                    }
                }
            }
            tile_done();
            ((pixels, costs, rays, dropped), stats)
        })
        .collect();
    let mut counts = AdaptiveCounts { traced: u64::from(w + 1) * u64::from(h + 1), ..Default::default() };
    refined.iter().for_each(|(_, s)| {
        counts.traced += s.traced;
        counts.reused += s.reused;
        counts.subdivisions += s.subdivisions;
    });
    let tiles: Vec<TileResult> = refined.into_iter().map(|(t, _)| t).collect();
    let mut image = assemble(settings, &tiles, want_cost);
    for (cy, (_, costs, row_rays)) in rows.iter().enumerate() {
        image.rays.add(row_rays);
        if let Some(cost) = image.cost.as_mut() {
            let y = (cy as u32).min(h - 1);
            for (cx, &n) in costs.iter().enumerate() {
                cost[(y * w + (cx as u32).min(w - 1)) as usize] += n;
            }
        }
    }
    (image, counts)
}

/// The colour at a lattice point (image position `p / res`): one camera sample (with one lens
/// point when the camera has an aperture), or where something moves, its share of the time
/// samples, each at its own time and lens point; effect budgets are scaled to the area the
/// point stands for. A pure function of the point's coordinates.
fn lattice_sample<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    res: u32,
    p: LatticePoint,
    rays: &mut RayCounts,
) -> Vec3 {
    let id = u64::from(p.y) * (u64::from(settings.width) * u64::from(res) + 1) + u64::from(p.x);
    let key =
        SampleKey { seed: settings.seed, frame: settings.frame, pixel: id as u32, sample: (id >> 32) as u32 };
    let (px, py) = (p.x as f32 / res as f32, p.y as f32 / res as f32);
    // A point first needed at subdivision level l stands for a square of 4^-l of a pixel: it
    // takes that share of each effect's per-pixel budget (corners, level 0, take all of it),
    // time samples included (at least one).
    let level =
        res.trailing_zeros() - p.x.trailing_zeros().min(p.y.trailing_zeros()).min(res.trailing_zeros());
    let spp = 1u32 << (2 * level);
    let times = match scene.motion {
        Some(_) => settings.time.samples.max(1).div_ceil(spp),
        None => 1,
    };
    let order = crate::sample::rng::hash(&key, DIM_TIME, PIXEL_PATTERNS - 1);
    let mut mean = SampleMean::default();
    for j in 0..times {
        // Sample 0 keeps the point's own key and draws; the others get keys of their own.
        let index = PIXEL_PATTERNS - 2 * j;
        let time = match scene.motion {
            Some(_) => {
                rays.timed += 1;
                let k = permute(j, times, order);
                let u = crate::sample::rng::uniform(&key, DIM_TIME, index);
                stratum_time(settings.time.pattern, k, times, u)
            }
            None => 0.0,
        };
        let cam = scene.camera_at(time);
        let ray = if cam.has_lens() {
            rays.lens += 1;
            let lens = disk_point(Pattern::Random, 1, 0, uniform2(&key, DIM_LENS, index));
            cam.lens_ray(px, py, settings.width, settings.height, lens)
        } else {
            rays.camera += 1;
            cam.ray(px, py, settings.width, settings.height)
        };
        let own = match j {
            0 => key,
            _ => SampleKey { sample: key.sample ^ j.wrapping_mul(0x9E37_79B9), ..key },
        };
        let camera = CameraSample { key: own, pixel: key, slot: j, spp: spp.saturating_mul(times) };
        mean.add(trace_camera_ray(scene, settings, &ray, camera, time, rays));
    }
    // A point none of whose samples is finite is non-finite, so refinement drops and counts it.
    match mean.dropped() == times {
        true => Vec3::NAN,
        false => mean.mean(),
    }
}

/// Figures of the mesh level of a store's two-level grid.
fn mesh_grid_stats<L: crate::store::TriangleLayout>(meshes: &[Arc<MeshEntry<L>>]) -> MeshGridStats {
    let mut m = MeshGridStats { assets: meshes.len() as u32, ..Default::default() };
    for e in meshes {
        m.triangles += e.asset.data.triangle_count() as u64;
        m.references += e.asset.grid.reference_count() as u64;
        m.grid_bytes += e.asset.grid.memory_bytes() as u64;
        m.store_bytes += e.memory_bytes() as u64;
        m.data_bytes += e.asset.data.memory_bytes() as u64;
    }
    if m.triangles > 0 {
        m.grid_bytes_per_triangle = m.grid_bytes as f64 / m.triangles as f64;
        m.store_bytes_per_triangle = (m.store_bytes + m.data_bytes) as f64 / m.triangles as f64;
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_keep_to_their_strata_by_pattern() {
        let n = 8;
        for k in 0..n {
            let (lo, hi) = (k as f32 / n as f32, (k + 1) as f32 / n as f32);
            for u in [0.0, 0.3, 1.0f32.next_down()] {
                let t = stratum_time(Pattern::Jittered, k, n, u);
                assert!((lo..hi).contains(&t), "jittered time {t} of stratum {k} at u = {u}");
            }
            assert_eq!(stratum_time(Pattern::Grid, k, n, 0.9), (k as f32 + 0.5) / n as f32);
            assert_eq!(stratum_time(Pattern::Random, k, n, 0.9), 0.9, "random ignores the stratum");
        }
        // The last stratum's end is pulled back inside it.
        assert!(stratum_time(Pattern::Jittered, 2, 3, 1.0f32.next_down()) < 1.0);
    }
}
