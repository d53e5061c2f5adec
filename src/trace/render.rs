//! The parallel renderer: rayon over tiles, one pure function per pixel.
//!
//! A pixel is the mean of `aa.samples × lens.samples` camera samples (lens samples only when
//! the camera has an aperture): sample positions come from the anti-aliasing pattern over the
//! pixel footprint (a box, or a tent two pixels wide), lens points from the lens pattern over
//! the unit disk, stratified across all of the pixel's samples. One sample per pixel goes
//! through the pixel centre; at AA 1 with several lens (or time) samples, each takes a position
//! of its own, as AA samples would. With adaptive supersampling the pixel corners are traced once for
//! the whole image, then each pixel is subdivided where its corners disagree
//! ([`crate::sample::adaptive`]).
//!
//! Every random number is keyed by (seed, frame, pixel, sample, dimension), so the image is
//! bit-identical for any thread count or tile order. A sample whose radiance is not finite is
//! dropped and counted where its pixel accumulates it ([`super::finite`]).

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use std::time::Instant;

use super::aov::first_hit_aovs;
use super::camera_samples::{fixed_pixel, CameraSampler};
use super::corners::render_adaptive;
use super::packet_tile::{camera_packets, lens_packets, lens_tile, packet_tile};
use super::scene::TraceScene;
use super::settings::RenderSettings;
use super::stats::{
    AdaptiveCounts, BudgetStats, GridStats, MeshGridStats, MotionStats, NoiseStats, RayCounts, RenderStats,
};
use super::tiles::{render_tiles, saturate, tile_count, Assembled, TileOut};
use crate::film::{AovSet, Aovs, Film};
use crate::store::{MeshEntry, PrimitiveStore};

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
        (None, None) => {
            let sampler = CameraSampler::new(scene, settings);
            // Packets of pixel blocks for a pinhole, of each pixel's samples for a lens (made
            // together, and traced alone where a pixel has too few); single rays where neither
            // applies (and for the cost AOV, which needs rays per pixel).
            let packets = camera_packets(scene, settings, wanted.cost);
            let lens = lens_packets(scene, settings, wanted.cost);
            let want_cost = wanted.cost;
            let tile = |area: [u32; 4], rays: &mut RayCounts, out: &mut TileOut| match (packets, lens) {
                (Some(level), _) => packet_tile(&sampler, level, area, rays, out),
                (None, Some(level)) => lens_tile(&sampler, level, area, rays, out),
                (None, None) => {
                    let [x0, y0, x1, y1] = area;
                    for y in y0..y1 {
                        for x in x0..x1 {
                            let before = rays.total();
                            out.pixels.push(fixed_pixel(&sampler, x, y, rays));
                            if want_cost {
                                out.costs.push(saturate(rays.total() - before));
                            }
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
