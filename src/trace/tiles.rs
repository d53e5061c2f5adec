//! Tiles: the image cut into squares of [`TILE`] pixels, shaded in parallel and assembled in
//! tile order, so the film does not depend on which thread shaded what.

use rayon::prelude::*;

use super::finite::DropTally;
use super::settings::RenderSettings;
use super::stats::RayCounts;

use crate::film::Film;
use crate::math::Vec3;

/// Edge length of a square render tile in pixels.
pub const TILE: u32 = 16;

/// The number of tiles an image of `width` × `height` pixels is rendered in (what progress
/// observers count to).
pub fn tile_count(width: u32, height: u32) -> u32 {
    width.div_ceil(TILE) * height.div_ceil(TILE)
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
pub(super) struct TileOut {
    pub(super) pixels: Vec<(Vec3, u32)>,
    pub(super) costs: Vec<u32>,
}

/// Runs `shade` over every tile (`[x0, y0, x1, y1]`, ends exclusive), tiles in parallel, and
/// assembles the film (and the cost image when `want_cost`: every tile then reports costs) in
/// tile order.
pub(super) fn render_tiles<F>(
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
