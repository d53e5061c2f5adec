//! A frame's fixed camera samples: where each lands in its pixel (anti-aliasing pattern and
//! filter), its lens point and shutter time, its sample key, and the path traced from it.

use super::finite::SampleMean;
use super::integrator::radiance;
use super::path::{CameraSample, PathContext, Replica};
use super::scene::TraceScene;
use super::settings::{AntiAliasing, RenderSettings};
use super::stats::RayCounts;

use crate::math::{Ray, RayPacket, Vec2, Vec3};
use crate::sample::dims;
use crate::sample::pattern::{disk_point_in, square_point_in, square_points_in, strata};
use crate::sample::rng::{permute, uniform2, Dimension, Permutation, SampleKey};
use crate::sample::sobol::Progressive;
use crate::sample::warp::{concentric_disk, tent};
use crate::sample::{Filter, Pattern};
use crate::store::PrimitiveStore;

/// A pixel as the mean of its fixed set of camera samples, less those dropped as non-finite,
/// and how many were dropped.
pub(super) fn fixed_pixel<S: PrimitiveStore>(
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
    /// One AA position but several camera samples (lens points or times): each camera sample
    /// then takes a pixel position of its own, so that a lens or a shutter anti-aliases too.
    spread: bool,
    /// Camera samples per pixel (`n_aa · n_lens · n_time`), and the strata lens points are
    /// drawn from.
    pub(super) n: u32,
    lens_strata: (u32, u32),
}

impl<'a, S: PrimitiveStore> CameraSampler<'a, S> {
    pub(super) fn new(scene: &'a TraceScene<S>, settings: &'a RenderSettings) -> Self {
        let n_aa = settings.aa.samples.max(1);
        let n_lens = if scene.camera.has_lens() { settings.lens.samples.max(1) } else { 1 };
        let n_time = if scene.motion.is_some() { settings.time.samples.max(1) } else { 1 };
        // The scene's camera-samples rule keeps the product within 32 bits.
        let n = n_aa.saturating_mul(n_lens).saturating_mul(n_time);
        Self {
            scene,
            settings,
            n_aa,
            aa_strata: strata(n_aa),
            n_lens,
            n_time,
            spread: n_aa == 1 && n > 1,
            n,
            lens_strata: strata(n),
        }
    }

    /// Camera sample `sample` of pixel `(x, y)`: its ray (counted as a camera or lens ray), its
    /// key and its time in the shutter interval. Samples `i · n_lens · n_time ..` are AA
    /// position `i` (through `n_lens` lens points, each at `n_time` times); with one AA
    /// position, each of several samples takes its own position in the pixel instead. Where
    /// something moves, times are stratified over the pixel's samples (one stratum of `1/n` each, in an
    /// order decorrelated from positions and lens points, placed by the time pattern);
    /// elsewhere every time is 0 and none is drawn.
    #[inline]
    pub(super) fn sample(
        &self,
        x: u32,
        y: u32,
        sample: u32,
        rays: &mut RayCounts,
    ) -> (Ray, CameraSample, f32) {
        let settings = self.settings;
        let pixel = y * settings.width + x;
        let patterns = self.pixel_key(pixel);
        let offset = self.offset(patterns, sample);
        let time = match self.scene.motion {
            Some(_) => {
                rays.timed += 1;
                let times = Dimension::new(&patterns, dims::TIME);
                let k = permute(sample, self.n, times.hash(dims::PERMUTATION_SEED));
                stratum_time(settings.time.pattern, k, self.n, times.uniform2(k).x)
            }
            None => 0.0,
        };
        let lens = || {
            // Lens points are stratified over all n samples, in an order decorrelated from the
            // pixel positions.
            let lens_points = Dimension::new(&patterns, dims::LENS);
            let k = permute(sample, self.n, lens_points.hash(dims::PERMUTATION_SEED));
            disk_point_in(settings.lens.pattern, self.lens_strata, k, lens_points.uniform2(k))
        };
        let ray = self.ray(x, y, offset, time, lens, rays);
        let key = SampleKey { seed: settings.seed, frame: settings.frame, pixel, sample };
        let camera = CameraSample { key, pixel: patterns, slot: sample, spp: self.n, progressive: None };
        (ray, camera, time)
    }

    /// Where in its pixel (in pixel units from the top-left corner) camera sample `sample`
    /// of the pixel whose patterns are keyed by `patterns` lands.
    #[inline]
    fn offset(&self, patterns: SampleKey, sample: u32) -> Vec2 {
        let settings = self.settings;
        match self.spread {
            // The n samples take the n positions an AA n render of this pixel takes (the same
            // strata and points), in an order decorrelated from their lens points and times: a
            // pinhole at AA n and a lens at AA 1 with n lens samples see the focal plane alike.
            true => {
                let positions = Dimension::new(&patterns, dims::PIXEL);
                let k = permute(sample, self.n, positions.hash(dims::PERMUTATION_SEED));
                pixel_offset(&settings.aa, self.n, self.lens_strata, k, positions.uniform2(k), true)
            }
            // One camera sample per pixel goes through its centre ([`pixel_offset`]): no point
            // drawn, no hash worked out (it was 3 % of the spheres twin's trace instructions).
            false if self.n == 1 => Vec2::splat(0.5),
            false => {
                // Most scenes take one camera sample per AA position: no division then.
                let per = self.n_lens * self.n_time;
                let i = if per == 1 { sample } else { sample / per };
                let u = uniform2(&patterns, dims::PIXEL, i);
                pixel_offset(&settings.aa, self.n_aa, self.aa_strata, i, u, false)
            }
        }
    }

    /// Camera sample `sample` of pixel `(x, y)` for a pinhole camera that does not move, as
    /// [`Self::sample`] gives it but without its ray: the image point the ray goes through (for
    /// [`crate::camera::Camera::pinhole_lanes`]) and the sample's key. Counted as a camera ray.
    #[inline]
    pub(super) fn image_point(
        &self,
        x: u32,
        y: u32,
        sample: u32,
        rays: &mut RayCounts,
    ) -> (Vec2, CameraSample) {
        debug_assert!(!self.scene.camera.has_lens() && self.scene.motion.is_none());
        let settings = self.settings;
        let pixel = y * settings.width + x;
        let patterns = self.pixel_key(pixel);
        let offset = self.offset(patterns, sample);
        rays.camera += 1;
        let key = SampleKey { seed: settings.seed, frame: settings.frame, pixel, sample };
        let camera = CameraSample { key, pixel: patterns, slot: sample, spp: self.n, progressive: None };
        (Vec2::new(x as f32 + offset.x, y as f32 + offset.y), camera)
    }

    /// Camera samples `first..first + count` of pixel `(x, y)` of a lens camera that does not
    /// move, `count` at most `N`: the rays in lanes `0..count` of a packet (their reciprocals
    /// not yet worked out) and their samples, each as [`Self::sample`] gives it, counted as lens
    /// rays. Where each sample takes its own pixel position (`spread`), the positions' and lens
    /// points' strata, hashes and jitters are found lane by lane, the per-pixel parts once
    /// ([`Permutation::at_lanes`], [`Dimension::uniform2_lanes`], [`square_points_in`]: the
    /// same bits); only the disk warp and the ray itself are taken lane after lane. Inline it
    /// into a [`crate::simd::SimdLevel::run`] closure to get the level's vectors.
    #[inline(always)]
    pub(super) fn lens_lanes<const N: usize>(
        &self,
        x: u32,
        y: u32,
        first: u32,
        count: usize,
        rays: &mut RayCounts,
    ) -> (RayPacket<N>, [Option<CameraSample>; N]) {
        debug_assert!(self.scene.motion.is_none() && self.scene.camera.has_lens() && count <= N);
        if !self.spread {
            return packet_of((first..first + count as u32).map(|sample| {
                let (ray, camera, _) = self.sample(x, y, sample, rays);
                (ray, camera)
            }));
        }
        let mut packet = RayPacket::<N>::default();
        let mut cameras = [None; N];
        let settings = self.settings;
        let pixel = y * settings.width + x;
        let patterns = self.pixel_key(pixel);
        // Lanes past `count` take sample `first` (a valid index) and are left out below.
        let samples: [u32; N] = std::array::from_fn(|k| if k < count { first + k as u32 } else { first });
        let points = |dim: u32, pattern: Pattern| {
            let points = Dimension::new(&patterns, dim);
            let k = Permutation::new(self.n, points.hash(dims::PERMUTATION_SEED)).at_lanes(&samples);
            let (ux, uy) = points.uniform2_lanes(&k);
            square_points_in(pattern, self.lens_strata, &k, &ux, &uy)
        };
        let offsets = points(dims::PIXEL, settings.aa.pattern);
        let lens = points(dims::LENS, settings.lens.pattern);
        let camera = &self.scene.camera;
        for lane in 0..count {
            let offset = filtered(&settings.aa, offsets[lane]);
            let (px, py) = (x as f32 + offset.x, y as f32 + offset.y);
            let ray = camera.lens_ray(px, py, settings.width, settings.height, concentric_disk(lens[lane]));
            packet.put(lane, &ray, 0.0, f32::INFINITY);
            let key = SampleKey { seed: settings.seed, frame: settings.frame, pixel, sample: samples[lane] };
            cameras[lane] = Some(CameraSample {
                key,
                pixel: patterns,
                slot: samples[lane],
                spp: self.n,
                progressive: None,
            });
        }
        rays.lens += count as u64;
        (packet, cameras)
    }

    /// Camera sample `sample` of batch `batch` of the pixel, for noise-driven sampling. The
    /// pixel's samples, counted over all its batches, take independent replicates in turn
    /// ([`Replica`]); each replicate's positions, lens points, times and effect
    /// points are the next of its progressive sequences ([`crate::sample::sobol`]), so every
    /// prefix of each replicate is stratified in every dimension, however many batches the
    /// pixel takes. Each camera sample takes its own position in the pixel.
    #[inline]
    pub(super) fn sample_in(
        &self,
        x: u32,
        y: u32,
        batch: u32,
        sample: u32,
        rays: &mut RayCounts,
    ) -> (Ray, CameraSample, f32) {
        let settings = self.settings;
        let pixel = y * settings.width + x;
        let patterns = self.pixel_key(pixel);
        // The noise rules cap a pixel's samples far below 2³².
        let j = batch.wrapping_mul(self.n).wrapping_add(sample);
        let r = Replica::of(j);
        let place = |pattern: Pattern, dim: u32, strata: (u32, u32)| {
            let points = Dimension::new(&patterns, dim);
            r.place(pattern, Progressive::new(points, r.replicate), points, strata)
        };
        let offset = filtered(&settings.aa, place(settings.aa.pattern, dims::PIXEL, self.aa_strata));
        let time = match self.scene.motion {
            Some(_) => {
                rays.timed += 1;
                let times = Dimension::new(&patterns, dims::TIME);
                match settings.time.pattern {
                    Pattern::Jittered => Progressive::new(times, r.replicate).point1(r.index),
                    pattern => {
                        stratum_time(pattern, r.index % self.n, self.n, place(pattern, dims::TIME, (1, 1)).x)
                    }
                }
            }
            None => 0.0,
        };
        let lens = || concentric_disk(place(settings.lens.pattern, dims::LENS, self.lens_strata));
        let ray = self.ray(x, y, offset, time, lens, rays);
        let key = SampleKey { seed: settings.seed, frame: settings.frame, pixel, sample: j };
        let camera = CameraSample { key, pixel: patterns, slot: sample, spp: self.n, progressive: Some(r) };
        (ray, camera, time)
    }

    /// The key every camera sample of `pixel` shares, for its pixel-level patterns.
    #[inline]
    fn pixel_key(&self, pixel: u32) -> SampleKey {
        let settings = self.settings;
        SampleKey { seed: settings.seed, frame: settings.frame, pixel, sample: dims::PIXEL_PATTERNS }
    }

    /// The ray through `offset` (pixel units from pixel `(x, y)`'s top-left corner) at `time`,
    /// through the lens point `lens` draws where the camera has a lens; counted as a camera or
    /// lens ray.
    #[inline]
    fn ray(
        &self,
        x: u32,
        y: u32,
        offset: Vec2,
        time: f32,
        lens: impl FnOnce() -> Vec2,
        rays: &mut RayCounts,
    ) -> Ray {
        let settings = self.settings;
        let (px, py) = (x as f32 + offset.x, y as f32 + offset.y);
        let camera = self.scene.camera_at(time);
        if camera.has_lens() {
            let point = lens();
            rays.lens += 1;
            camera.lens_ray(px, py, settings.width, settings.height, point)
        } else {
            rays.camera += 1;
            camera.ray(px, py, settings.width, settings.height)
        }
    }
}

/// Time sample `k` of `n` placed by `pattern` with `u ∈ [0, 1)`: jittered, at offset `u` in
/// stratum `[k/n, (k+1)/n)` (a sum that rounds up to the stratum's end is pulled back below
/// it); grid, at the stratum's middle; random, `u` anywhere in `[0, 1)`.
#[inline]
pub(super) fn stratum_time(pattern: Pattern, k: u32, n: u32, u: f32) -> f32 {
    let u = match pattern {
        Pattern::Jittered => u,
        Pattern::Grid => 0.5,
        Pattern::Random => return u,
    };
    let t = (k as f32 + u) / n as f32;
    t.min(((k + 1) as f32 / n as f32).next_down())
}

/// Where in the pixel (in pixel units from its top-left corner) sample `i` of `n` lands. A
/// single sample goes through the pixel's centre, unless `cover`: it is one of a lens's (or a
/// shutter's) samples at AA 1, which together must cover the footprint.
pub(super) fn pixel_offset(
    aa: &AntiAliasing,
    n: u32,
    strata: (u32, u32),
    i: u32,
    u: Vec2,
    cover: bool,
) -> Vec2 {
    if n == 1 && !cover {
        return Vec2::splat(0.5);
    }
    filtered(aa, square_point_in(aa.pattern, strata, i, u))
}

/// A point `p` of the unit square spread over the footprint of `aa`'s filter.
#[inline]
fn filtered(aa: &AntiAliasing, p: Vec2) -> Vec2 {
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

/// A packet of the camera rays `samples` gives, lane by lane from lane 0, each searched from 0 to
/// ∞ (reciprocals not yet taken: [`RayPacket::reciprocals`], at the packet's SIMD level), with
/// each lane's camera sample; at most `N` are taken.
pub(super) fn packet_of<const N: usize>(
    samples: impl IntoIterator<Item = (Ray, CameraSample)>,
) -> (RayPacket<N>, [Option<CameraSample>; N]) {
    let mut packet = RayPacket::<N>::default();
    let mut cameras = [None; N];
    for (lane, (ray, camera)) in samples.into_iter().take(N).enumerate() {
        packet.put(lane, &ray, 0.0, f32::INFINITY);
        cameras[lane] = Some(camera);
    }
    (packet, cameras)
}

#[cfg(test)]
mod tests;
