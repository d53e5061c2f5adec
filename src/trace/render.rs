//! The parallel renderer: tiles over rayon, one pure function per pixel.

use std::time::Instant;

use rayon::prelude::*;

use super::integrator::{radiance, PathContext};
use super::scene::TraceScene;
use super::stats::{GridStats, RayCounts, RenderStats};
use crate::film::Film;
use crate::math::Vec3;
use crate::store::PrimitiveStore;

/// Edge length of a square render tile in pixels.
pub const TILE: u32 = 16;

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
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self { width: 640, height: 480, max_depth: 5, min_contribution: 1e-3, seed: 0, frame: 0 }
    }
}

/// Renders a snapshot into a linear film. Pure: the same inputs give the same bits for any
/// thread count or tile order, because each pixel depends only on its coordinates.
pub fn render<S: PrimitiveStore>(scene: &TraceScene<S>, settings: &RenderSettings) -> (Film, RenderStats) {
    let started = Instant::now();
    let (w, h) = (settings.width, settings.height);
    let tiles_x = w.div_ceil(TILE);
    let tiles_y = h.div_ceil(TILE);
    let tiles: Vec<(Vec<Vec3>, RayCounts)> = (0..tiles_x * tiles_y)
        .into_par_iter()
        .map(|tile| render_tile(scene, settings, tile % tiles_x, tile / tiles_x))
        .collect();

    let mut film = Film::new(w, h);
    let mut rays = RayCounts::default();
    for (tile, (pixels, counts)) in tiles.iter().enumerate() {
        let (tx, ty) = (tile as u32 % tiles_x, tile as u32 / tiles_x);
        let x0 = tx * TILE;
        let tw = TILE.min(w - x0);
        for (k, &c) in pixels.iter().enumerate() {
            let (x, y) = (x0 + k as u32 % tw, ty * TILE + k as u32 / tw);
            film.set(x, y, c);
        }
        rays.add(counts);
    }
    let mut stats = RenderStats {
        width: w,
        height: h,
        threads: rayon::current_num_threads(),
        rays,
        ..Default::default()
    };
    stats.times.trace = started.elapsed().as_secs_f64();
    stats.grid = GridStats {
        dims: scene.grid.dims,
        objects: scene.store.bounded_count(),
        references: scene.grid.reference_count() as u64,
        grid_bytes: scene.grid.memory_bytes() as u64,
        store_bytes: scene.store.memory_bytes() as u64,
    };
    (film, stats)
}

fn render_tile<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    settings: &RenderSettings,
    tx: u32,
    ty: u32,
) -> (Vec<Vec3>, RayCounts) {
    let (x0, y0) = (tx * TILE, ty * TILE);
    let (x1, y1) = ((x0 + TILE).min(settings.width), (y0 + TILE).min(settings.height));
    let mut rays = RayCounts::default();
    let mut pixels = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
    let mut ctx = PathContext {
        max_depth: settings.max_depth,
        min_contribution: settings.min_contribution,
        rays: &mut rays,
    };
    for y in y0..y1 {
        for x in x0..x1 {
            let ray = scene.camera.ray(x as f32 + 0.5, y as f32 + 0.5, settings.width, settings.height);
            ctx.rays.camera += 1;
            let c = radiance(scene, &ray, 0, 1.0, &mut ctx);
            debug_assert!(c.is_finite(), "non-finite radiance at pixel ({x}, {y})");
            pixels.push(c);
        }
    }
    (pixels, rays)
}
