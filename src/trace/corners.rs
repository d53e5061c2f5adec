//! Adaptive supersampling's renderer: the pixel corners of the whole image first, then each
//! pixel subdivided where its corners disagree ([`crate::sample::adaptive`]).

use rayon::prelude::*;

use super::camera_samples::{packet_of, stratum_time, trace_camera_ray};
use super::finite::SampleMean;
use super::packet::LANES;
use super::packet_tile::{camera_packets, lens_packets, shade_packet, BLOCK, MIN_LENS_LANES};
use super::path::CameraSample;
use super::scene::TraceScene;
use super::settings::RenderSettings;
use super::stats::{AdaptiveCounts, RayCounts};
use super::tiles::{render_tiles_with, saturate, Assembled, TileOut};
use crate::math::{Vec2, Vec3};
use crate::sample::adaptive::{
    refine_pixel, AdaptiveSettings, AdaptiveStats, LatticePoint, PointCache, PointSample,
};
use crate::sample::dims;
use crate::sample::pattern::{disk_point, disk_point_in, strata};
use crate::sample::rng::{permute, Dimension, SampleKey};
use crate::sample::Pattern;
use crate::simd::SimdLevel;
use crate::store::PrimitiveStore;
use glam::DVec3;

/// Adaptive supersampling: the `(W+1) × (H+1)` pixel corners first (each traced once), then
/// every pixel refined by corner subdivision, tiles in parallel with a cache per tile. In the
/// cost image a corner's rays count for the pixel whose top-left corner it is (clamped).
/// Non-finite lattice samples are dropped by [`refine_pixel`] and counted per pixel.
pub(super) fn render_adaptive<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    adaptive: &AdaptiveSettings,
    want_cost: bool,
    tile_done: &(dyn Fn() + Sync),
) -> (Assembled, AdaptiveCounts) {
    let (w, h) = (settings.width, settings.height);
    let res = adaptive.resolution();
    let packets = lens_packets(scene, settings, want_cost);
    let point =
        |p: LatticePoint, rays: &mut RayCounts| lattice_sample(scene, settings, res, p, packets, rays);
    // Each row and tile runs with this thread's single-ray kernels at the frame's level.
    let at_level = |work: &mut dyn FnMut()| crate::simd::with_single_ray_level(settings.simd, work);

    // Pass 1: the corner lattice, bands of rows in parallel, with each corner's ray count. A
    // pinhole camera's corners are one camera ray each, as regular as a fixed render's pixels:
    // they go in packets of [`BLOCK`] corners, bands of `BLOCK[1]` rows (no per-corner counts,
    // which only the cost image wants and which keeps single rays).
    let corner_packets = camera_packets(scene, settings, want_cost);
    let band = corner_packets.map_or(1, |_| BLOCK[1]);
    let rows: Vec<(Vec<PointSample>, Vec<u32>, RayCounts)> = (0..=h)
        .step_by(band as usize)
        .collect::<Vec<_>>()
        .into_par_iter()
        // One band per job, as tiles are ([`super::tiles::render_tiles`]).
        .with_max_len(1)
        .flat_map_iter(|y0| {
            let mut rays = RayCounts::default();
            let y1 = (y0 + band).min(h + 1);
            let mut rows: Vec<(Vec<PointSample>, Vec<u32>)> =
                (y0..y1).map(|_| (Vec::with_capacity(w as usize + 1), Vec::new())).collect();
            at_level(&mut || match corner_packets {
                Some(level) => corner_band(scene, settings, res, level, y0..y1, &mut rows, &mut rays),
                None => {
                    let (row, costs) = &mut rows[0];
                    for cx in 0..=w {
                        let before = rays.total();
                        row.push(point(LatticePoint { x: cx * res, y: y0 * res }, &mut rays));
                        costs.push(saturate(rays.total() - before));
                    }
                }
            });
            // The band's rays count with its first row.
            let mut counts = Some(rays);
            rows.into_iter().map(move |(row, costs)| (row, costs, counts.take().unwrap_or_default()))
        })
        .collect();
    let corner = |cx: u32, cy: u32| rows[cy as usize].0[cx as usize];

    // Pass 2: refinement, tiles in parallel, each with its own cache and adaptive figures.
    let refine =
        |[x0, y0, x1, y1]: [u32; 4], rays: &mut RayCounts, out: &mut TileOut, stats: &mut AdaptiveStats| {
            let mut cache = PointCache::default();
            for y in y0..y1 {
                for x in x0..x1 {
                    let corners = [corner(x, y), corner(x + 1, y), corner(x, y + 1), corner(x + 1, y + 1)];
                    let before = rays.total();
                    let dropped_before = stats.dropped;
                    let mut trace = |p: LatticePoint| point(p, rays);
                    let colour = refine_pixel(x, y, corners, adaptive, &mut cache, &mut trace, stats);
                    out.pixels.push((colour, saturate(stats.dropped - dropped_before)));
                    if want_cost {
                        out.costs.push(saturate(rays.total() - before));
                    }
                }
            }
        };
    let (mut image, stats) = render_tiles_with(settings, want_cost, refine, tile_done);
    let counts = AdaptiveCounts {
        traced: u64::from(w + 1) * u64::from(h + 1) + stats.traced,
        reused: stats.reused,
        subdivisions: stats.subdivisions,
    };
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

/// The colour at a lattice point (image position `p / res`), and the spread of its samples:
/// its share of the pixel's camera samples. A point first needed at subdivision level `l`
/// stands for `4^-l` of a pixel, and takes that share of the lens samples (with an aperture)
/// and of the time samples (where something moves), each at least one, stratified over the
/// point's samples; effect budgets are scaled to the same area. Pixel corners (level 0) take
/// them all, as a fixed render's pixel does. A pure function of the point's coordinates.
///
/// With `packets` (a lens camera that does not move: [`lens_packets`]), a point's samples, which
/// all pass through its image position and so converge on one point of the plane in focus, go
/// in packets of up to [`LANES`] where there are at least [`MIN_LENS_LANES`] of them, each lane
/// shaded as its ray alone would be ([`shade_packet`]): the same bits.
pub(super) fn lattice_sample<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    res: u32,
    p: LatticePoint,
    packets: Option<SimdLevel>,
    rays: &mut RayCounts,
) -> PointSample {
    let key = point_key(settings, res, p);
    let Vec2 { x: px, y: py } = image_point(res, p);
    let level =
        res.trailing_zeros() - p.x.trailing_zeros().min(p.y.trailing_zeros()).min(res.trailing_zeros());
    let spp = 1u32 << (2 * level);
    let share = |samples: u32| samples.max(1).div_ceil(spp);
    let times = match scene.motion {
        Some(_) => share(settings.time.samples),
        None => 1,
    };
    let lenses = match scene.camera.has_lens() {
        true => share(settings.lens.samples),
        false => 1,
    };
    // The scene's camera-samples rule keeps lens × time samples within 32 bits.
    let m = times.saturating_mul(lenses);
    // Each dimension is hashed once, and only where it is drawn from. The orders' seeds take an
    // index no sample's draw uses (those are `PIXEL_PATTERNS - 2j`); a point of one sample needs
    // no order (the one permutation of one element is the identity).
    let times_dim = scene.motion.as_ref().map(|_| Dimension::new(&key, dims::TIME));
    let lens_dim = scene.camera.has_lens().then(|| Dimension::new(&key, dims::LENS));
    let order = match times_dim {
        Some(d) if m > 1 => d.hash(dims::PIXEL_PATTERNS - 1),
        _ => 0,
    };
    let (lens_order, lens_strata) = match lens_dim {
        Some(d) if lenses > 1 => (d.hash(dims::PIXEL_PATTERNS - 1), strata(m)),
        _ => (0, (1, 1)),
    };
    // Sample `j`'s ray, key and time, counted as a camera or lens ray.
    let sample = |j: u32, rays: &mut RayCounts| {
        // Sample 0 keeps the point's own key and draws; the others get keys of their own.
        let index = dims::PIXEL_PATTERNS - 2 * j;
        let time = match times_dim {
            Some(times_dim) => {
                rays.timed += 1;
                let k = permute(j, m, order);
                // `uniform(key, TIME, index)`: the first of the point's pair.
                let u = times_dim.uniform2(index).x;
                stratum_time(settings.time.pattern, k, m, u)
            }
            None => 0.0,
        };
        let cam = scene.camera_at(time);
        let ray = if cam.has_lens() {
            rays.lens += 1;
            let u = lens_dim.unwrap_or_else(|| Dimension::new(&key, dims::LENS)).uniform2(index);
            let lens = match lenses {
                // One lens point: anywhere on the lens.
                1 => disk_point(Pattern::Random, 1, 0, u),
                // Several: stratified over the point's samples, in an order decorrelated from
                // their times.
                _ => disk_point_in(settings.lens.pattern, lens_strata, permute(j, m, lens_order), u),
            };
            cam.lens_ray(px, py, settings.width, settings.height, lens)
        } else {
            rays.camera += 1;
            cam.ray(px, py, settings.width, settings.height)
        };
        let own = match j {
            0 => key,
            _ => SampleKey { sample: key.sample ^ j.wrapping_mul(0x9E37_79B9), ..key },
        };
        let camera =
            CameraSample { key: own, pixel: key, slot: j, spp: spp.saturating_mul(m), progressive: None };
        (ray, camera, time)
    };
    let mut mean = SampleMean::default();
    let mut spread = Spread::default();
    match packets.filter(|_| m as usize >= MIN_LENS_LANES) {
        Some(level) => {
            for first in (0..m).step_by(LANES) {
                // Nothing moves where there are packets: every time is 0.
                let (mut packet, cameras) =
                    packet_of::<LANES>((first..m.min(first + LANES as u32)).map(|j| {
                        let (ray, camera, _) = sample(j, rays);
                        (ray, camera)
                    }));
                level.run(
                    #[inline(always)]
                    || packet.reciprocals(),
                );
                for colour in
                    shade_packet((scene, settings), level, &packet, &cameras, rays).into_iter().flatten()
                {
                    mean.add(colour);
                    spread.add(colour);
                }
            }
        }
        None => {
            for j in 0..m {
                let (ray, camera, time) = sample(j, rays);
                let colour = trace_camera_ray(scene, settings, &ray, camera, time, rays);
                mean.add(colour);
                // One sample has no spread.
                if m > 1 {
                    spread.add(colour);
                }
            }
        }
    }
    point_of(&mean, &spread, m)
}

/// Lattice point `p`'s image position in pixels, as its camera rays aim at it: one rounding per
/// coordinate in `f32` (not [`LatticePoint::position`]'s `f64` quotient), shared by the single
/// rays and the corner packets so that both aim at the same bits.
#[inline]
fn image_point(res: u32, p: LatticePoint) -> Vec2 {
    Vec2::new(p.x as f32 / res as f32, p.y as f32 / res as f32)
}

/// The key of lattice point `p`'s stream (its first sample's): a pure function of the point.
fn point_key(settings: &RenderSettings, res: u32, p: LatticePoint) -> SampleKey {
    let id = u64::from(p.y) * (u64::from(settings.width) * u64::from(res) + 1) + u64::from(p.x);
    SampleKey { seed: settings.seed, frame: settings.frame, pixel: id as u32, sample: (id >> 32) as u32 }
}

/// A point of `m` camera samples, from the `mean` and `spread` of those that were finite.
fn point_of(mean: &SampleMean, spread: &Spread, m: u32) -> PointSample {
    // A point none of whose samples is finite is non-finite, so refinement drops and counts it.
    let colour = match mean.dropped() == m {
        true => Vec3::NAN,
        false => mean.mean(),
    };
    PointSample { colour, samples: mean.kept().max(1), spread: spread.variance() }
}

/// The pixel corners of rows `ys` (a band of at most `BLOCK[1]`) of a pinhole camera that does
/// not move, traced in packets of [`BLOCK`] corners ([`shade_packet`], compiled for `level`) and
/// pushed onto `rows` (one per row of the band) from left to right. A corner is one camera
/// sample (its pixel's only one, [`CameraSample::single`]) whose ray, key and colour are those
/// [`lattice_sample`] gives it: the same bits.
fn corner_band<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    res: u32,
    level: SimdLevel,
    ys: std::ops::Range<u32>,
    rows: &mut [(Vec<PointSample>, Vec<u32>)],
    rays: &mut RayCounts,
) {
    const { assert!((BLOCK[0] * BLOCK[1]) as usize == LANES) };
    debug_assert!(!scene.camera.has_lens() && scene.motion.is_none());
    let w = settings.width;
    for x0 in (0..=w).step_by(BLOCK[0] as usize) {
        let corner = |lane: usize| {
            let (x, y) = (x0 + lane as u32 % BLOCK[0], ys.start + lane as u32 / BLOCK[0]);
            (x <= w && ys.contains(&y)).then_some(LatticePoint { x: x * res, y: y * res })
        };
        let mut points = [Vec2::ZERO; LANES];
        let mut cameras = [None; LANES];
        for (lane, camera) in cameras.iter_mut().enumerate() {
            if let Some(p) = corner(lane) {
                points[lane] = image_point(res, p);
                *camera = Some(CameraSample::single(point_key(settings, res, p)));
                rays.camera += 1;
            }
        }
        let active = cameras.map(|c| c.is_some());
        let packet = level.run(
            #[inline(always)]
            || scene.camera.pinhole_lanes(&points, &active, settings.width, settings.height),
        );
        let colours = shade_packet((scene, settings), level, &packet, &cameras, rays);
        for (lane, colour) in colours.into_iter().enumerate() {
            if let Some(colour) = colour {
                let mut mean = SampleMean::default();
                mean.add(colour);
                rows[lane / BLOCK[0] as usize].0.push(point_of(&mean, &Spread::default(), 1));
            }
        }
    }
}

/// The running per-channel variance of a point's finite samples (Welford's update, in `f64`).
#[derive(Debug, Clone, Copy, Default)]
struct Spread {
    n: u32,
    mean: DVec3,
    m2: DVec3,
}

impl Spread {
    /// Counts `c`, unless a channel is not finite.
    fn add(&mut self, c: Vec3) {
        if !c.is_finite() {
            return;
        }
        let c = c.as_dvec3();
        self.n += 1;
        let delta = c - self.mean;
        self.mean += delta / f64::from(self.n);
        self.m2 += delta * (c - self.mean);
    }

    /// The unbiased variance of one sample, from two samples or more; finite (a spread past
    /// `f32` is as large as `f32` holds).
    fn variance(&self) -> Option<Vec3> {
        (self.n >= 2).then(|| (self.m2 / f64::from(self.n - 1)).as_vec3().min(Vec3::splat(f32::MAX)))
    }
}
